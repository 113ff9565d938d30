// Edge flips among the triangles that boundary stitching adds (core/extract/boundary.h).

#include <gtest/gtest.h>

#include <cmath>

#include "core/extract/boundary.h"

namespace hexcover::extract_detail {
namespace {

double smallestAngleDegrees(const std::vector<Eigen::Vector3d>& p, const std::vector<Triangle>& ts) {
  double smallest = 180.0;
  for (const auto& t : ts)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d u = p[t[(k + 1) % 3]] - p[t[k]], v = p[t[(k + 2) % 3]] - p[t[k]];
      smallest = std::min(smallest, std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / M_PI);
    }
  return smallest;
}

// A flat rhombus 0-1-2-3 (long diagonal 0-2) split along its long diagonal: slivers of 15°;
// the short diagonal gives 30°+.
const std::vector<Eigen::Vector3d> kRhombus = {
    {0, 0, 0}, {1, -0.2679, 0}, {2, 0, 0}, {1, 0.2679, 0}};

TEST(BoundaryFlips, FlipsTheLongDiagonalOfAThinRhombus) {
  std::vector<Triangle> region = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_NEAR(smallestAngleDegrees(kRhombus, region), 15.0, 0.01);
  EXPECT_EQ(improveByFlips(kRhombus, {}, region), 1);
  EXPECT_GT(smallestAngleDegrees(kRhombus, region), 29.9);
  // Still two counter-clockwise triangles (normals +z) covering the rhombus, sharing 1-3.
  for (const auto& t : region) {
    const Eigen::Vector3d n = (kRhombus[t[1]] - kRhombus[t[0]]).cross(kRhombus[t[2]] - kRhombus[t[0]]);
    EXPECT_GT(n.z(), 0.0);
  }
  EXPECT_EQ(improveByFlips(kRhombus, {}, region), 0) << "a second call finds nothing to improve";
}

TEST(BoundaryFlips, NeverCreatesAnEdgeThatExistsElsewhereOrTouchesOtherTriangles) {
  std::vector<Triangle> region = {{0, 1, 2}, {0, 2, 3}};
  // Another triangle already uses the edge 1-3 (a lattice triangle elsewhere): no flip.
  std::vector<Eigen::Vector3d> points = kRhombus;
  points.push_back({1, 0, 1});
  const std::vector<Triangle> others = {{1, 4, 3}};
  EXPECT_EQ(improveByFlips(points, others, region), 0);
  EXPECT_EQ(region[0], (Triangle{0, 1, 2}));
}

TEST(BoundaryFlips, NeverTurnsATriangleOver) {
  // A non-convex quad a-d-b-c: the other diagonal would raise the smallest angle (2.3° -> 7°)
  // but leave triangle d-b-c facing down.
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {2.5, -0.1, 0}};
  std::vector<Triangle> region = {{0, 1, 2}, {1, 0, 3}};
  EXPECT_EQ(improveByFlips(points, {}, region), 0);
}

}  // namespace
}  // namespace hexcover::extract_detail
