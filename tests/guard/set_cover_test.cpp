// Set cover (§2.2.2-2.2.3): greedy, the reductions and the CBC ILP against brute force
// on small random instances, plus hand-made cases and the error path.
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace structmesh {
namespace {

CompressedRows make_sets(const std::vector<std::vector<Index>>& sets) {
  CompressedRows rows;
  for (const auto& s : sets) {
    rows.items.insert(rows.items.end(), s.begin(), s.end());
    rows.offsets.push_back(static_cast<Index>(rows.items.size()));
  }
  return rows;
}

/// Random instance: `columns` sets over `rows` elements, every element in `least` to
/// `most` sets (fewer when a set is drawn twice).
CompressedRows random_instance(std::mt19937& rng, std::size_t columns, std::size_t rows, std::size_t least,
                               std::size_t most) {
  std::vector<std::vector<Index>> sets(columns);
  std::uniform_int_distribution<std::size_t> pick(0, columns - 1), how_many(least, most);
  for (Index e = 0; e < rows; ++e) {
    const std::size_t k = how_many(rng);
    for (std::size_t i = 0; i < k; ++i) sets[pick(rng)].push_back(e);
  }
  for (auto& s : sets) {
    std::sort(s.begin(), s.end());
    s.erase(std::unique(s.begin(), s.end()), s.end());
  }
  return make_sets(sets);
}

/// Size of a smallest cover by enumerating all subsets (at most 14 sets, 64 elements).
std::size_t brute_force_minimum(const CompressedRows& sets, std::size_t element_count) {
  std::vector<std::uint64_t> mask(sets.row_count(), 0);
  for (std::size_t c = 0; c < sets.row_count(); ++c)
    for (const Index e : sets.row(c)) mask[c] |= std::uint64_t{1} << e;
  const std::uint64_t all = element_count == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << element_count) - 1;
  std::size_t best = sets.row_count() + 1;
  for (std::uint32_t subset = 0; subset < (1u << sets.row_count()); ++subset) {
    const auto size = static_cast<std::size_t>(std::popcount(subset));
    if (size >= best) continue;
    std::uint64_t covered = 0;
    for (std::size_t c = 0; c < sets.row_count(); ++c)
      if ((subset >> c) & 1u) covered |= mask[c];
    if (covered == all) best = size;
  }
  return best;
}

TEST(SetCover, LocalImprovementKeepsACoverAndReachesTheOptimumWithAGroupAsLargeAsTheCover) {
  std::size_t improved = 0;
  for (unsigned seed = 1; seed <= 120; ++seed) {
    std::mt19937 rng(seed);
    const std::size_t columns = std::uniform_int_distribution<std::size_t>(6, 14)(rng);
    const std::size_t rows = std::uniform_int_distribution<std::size_t>(10, 40)(rng);
    const CompressedRows sets = random_instance(rng, columns, rows, 1, 4);
    SCOPED_TRACE("seed " + std::to_string(seed));
    const std::size_t optimum = brute_force_minimum(sets, rows);
    // From the worst start there is: every set.
    std::vector<Index> everything(columns);
    for (std::size_t c = 0; c < columns; ++c) everything[c] = static_cast<Index>(c);
    std::vector<Index> pairs = everything;
    const std::size_t saved = improve_set_cover(sets, rows, pairs, 2, 30);
    EXPECT_EQ(saved + pairs.size(), columns);
    EXPECT_TRUE(covers_all(sets, rows, pairs));
    EXPECT_GE(pairs.size(), optimum);
    // A group as large as the cover is one exact ILP: the optimum.
    std::vector<Index> greedy = greedy_set_cover(sets, rows);
    const std::size_t greedy_size = greedy.size();
    improve_set_cover(sets, rows, greedy, greedy_size, 30);
    EXPECT_TRUE(covers_all(sets, rows, greedy));
    EXPECT_EQ(greedy.size(), optimum);
    improved += greedy.size() < greedy_size;
  }
  EXPECT_GT(improved, 0U);  // the instances include ones where greedy is not optimal
}

TEST(SetCover, LocalImprovementRefusesANonCover) {
  const CompressedRows sets = make_sets({{0, 1}, {1, 2}, {2, 3}});
  std::vector<Index> partial{0};
  EXPECT_THROW(improve_set_cover(sets, 4, partial, 3), InputError);
  std::vector<Index> missing_set{0, 7};
  EXPECT_THROW(improve_set_cover(sets, 4, missing_set, 3), InputError);
  std::vector<Index> cover{0, 1, 2};
  EXPECT_EQ(improve_set_cover(sets, 4, cover, 3), 1U);  // {0, 2} suffices
  EXPECT_EQ(cover.size(), 2U);
}

TEST(SetCover, IlpMatchesBruteForceAndBeatsGreedyOnRandomInstances) {
  std::size_t greedy_worse = 0, reduced_to_nothing = 0;
  for (unsigned seed = 1; seed <= 200; ++seed) {
    std::mt19937 rng(seed);
    const std::size_t columns = std::uniform_int_distribution<std::size_t>(6, 14)(rng);
    const std::size_t rows = std::uniform_int_distribution<std::size_t>(10, 40)(rng);
    const CompressedRows sets = random_instance(rng, columns, rows, 1 + seed % 2, 5 + seed % 2);
    SCOPED_TRACE("seed " + std::to_string(seed) + ": " + std::to_string(columns) + " sets, " + std::to_string(rows) +
                 " elements");
    const std::size_t optimum = brute_force_minimum(sets, rows);

    const std::vector<Index> greedy = greedy_set_cover(sets, rows);
    EXPECT_TRUE(covers_all(sets, rows, greedy));
    EXPECT_GE(greedy.size(), optimum);

    const IlpSetCoverResult ilp = ilp_set_cover(sets, rows, 30);
    EXPECT_TRUE(covers_all(sets, rows, ilp.chosen));
    EXPECT_TRUE(ilp.optimal);
    EXPECT_EQ(ilp.chosen.size(), optimum);
    EXPECT_LE(ilp.chosen.size(), greedy.size());
    EXPECT_DOUBLE_EQ(ilp.lower_bound, static_cast<double>(optimum));
    EXPECT_TRUE(std::is_sorted(ilp.chosen.begin(), ilp.chosen.end()));
    EXPECT_EQ(ilp.rows_before, rows);
    EXPECT_EQ(ilp.columns_before, columns);
    greedy_worse += greedy.size() > optimum ? 1 : 0;

    // The reduced instance keeps the optimum: forced sets + its own optimum.
    const SetCoverReduction reduction = reduce_set_cover(sets, rows);
    EXPECT_EQ(reduction.rows_after, reduction.kept_rows.size());
    EXPECT_EQ(reduction.columns_after, reduction.kept_columns.size());
    EXPECT_LE(reduction.rows_after, rows);
    EXPECT_LE(reduction.columns_after, columns);
    const std::size_t reduced_optimum =
        reduction.rows_after == 0 ? 0 : brute_force_minimum(reduction.reduced_sets, reduction.rows_after);
    EXPECT_EQ(reduction.forced.size() + reduced_optimum, optimum);
    reduced_to_nothing += reduction.rows_after == 0 ? 1 : 0;
    // Forced sets plus any cover of the reduced instance cover the input.
    if (reduction.rows_after > 0) {
      std::vector<Index> cover = reduction.forced;
      for (const Index k : greedy_set_cover(reduction.reduced_sets, reduction.rows_after))
        cover.push_back(reduction.kept_columns[k]);
      EXPECT_TRUE(covers_all(sets, rows, cover));
    } else {
      EXPECT_TRUE(covers_all(sets, rows, reduction.forced));
    }
  }
  // The instances must exercise both paths: greedy not optimal, and CBC needed.
  EXPECT_GT(greedy_worse, 0u);
  EXPECT_LT(reduced_to_nothing, 150u);
  std::printf("greedy above the optimum on %zu of 200 instances; reductions alone solved %zu\n", greedy_worse,
              reduced_to_nothing);
}

TEST(SetCover, GreedyTakesTheLargestSetTiesToTheLowestIndex) {
  // Greedy takes {0, 1, 3, 4} first and then needs both halves: 3 sets, optimum 2.
  const CompressedRows sets = make_sets({{0, 1, 2}, {3, 4, 5}, {0, 1, 3, 4}});
  EXPECT_EQ(greedy_set_cover(sets, 6), (std::vector<Index>{2, 0, 1}));
  const IlpSetCoverResult ilp = ilp_set_cover(sets, 6);
  EXPECT_EQ(ilp.chosen, (std::vector<Index>{0, 1}));
  EXPECT_TRUE(ilp.optimal);
  // Equal sets: the lowest index wins.
  EXPECT_EQ(greedy_set_cover(make_sets({{1, 0}, {0, 1}, {0}}), 2), (std::vector<Index>{0}));
  // A set listing an element twice counts it once.
  EXPECT_EQ(greedy_set_cover(make_sets({{0, 0, 0}, {0, 1}}), 2), (std::vector<Index>{1}));
  EXPECT_TRUE(greedy_set_cover(make_sets({{}, {}}), 0).empty());
}

TEST(SetCover, ReductionRules) {
  // Element 5 is only in set 3: set 3 is forced and takes elements 4, 5 with it.
  // Elements 0 and 1 are in the same sets (duplicate rows). Element 2's sets {0, 1, 2}
  // are a superset of element 0's {0, 1}: implied. Set 2 = {2, 3} ⊂ set 1 = {0, 1, 2, 3}:
  // dominated. Then set 0 = {0, 1, 2} ⊂ set 1: dominated, and everything left is in
  // set 1 alone: forced. Optimum 2 = {1, 3}.
  const CompressedRows sets = make_sets({{0, 1, 2}, {0, 1, 2, 3}, {2, 3}, {4, 5}});
  const SetCoverReduction reduction = reduce_set_cover(sets, 6);
  EXPECT_EQ(reduction.rows_before, 6u);
  EXPECT_EQ(reduction.columns_before, 4u);
  EXPECT_EQ(reduction.forced, (std::vector<Index>{1, 3}));
  EXPECT_EQ(reduction.rows_after, 0u);
  EXPECT_EQ(reduction.columns_after, 0u);
  const IlpSetCoverResult ilp = ilp_set_cover(sets, 6);
  EXPECT_EQ(ilp.chosen, (std::vector<Index>{1, 3}));
  EXPECT_TRUE(ilp.optimal);

  // A 5-cycle (element i in sets i and i+1 mod 5): nothing reduces; optimum 3.
  const CompressedRows cycle = make_sets({{0, 4}, {0, 1}, {1, 2}, {2, 3}, {3, 4}});
  const SetCoverReduction none = reduce_set_cover(cycle, 5);
  EXPECT_TRUE(none.forced.empty());
  EXPECT_EQ(none.rows_after, 5u);
  EXPECT_EQ(none.columns_after, 5u);
  EXPECT_EQ(none.kept_columns, (std::vector<Index>{0, 1, 2, 3, 4}));
  EXPECT_EQ(ilp_set_cover(cycle, 5).chosen.size(), 3u);

  // Two equal sets: the lower index stays.
  const SetCoverReduction equal = reduce_set_cover(make_sets({{0, 1}, {0, 1}, {1, 2}, {2, 0}}), 3);
  EXPECT_EQ(equal.columns_after, 3u);
  EXPECT_EQ(equal.kept_columns, (std::vector<Index>{0, 2, 3}));
}

TEST(SetCover, ATimeOutStillGivesACover) {
  // Large enough that CBC needs seconds to prove optimality (about 7 s here).
  std::mt19937 rng(7);
  const CompressedRows sets = random_instance(rng, 60, 300, 3, 6);
  const IlpSetCoverResult quick = ilp_set_cover(sets, 300, 0);  // no time: the greedy cover
  EXPECT_TRUE(covers_all(sets, 300, quick.chosen));
  ASSERT_GT(quick.rows_after, 0u);
  EXPECT_FALSE(quick.optimal);
  EXPECT_EQ(quick.chosen.size(), quick.greedy_size);
  const IlpSetCoverResult timed = ilp_set_cover(sets, 300, 0.3);
  EXPECT_TRUE(covers_all(sets, 300, timed.chosen));
  EXPECT_LE(timed.chosen.size(), quick.chosen.size());
  EXPECT_GE(timed.lower_bound, 1.0);
  EXPECT_LE(timed.lower_bound, static_cast<double>(timed.chosen.size()));
  std::printf("60 x 300 instance: greedy %zu, CBC after 0.3 s %zu (%s), lower bound %g\n", quick.chosen.size(),
              timed.chosen.size(), timed.optimal ? "optimal" : "not proven", timed.lower_bound);
}

TEST(SetCover, IndependentBlocksAreSolvedSeparatelyAndTheirOptimaAdd) {
  // Random instances side by side on disjoint elements and sets (rule 4 of §2.2.3): the
  // optimum of the union is the sum of the optima, found block by block.
  std::mt19937 rng(11);
  std::size_t split = 0;  // trials where more than one block reached the solver
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<CompressedRows> parts;
    std::size_t expected = 0, element_offset = 0;
    CompressedRows joined;
    for (int k = 0; k < 3; ++k) {
      const CompressedRows part = random_instance(rng, 10, 20, 1, 3);
      expected += brute_force_minimum(part, 20);
      for (std::size_t c = 0; c < part.row_count(); ++c) {
        for (const Index e : part.row(c)) joined.items.push_back(static_cast<Index>(e + element_offset));
        joined.offsets.push_back(static_cast<Index>(joined.items.size()));
      }
      element_offset += 20;
    }
    const IlpSetCoverResult result = ilp_set_cover(joined, element_offset);
    EXPECT_TRUE(result.optimal);
    EXPECT_EQ(result.chosen.size(), expected) << "trial " << trial;
    EXPECT_TRUE(covers_all(joined, element_offset, result.chosen));
    // The reductions may solve a block outright; what is left is at most 3 blocks and
    // at least 1 when anything is left.
    EXPECT_LE(result.blocks, 3u);
    EXPECT_EQ(result.blocks == 0, result.rows_after == 0);
    split += result.blocks >= 2;
  }
  EXPECT_GT(split, 0u);
}

TEST(SetCover, UncoverableElementsAreInputErrors) {
  const CompressedRows sets = make_sets({{0, 2}, {2, 5}});
  try {
    greedy_set_cover(sets, 7);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("element 1 is in no set"), std::string::npos) << message;
    EXPECT_NE(message.find("(4 elements are not coverable)"), std::string::npos) << message;
  }
  EXPECT_THROW(ilp_set_cover(sets, 7), InputError);
  EXPECT_THROW(reduce_set_cover(sets, 7), InputError);
  // An element id beyond element_count.
  EXPECT_THROW(greedy_set_cover(make_sets({{0, 3}}), 3), InputError);
  EXPECT_FALSE(covers_all(sets, 7, std::vector<Index>{0, 1}));
  EXPECT_FALSE(covers_all(sets, 3, std::vector<Index>{0}));
  EXPECT_TRUE(covers_all(make_sets({{0, 2}, {1}}), 3, std::vector<Index>{1, 0}));
}

}  // namespace
}  // namespace structmesh
