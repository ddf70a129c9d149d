#include "mesh/planar_geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

// The error-free transformations below need every product and sum rounded on
// its own; a fused multiply-add contracted by the compiler would break them.
#ifdef __clang__
#pragma clang fp contract(off)
#endif

namespace structmesh::detail {

namespace {

constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1.0
// Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
// Geometric Predicates" (1997): the first-stage error bound of orient2d.
constexpr double kCcwErrBoundA = (3.0 + 16.0 * kEpsilon) * kEpsilon;

int sign(double x) { return (x > 0) - (x < 0); }

// x + y == a + b exactly, |y| <= ulp(x) / 2.
void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  y = (a - a_virtual) + (b - b_virtual);
}

// x + y == a - b exactly.
void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double b_virtual = a - x;
  const double a_virtual = x + b_virtual;
  y = (a - a_virtual) + (b_virtual - b);
}

// x + y == a * b exactly (fma computes the rounding error of the product).
void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// A sum of non-overlapping doubles in increasing magnitude, exact (Shewchuk's
// expansions); its sign is the sign of its largest component.
class Expansion {
 public:
  void add(double b) {
    // Grow-Expansion with zero elimination, written in place (index <= i always).
    double q = b;
    std::size_t out = 0;
    for (std::size_t i = 0; i < size_; ++i) {
      double sum = 0, error = 0;
      two_sum(q, terms_[i], sum, error);
      q = sum;
      if (error != 0) terms_[out++] = error;
    }
    if (q != 0 || out == 0) terms_[out++] = q;
    size_ = out;
  }
  int sign_of_sum() const { return size_ == 0 ? 0 : sign(terms_[size_ - 1]); }

 private:
  std::array<double, 17> terms_{};
  std::size_t size_ = 0;
};

int orient2d_exact(const Vec2& a, const Vec2& b, const Vec2& c) {
  // det = (ax-cx)(by-cy) - (ay-cy)(bx-cx), every difference split into value + tail.
  double acx, acx_t, bcy, bcy_t, acy, acy_t, bcx, bcx_t;
  two_diff(a.x(), c.x(), acx, acx_t);
  two_diff(b.y(), c.y(), bcy, bcy_t);
  two_diff(a.y(), c.y(), acy, acy_t);
  two_diff(b.x(), c.x(), bcx, bcx_t);
  const std::array<std::array<double, 2>, 4> left{{{acx, bcy}, {acx, bcy_t}, {acx_t, bcy}, {acx_t, bcy_t}}};
  const std::array<std::array<double, 2>, 4> right{{{acy, bcx}, {acy, bcx_t}, {acy_t, bcx}, {acy_t, bcx_t}}};
  Expansion det;
  for (const auto& [u, v] : left) {
    double p, e;
    two_product(u, v, p, e);
    det.add(p);
    det.add(e);
  }
  for (const auto& [u, v] : right) {
    double p, e;
    two_product(u, v, p, e);
    det.add(-p);
    det.add(-e);
  }
  return det.sign_of_sum();
}

// Overlap of the closed intervals [a0,a1] and [b0,b1] given in any order.
bool intervals_meet(double a0, double a1, double b0, double b1) {
  return std::max(std::min(a0, a1), std::min(b0, b1)) <= std::min(std::max(a0, a1), std::max(b0, b1));
}

}  // namespace

int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double det_left = (a.x() - c.x()) * (b.y() - c.y());
  const double det_right = (a.y() - c.y()) * (b.x() - c.x());
  const double det = det_left - det_right;
  double det_sum = 0;
  if (det_left > 0) {
    if (det_right <= 0) return sign(det);
    det_sum = det_left + det_right;
  } else if (det_left < 0) {
    if (det_right >= 0) return sign(det);
    det_sum = -det_left - det_right;
  } else {
    return sign(det);
  }
  const double bound = kCcwErrBoundA * det_sum;
  if (det >= bound || -det >= bound) return sign(det);
  return orient2d_exact(a, b, c);
}

bool has_three_distinct_points(std::span<const Vec2> ring) {
  if (ring.empty()) return false;
  const Vec2 first = ring[0];
  const Vec2* second = nullptr;
  for (const Vec2& p : ring) {
    if (p == first) continue;
    if (second == nullptr) {
      second = &p;
    } else if (p != *second) {
      return true;
    }
  }
  return false;
}

void normalize_orientation(Polygon2& polygon) {
  for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
    const double area = signed_area(polygon.ring(r));
    if (r == 0 ? area < 0 : area > 0)
      std::reverse(polygon.points.begin() + polygon.ring_offsets[r] + 1,
                   polygon.points.begin() + polygon.ring_offsets[r + 1]);
  }
}

SegmentContact segment_contact(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int o1 = orient2d(a, b, c), o2 = orient2d(a, b, d);
  if (o1 * o2 > 0) return SegmentContact::None;
  const int o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
  if (o3 * o4 > 0) return SegmentContact::None;
  if (o1 != 0 && o2 != 0 && o3 != 0 && o4 != 0) return SegmentContact::Cross;
  if (o1 == 0 && o2 == 0) {
    // Collinear: they meet when their extents overlap along the line (x unless vertical).
    const bool meet =
        a.x() != b.x() ? intervals_meet(a.x(), b.x(), c.x(), d.x()) : intervals_meet(a.y(), b.y(), c.y(), d.y());
    return meet ? SegmentContact::Touch : SegmentContact::None;
  }
  // Not collinear and an endpoint lies on the other segment's line with the
  // other segment straddling: that endpoint is the (unique) meeting point.
  return SegmentContact::Touch;
}

RingLocator::RingLocator(std::vector<std::span<const Vec2>> rings) : rings_(std::move(rings)) {
  // Segments are referred to, not copied: a locator over 10^7 segments stays small.
  auto for_each_segment = [this](auto&& visit) {
    for (std::uint32_t r = 0; r < rings_.size(); ++r) {
      const auto ring = rings_[r];
      for (std::uint32_t i = 0; i < ring.size(); ++i) {
        const Vec2& a = ring[i];
        const Vec2& b = ring[(i + 1) % ring.size()];
        if (a.allFinite() && b.allFinite() && a.y() != b.y())
          visit(r, i, std::min(a.y(), b.y()), std::max(a.y(), b.y()));
      }
    }
  };
  double y1 = -std::numeric_limits<double>::infinity();
  y0_ = std::numeric_limits<double>::infinity();
  double vertical_extent = 0;
  std::size_t count = 0;
  for_each_segment([&](std::uint32_t, std::uint32_t, double low, double high) {
    y0_ = std::min(y0_, low);
    y1 = std::max(y1, high);
    vertical_extent += high - low;
    ++count;
  });
  if (count == 0) return;
  // Band count: as many as segments, but few enough that segments spanning many
  // bands add at most ~4 entries per segment (sum of spans = extent * bands / height).
  const double n = static_cast<double>(count);
  const double height = y1 - y0_;
  double bands = n;
  if (std::isfinite(height) && height > 0 && std::isfinite(vertical_extent) && vertical_extent > 0)
    bands = std::min(bands, 4.0 * n * height / vertical_extent);
  else
    bands = 1;
  band_count_ = static_cast<std::size_t>(std::clamp(bands, 1.0, double{1 << 22}));
  band_height_ = height / static_cast<double>(band_count_);
  if (!(band_height_ > 0) || !std::isfinite(band_height_)) {
    band_count_ = 1;
    band_height_ = 1;
  }

  band_offsets_.assign(band_count_ + 1, 0);
  for_each_segment([&](std::uint32_t, std::uint32_t, double low, double high) {
    for (std::size_t k = band_of(low); k <= band_of(high); ++k) ++band_offsets_[k + 1];
  });
  for (std::size_t k = 0; k < band_count_; ++k) band_offsets_[k + 1] += band_offsets_[k];
  band_items_.resize(band_offsets_.back());
  std::vector<std::uint32_t> fill(band_offsets_.begin(), band_offsets_.end() - 1);
  for_each_segment([&](std::uint32_t r, std::uint32_t i, double low, double high) {
    for (std::size_t k = band_of(low); k <= band_of(high); ++k) band_items_[fill[k]++] = {r, i};
  });
}

std::size_t RingLocator::band_of(double y) const {
  // Clamped in floating point first: out-of-range and NaN values never reach the integer cast.
  const double t = (y - y0_) / band_height_;
  const double last = static_cast<double>(band_count_ - 1);
  if (!(t > 0)) return 0;
  if (t >= last) return band_count_ - 1;
  return static_cast<std::size_t>(t);
}

std::vector<std::uint32_t> RingLocator::containing(const Vec2& p, std::uint32_t skip) const {
  std::vector<std::uint32_t> hits;
  if (band_count_ == 0 || !p.allFinite()) return hits;
  const std::size_t k = band_of(p.y());
  for (std::uint32_t i = band_offsets_[k]; i < band_offsets_[k + 1]; ++i) {
    const SegmentRef s = band_items_[i];
    if (s.ring == skip) continue;
    const auto ring = rings_[s.ring];
    Vec2 a = ring[s.index], b = ring[(s.index + 1) % ring.size()];
    if (a.y() > b.y()) std::swap(a, b);
    if (!(a.y() <= p.y() && p.y() < b.y())) continue;
    // Upwards from a to b, the segment crosses the ray left of p exactly when p is to its right.
    if (orient2d(a, b, p) < 0) hits.push_back(s.ring);
  }
  std::sort(hits.begin(), hits.end());
  std::vector<std::uint32_t> inside;
  for (std::size_t i = 0; i < hits.size();) {
    std::size_t j = i;
    while (j < hits.size() && hits[j] == hits[i]) ++j;
    if ((j - i) % 2 == 1) inside.push_back(hits[i]);
    i = j;
  }
  return inside;
}

bool point_in_ring(std::span<const Vec2> ring, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Vec2& a = ring[i];
    const Vec2& b = ring[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

}  // namespace structmesh::detail
