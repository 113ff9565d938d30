// Flips and smoothing next to the remesh boundary (core/extract/boundary_zone.h).

#include <gtest/gtest.h>

#include <algorithm>

#include "core/extract/boundary_zone.h"
#include "core/extract/fan_geometry.h"
#include "core/mesh/primitives.h"

namespace hexcover::extract_detail {
namespace {

double smallestAngleDegrees(const TriMesh& mesh) {
  double smallest = 180.0;
  for (const auto f : mesh.faces())
    smallest = std::min(smallest, angleRange(facePositions(mesh, f, OpenMesh::VertexHandle(),
                                                           Eigen::Vector3d::Zero()))[0]);
  return smallest;
}

/// Interior vertices of valence ≠ 6.
int irregularInterior(const TriMesh& mesh) {
  int count = 0;
  for (const auto v : mesh.vertices()) count += !mesh.is_boundary(v) && v.valence() != 6;
  return count;
}

TEST(BoundaryZone, FlipsBackTheEdgesThatMadeTheFrontIrregular) {
  const TriMesh grid = makeEquilateralGrid(9, 9);
  TriMesh remesh = grid;
  // Flip one edge between two interior vertices next to the boundary: valences 5, 5, 7, 7 and
  // 30° angles.
  int flipped = 0;
  for (const auto e : remesh.edges()) {
    if (remesh.is_boundary(e)) continue;
    const bool nextToBoundary = std::any_of(e.v0().vertices().begin(), e.v0().vertices().end(),
                                            [&](auto w) { return remesh.is_boundary(w); });
    if (!nextToBoundary || remesh.is_boundary(e.v0()) || remesh.is_boundary(e.v1()) ||
        !remesh.is_flip_ok(e))
      continue;
    remesh.flip(e);
    ++flipped;
    break;
  }
  ASSERT_EQ(flipped, 1);
  ASSERT_GT(irregularInterior(remesh), 0);
  ASSERT_LT(smallestAngleDegrees(remesh), 31.0);

  const BoundaryZoneCounts counts = improveBoundaryZone(ClosestPointQuery(grid), remesh, 1.0);
  EXPECT_GE(counts.flips, 1);
  EXPECT_EQ(irregularInterior(remesh), 0);
  EXPECT_GT(smallestAngleDegrees(remesh), 59.9);
  for (const auto v : remesh.vertices()) EXPECT_EQ(remesh.point(v), grid.point(v));
}

TEST(BoundaryZone, CollapsesABoundarySampleThatCrowdsItsNeighbour) {
  const TriMesh grid = makeEquilateralGrid(9, 9);
  TriMesh remesh = grid;
  // A boundary sample a tenth of an edge from a boundary vertex (away from the grid's corners):
  // a 0.1-long boundary edge and a sliver.
  const auto e = *std::find_if(remesh.edges().begin(), remesh.edges().end(), [&](auto edge) {
    const auto p = remesh.point(edge.v0()), q = remesh.point(edge.v1());
    return remesh.is_boundary(edge) && p[1] == 0.0 && q[1] == 0.0 && std::min(p[0], q[0]) == 3.0;
  });
  const auto p = remesh.point(e.v0()), q = remesh.point(e.v1());
  const auto crowded = p[0] < q[0] ? p : q;
  remesh.split(e, crowded + TriMesh::Point(0.1, 0.0, 0.0));
  ASSERT_EQ(remesh.n_vertices(), grid.n_vertices() + 1);
  ASSERT_LT(smallestAngleDegrees(remesh), 10.0);

  const BoundaryZoneCounts counts = improveBoundaryZone(ClosestPointQuery(grid), remesh, 1.0);
  EXPECT_EQ(counts.collapses, 1);
  EXPECT_EQ(remesh.n_vertices(), grid.n_vertices());
  EXPECT_GT(smallestAngleDegrees(remesh), 59.9);
  EXPECT_EQ(irregularInterior(remesh), 0);
}

TEST(BoundaryZone, RemovesAPoorEarOnTheBoundary) {
  const TriMesh grid = makeEquilateralGrid(9, 9);
  TriMesh remesh = grid;
  // An ear below the bottom edge (3, 0)-(4, 0): a boundary vertex with one triangle whose angle
  // at (4, 0) is 9.5°.
  const auto at = [&](double x, double y) {
    return *std::find_if(remesh.vertices().begin(), remesh.vertices().end(),
                         [&](auto v) { return remesh.point(v) == TriMesh::Point(x, y, 0.0); });
  };
  const auto a = at(3.0, 0.0), b = at(4.0, 0.0);
  const auto tip = remesh.add_vertex({3.1, -0.15, 0.0});
  ASSERT_TRUE(remesh.add_face(b, a, tip).is_valid());
  ASSERT_LT(smallestAngleDegrees(remesh), 10.0);

  const TriMesh withEar = remesh;
  const BoundaryZoneCounts counts = improveBoundaryZone(ClosestPointQuery(withEar), remesh, 1.0);
  EXPECT_EQ(counts.collapses, 1);
  EXPECT_EQ(remesh.n_vertices(), grid.n_vertices());
  EXPECT_GT(smallestAngleDegrees(remesh), 59.9);
}

TEST(BoundaryZone, LeavesAClosedMeshAlone) {
  const TriMesh sphere = makeIcosphere(2);
  TriMesh remesh = sphere;
  const BoundaryZoneCounts counts = improveBoundaryZone(ClosestPointQuery(sphere), remesh, 0.3);
  EXPECT_EQ(counts.collapses + counts.flips + counts.smoothed, 0);
}

}  // namespace
}  // namespace hexcover::extract_detail
