// Input checks shared by the set-cover solvers (greedy, reductions, ILP).
#pragma once

#include "structmesh/mesh.hpp"

#include <cstddef>

namespace structmesh::guard {

/// InputError when a set lists an element >= element_count, or when some element is in
/// no set (naming the first such element and how many there are). `who` starts the
/// message ("greedy_set_cover").
void require_coverable(const CompressedRows& sets, std::size_t element_count, const char* who);

}  // namespace structmesh::guard
