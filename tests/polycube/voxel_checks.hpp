// Checks on voxel sets shared by the polycube tests.
#pragma once

#include "structmesh/polycube.hpp"

#include <gtest/gtest.h>

namespace structmesh::test {

/// Expects every voxel of `before` to stay in `after`, and calls added(x, y, z) for each
/// voxel `after` has and `before` has not.
template <class Added>
void expect_only_additions(const VoxelGrid& before, const VoxelGrid& after, Added&& added) {
  for (int z = 0; z < after.dims[2]; ++z)
    for (int y = 0; y < after.dims[1]; ++y)
      for (int x = 0; x < after.dims[0]; ++x) {
        if (before.at(x, y, z)) {
          EXPECT_TRUE(after.at(x, y, z)) << x << " " << y << " " << z;
        } else if (after.at(x, y, z)) {
          added(x, y, z);
        }
      }
}

}  // namespace structmesh::test
