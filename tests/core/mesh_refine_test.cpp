// splitLongEdges and flipFlatRegionsToDelaunay: the same surface, sampled more finely and with
// better angles where it is flat.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "core/common/error.h"
#include "core/mesh/primitives.h"
#include "core/mesh/refine.h"
#include "core/mesh/topology.h"

namespace hexcover {
namespace {

using Triangle = std::array<Eigen::Vector3d, 3>;

std::vector<Triangle> trianglesOf(const TriMesh& mesh) {
  std::vector<Triangle> triangles;
  for (const auto f : mesh.faces()) {
    Triangle t;
    int k = 0;
    for (const auto v : f.vertices()) t[k++] = toEigen(mesh.point(v));
    triangles.push_back(t);
  }
  return triangles;
}

double area(const Triangle& t) { return 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm(); }

/// Whether p lies in triangle t: in its plane and with barycentric coordinates ≥ 0 (to `eps`
/// relative to the triangle's size).
bool inTriangle(const Eigen::Vector3d& p, const Triangle& t, double eps) {
  const Eigen::Vector3d u = t[1] - t[0], w = t[2] - t[0], n = u.cross(w), q = p - t[0];
  const double scale = std::max(u.norm(), w.norm());
  if (std::abs(q.dot(n.normalized())) > eps * scale) return false;
  const double a = n.dot(u.cross(q)) / n.squaredNorm(), b = n.dot(q.cross(w)) / n.squaredNorm();
  return b >= -eps && a >= -eps && a + b <= 1.0 + eps;
}

TEST(MeshRefine, SplitsLongEdgesInsideTheOriginalTriangles) {
  const TriMesh original = makeCappedCylinder(1.0, 2.0, 32);
  TriMesh refined = original;
  const double longest = 0.3;
  const long long splits = splitLongEdges(refined, longest);
  EXPECT_GT(splits, 0);
  EXPECT_EQ(refined.n_vertices(), original.n_vertices() + static_cast<std::size_t>(splits));
  for (const auto e : refined.edges()) EXPECT_LE(refined.calc_edge_length(e), longest);
  // Every new triangle lies in one original triangle, and the areas add up: the same surface.
  const std::vector<Triangle> before = trianglesOf(original);
  double areaBefore = 0.0, areaAfter = 0.0;
  for (const auto& t : before) areaBefore += area(t);
  for (const auto& t : trianglesOf(refined)) {
    areaAfter += area(t);
    bool inside = false;
    for (const auto& s : before)
      inside = inside || (inTriangle(t[0], s, 1e-9) && inTriangle(t[1], s, 1e-9) &&
                          inTriangle(t[2], s, 1e-9));
    EXPECT_TRUE(inside) << "a refined triangle leaves the original surface";
  }
  EXPECT_NEAR(areaAfter, areaBefore, 1e-12 * areaBefore);
  const MeshTopology a = computeTopology(original), b = computeTopology(refined);
  EXPECT_TRUE(a.sameAs(b));
}

/// Triangles of the mesh with a corner angle below `degrees`.
int trianglesWithAngleBelow(const TriMesh& mesh, double degrees) {
  int count = 0;
  for (const auto& t : trianglesOf(mesh)) {
    double smallest = 180.0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d u = t[(k + 1) % 3] - t[k], w = t[(k + 2) % 3] - t[k];
      smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)) * 180.0 / M_PI);
    }
    count += smallest < degrees ? 1 : 0;
  }
  return count;
}

/// A unit square in the z = 0 plane fanned from its corner (0, 0) to 10 points on each far side
/// (a CAD exporter's triangulation of a planar face: slivers at the corner).
TriMesh fannedSquare() {
  TriMesh mesh;
  const auto corner = mesh.add_vertex({0.0, 0.0, 0.0});
  std::vector<OpenMesh::VertexHandle> rim;
  for (int i = 0; i <= 10; ++i) rim.push_back(mesh.add_vertex({i / 10.0, 1.0, 0.0}));
  for (int i = 9; i >= 0; --i) rim.push_back(mesh.add_vertex({1.0, i / 10.0, 0.0}));
  for (std::size_t i = 0; i + 1 < rim.size(); ++i) mesh.add_face(corner, rim[i + 1], rim[i]);
  return mesh;
}

/// The refined unit square: every triangle in the z = 0 plane and counter-clockwise (nothing
/// folded), and their areas add up to 1 (the same square).
void expectTheUnitSquareUnfolded(const TriMesh& mesh) {
  double total = 0.0;
  for (const auto& t : trianglesOf(mesh)) {
    total += area(t);
    for (const auto& p : t) EXPECT_EQ(p.z(), 0.0);
    EXPECT_GT((t[1] - t[0]).cross(t[2] - t[0]).z(), 0.0) << "a folded triangle";
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
}

// Midpoint splits keep a planar face's slivers; Delaunay flips on the flat region improve its
// angles with the same surface (590 -> 420 triangles with an angle below 20°: the splits' points
// crowd along the fan's spokes, which flips cannot move), and leave a curved mesh alone.
TEST(MeshRefine, FlipsFlatRegionsToDelaunayAndLeavesCurvedOnesAlone) {
  const TriMesh original = fannedSquare();
  TriMesh refined = original;
  splitLongEdges(refined, 0.15);
  const int before = trianglesWithAngleBelow(refined, 20.0);
  EXPECT_GT(flipFlatRegionsToDelaunay(refined), 0);
  const int after = trianglesWithAngleBelow(refined, 20.0);
  EXPECT_LT(after, 0.8 * before) << before << " triangles with an angle below 20° before the flips";
  expectTheUnitSquareUnfolded(refined);
  EXPECT_TRUE(computeTopology(original).sameAs(computeTopology(refined)));

  TriMesh sphere = makeIcosphere(2);
  EXPECT_EQ(flipFlatRegionsToDelaunay(sphere), 0);
}

// Relaxing the flat region moves the points off the spokes: far fewer slivers, the same square,
// its boundary vertices where they were.
TEST(MeshRefine, RelaxingAFlatRegionSpreadsItsPointsAndKeepsItsBoundary) {
  TriMesh refined = fannedSquare();
  splitLongEdges(refined, 0.15);
  flipFlatRegionsToDelaunay(refined);
  const TriMesh before = refined;
  const int slivers = trianglesWithAngleBelow(refined, 20.0);
  EXPECT_GT(relaxFlatRegions(refined, 5), 0);
  EXPECT_LT(trianglesWithAngleBelow(refined, 20.0), slivers / 4) << slivers << " before";
  expectTheUnitSquareUnfolded(refined);
  for (const auto v : refined.vertices())
    if (refined.is_boundary(v)) {
      EXPECT_EQ(refined.point(v), before.point(v));
    }

  TriMesh sphere = makeIcosphere(2);
  EXPECT_EQ(relaxFlatRegions(sphere, 3), 0);
}

// refineLongEdges is the three steps in order, and only the split when there is nothing to split:
// the same mesh as splitting, flipping and relaxing by hand, and a fine mesh left as it is.
TEST(MeshRefine, RefineLongEdgesSplitsThenFlipsAndRelaxesTheFlatRegions) {
  TriMesh byHand = fannedSquare();
  const long long splits = splitLongEdges(byHand, 0.15);
  flipFlatRegionsToDelaunay(byHand);
  relaxFlatRegions(byHand, kFlatRelaxationRounds);
  TriMesh refined = fannedSquare();
  EXPECT_EQ(refineLongEdges(refined, 0.15), splits);
  ASSERT_EQ(refined.n_vertices(), byHand.n_vertices());
  for (const auto v : refined.vertices()) EXPECT_EQ(refined.point(v), byHand.point(v));
  EXPECT_EQ(trianglesOf(refined).size(), trianglesOf(byHand).size());

  TriMesh fine = fannedSquare();
  EXPECT_EQ(refineLongEdges(fine, 10.0), 0);
  EXPECT_EQ(trianglesWithAngleBelow(fine, 20.0), trianglesWithAngleBelow(fannedSquare(), 20.0))
      << "nothing split, so the slivers are not flipped either";
}

TEST(MeshRefine, StopsAtTheFaceLimit) {
  TriMesh cylinder = makeCappedCylinder(1.0, 2.0, 16);
  const std::size_t limit = cylinder.n_faces() + 40;
  EXPECT_GT(splitLongEdges(cylinder, 0.01, limit), 0);
  EXPECT_LE(cylinder.n_faces(), limit);
  EXPECT_GE(cylinder.n_faces() + 2, limit);
}

TEST(MeshRefine, LeavesAMeshOfShortEdgesAsItIsAndRefusesABadLength) {
  TriMesh sphere = makeIcosphere(2);
  const std::size_t vertices = sphere.n_vertices();
  EXPECT_EQ(splitLongEdges(sphere, 1.0), 0);
  EXPECT_EQ(sphere.n_vertices(), vertices);
  EXPECT_THROW(splitLongEdges(sphere, 0.0), Error);
  EXPECT_THROW(splitLongEdges(sphere, std::numeric_limits<double>::quiet_NaN()), Error);
}

}  // namespace
}  // namespace hexcover
