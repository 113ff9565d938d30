// Edge flips and boundary-sample slides among the triangles that boundary stitching adds
// (core/extract/boundary.h).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/extract/boundary.h"
#include "core/extract/fan_geometry.h"

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

double smallestAngle(const TriMesh& mesh) {
  double angle = 180.0;
  for (const auto f : mesh.faces())
    angle = std::min(angle, angleRange(facePositions(mesh, f, OpenMesh::VertexHandle(),
                                                     Eigen::Vector3d::Zero()))[0]);
  return angle;
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

// Step 8 on a mesh: the rhombus's 15° slivers touch its boundary and are flipped below 20°; a
// rhombus with 25° angles is not, unless its 130° angles are above the obtuse bound.
TEST(BoundaryFlips, FlipBoundarySliversBelowTheFloorOnly) {
  const auto rhombusMesh = [](double halfWidth) {
    TriMesh mesh;
    std::vector<TriMesh::VertexHandle> v;
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, -halfWidth, 0),
                                     Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(1, halfWidth, 0)})
      v.push_back(mesh.add_vertex(toOpenMesh(p)));
    mesh.add_face(v[0], v[1], v[2]);
    mesh.add_face(v[0], v[2], v[3]);
    return mesh;
  };
  TriMesh thin = rhombusMesh(0.2679);  // tan 15°
  ASSERT_NEAR(smallestAngle(thin), 15.0, 0.01);
  EXPECT_EQ(flipBoundarySlivers(thin, 20.0), 1);
  EXPECT_GT(smallestAngle(thin), 29.9);
  EXPECT_EQ(thin.n_faces(), 2u);
  TriMesh wide = rhombusMesh(0.4663);  // tan 25°
  EXPECT_EQ(flipBoundarySlivers(wide, 20.0), 0);
  EXPECT_NEAR(smallestAngle(wide), 25.0, 0.01);
  // Its two 130° angles are flipped away above 120° (not above 135°): 50° and 65° after.
  EXPECT_EQ(flipBoundarySlivers(wide, 20.0, 135.0), 0);
  EXPECT_EQ(flipBoundarySlivers(wide, 20.0, 120.0), 1);
  EXPECT_NEAR(smallestAngle(wide), 50.0, 0.01);
  // N = 4: a triangle marked fixed (half of a square) keeps its vertices.
  TriMesh halfOfSquare = rhombusMesh(0.2679);
  OpenMesh::FPropHandleT<bool> fixed;
  halfOfSquare.add_property(fixed);
  for (const auto f : halfOfSquare.faces()) halfOfSquare.property(fixed, f) = f.idx() == 1;
  EXPECT_EQ(flipBoundarySlivers(halfOfSquare, 20.0, 180.0, fixed), 0);
  EXPECT_NEAR(smallestAngle(halfOfSquare), 15.0, 0.01);
}

// A flat 4 × 3 grid of unit squares (diagonals (x, y)-(x+1, y+1)) whose bottom boundary vertex
// (1, 0) sits at (1.9, 0), 0.1 from its neighbour (2, 0): its triangles are slivers of 6°. The
// vertex is collapsed along the straight boundary; the corner (0, 0), whose boundary turns by
// 90°, is not, and a regular grid is left alone. So is the vertex at (1.9, −0.1), a lip of the
// boundary, but not at (1.9, −0.6), a notch.
TEST(BoundaryFlips, CollapsesABoundarySampleThatMakesSliversWhereTheBoundaryRunsStraight) {
  const auto grid = [](double movedX, double movedY = 0.0) {
    TriMesh mesh;
    std::vector<TriMesh::VertexHandle> v;
    for (int y = 0; y <= 3; ++y)
      for (int x = 0; x <= 4; ++x)
        v.push_back(
            mesh.add_vertex({y == 0 && x == 1 ? movedX : x, y == 0 && x == 1 ? movedY : y, 0.0}));
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        const auto at = [&](int dx, int dy) { return v[(y + dy) * 5 + x + dx]; };
        mesh.add_face(at(0, 0), at(1, 0), at(1, 1));
        mesh.add_face(at(0, 0), at(1, 1), at(0, 1));
      }
    return mesh;
  };
  TriMesh slivers = grid(1.9);
  ASSERT_LT(smallestAngle(slivers), 6.0);
  EXPECT_EQ(collapseBoundarySlivers(slivers, 20.0, 30.0), 1);
  EXPECT_GT(smallestAngle(slivers), 20.0);
  EXPECT_EQ(slivers.n_vertices(), 19u);
  EXPECT_EQ(slivers.n_faces(), 23u) << "one boundary triangle less, still a disk";
  int boundaryVertices = 0;
  bool cornerKept = false;
  for (const auto v : slivers.vertices()) {
    if (!v.is_boundary()) continue;
    ++boundaryVertices;
    const auto p = slivers.point(v);
    cornerKept = cornerKept || (p[0] == 0.0 && p[1] == 0.0);
    EXPECT_TRUE(p[0] == 0.0 || p[0] == 4.0 || p[1] == 0.0 || p[1] == 3.0)
        << "a boundary vertex left the boundary: (" << p[0] << ", " << p[1] << ")";
  }
  EXPECT_EQ(boundaryVertices, 13);
  EXPECT_TRUE(cornerKept);

  TriMesh regular = grid(1.0);
  EXPECT_EQ(collapseBoundarySlivers(regular, 20.0, 30.0), 0);
  EXPECT_EQ(regular.n_vertices(), 20u);

  // Pushed 0.1 out of the boundary, the vertex turns it by 48°, but the boundary without it stays
  // within a quarter of its edges' mean length (a lip curled at a fraction of an edge length): it
  // goes. Pushed 0.6 out, it is a corner of a notch, and stays.
  TriMesh lip = grid(1.9, -0.1);
  ASSERT_LT(smallestAngle(lip), 10.0);
  EXPECT_EQ(collapseBoundarySlivers(lip, 20.0, 30.0), 1);
  EXPECT_EQ(lip.n_vertices(), 19u);
  for (const auto v : lip.vertices())
    EXPECT_FALSE(lip.point(v)[0] == 1.9 && lip.point(v)[1] == -0.1) << "the lip's vertex stayed";
  TriMesh notch = grid(1.9, -0.6);
  ASSERT_LT(smallestAngle(notch), 10.0);
  collapseBoundarySlivers(notch, 20.0, 30.0);
  bool notchKept = false;
  for (const auto v : notch.vertices())
    notchKept = notchKept || (notch.point(v)[0] == 1.9 && notch.point(v)[1] == -0.6);
  EXPECT_TRUE(notchKept);

  // N = 4: the sliver vertex stays while one of its triangles is marked fixed (half of a
  // square); marks elsewhere do not stop it, and they move along with the faces' renumbering.
  const auto marked = [&](int x, int y, int triangle) {
    TriMesh mesh = grid(1.9);
    OpenMesh::FPropHandleT<bool> fixed;
    mesh.add_property(fixed);
    for (const auto f : mesh.faces())
      mesh.property(fixed, f) = f.idx() == 2 * (y * 4 + x) + triangle;
    return std::make_pair(std::move(mesh), fixed);
  };
  auto [besideSliver, fixedBeside] = marked(1, 0, 0);  // (1, 0)-(2, 0)-(2, 1): a sliver of (1.9, 0)
  EXPECT_EQ(collapseBoundarySlivers(besideSliver, 20.0, 30.0, fixedBeside), 0);
  auto [farAway, fixedFar] = marked(3, 2, 1);  // the top right square's upper triangle
  EXPECT_EQ(collapseBoundarySlivers(farAway, 20.0, 30.0, fixedFar), 1);
  int fixedFaces = 0;
  for (const auto f : farAway.faces()) {
    if (!farAway.property(fixedFar, f)) continue;
    ++fixedFaces;
    for (const auto v : f.vertices())  // (3, 2), (4, 3), (3, 3)
      EXPECT_TRUE(farAway.point(v)[0] >= 3.0 && farAway.point(v)[1] >= 2.0);
  }
  EXPECT_EQ(fixedFaces, 1);
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

// A fold: a third triangle on the rhombus's long diagonal 0-2 (the strip folded onto itself, as
// where a zip reuses an edge). Flipping the diagonal under it would leave the third triangle's
// edge with no neighbour and join vertex 2's two fans at one vertex; the repair mends folds.
TEST(BoundaryFlips, LeavesAnEdgeOfAFoldAsItIs) {
  std::vector<Eigen::Vector3d> points = kRhombus;
  points.push_back({1, 0, 1});
  std::vector<Triangle> region = {{0, 1, 2}, {0, 2, 3}, {2, 0, 4}};
  EXPECT_EQ(improveByFlips(points, {}, region), 0);
  // The same fold made of a lattice triangle.
  region.pop_back();
  EXPECT_EQ(improveByFlips(points, {{2, 0, 4}}, region), 0);
  EXPECT_EQ(improveByFlips(points, {}, region), 1) << "without the fold, the diagonal flips";
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

namespace hexcover::extract_detail {
namespace {

// A unit square boundary loop (four sharp corners) with one sample at arc 0.2 on its first side
// and a front vertex above the side's middle: sliding centres the sample under the front vertex
// (right angles at the sample, the smallest deviation from 60° there), keeps it on the boundary
// and leaves the corners.
TEST(BoundarySlides, CentreASampleUnderItsFrontVertexAlongTheBoundary) {
  const std::vector<Eigen::Vector3d> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const BoundaryIndex index({square}, 0.5);
  std::vector<Eigen::Vector3d> positions = square;
  positions.push_back({0.2, 0, 0});    // 4: the sample
  positions.push_back({0.5, 0.4, 0});  // 5: the front vertex
  const std::vector<Triangle> region = {{0, 4, 5}, {4, 1, 5}};
  std::vector<LoopSamples> samples = {
      {0, 1.0, {0, 4, 1, 2, 3}, {0.0, 0.2, 1.0, 2.0, 3.0}, {true, false, true, true, true}}};
  EXPECT_EQ(slideBoundarySamples(index, samples, region, positions), 1);
  EXPECT_NEAR(samples[0].arc[1], 0.5, 1e-12);
  EXPECT_TRUE(positions[4].isApprox(Eigen::Vector3d(0.5, 0, 0)));
  for (int corner = 0; corner < 4; ++corner) EXPECT_EQ(positions[corner], square[corner]);
  EXPECT_EQ(slideBoundarySamples(index, samples, region, positions), 0) << "nothing left to gain";
}

// Samples keep 0.3 spacings from their neighbours: a sample between two that are closer than
// that on both sides stays where it is, whatever its triangles look like.
TEST(BoundarySlides, NeverCrowdTheirNeighbours) {
  const std::vector<Eigen::Vector3d> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const BoundaryIndex index({square}, 0.5);
  std::vector<Eigen::Vector3d> positions = square;
  positions.push_back({0.1, 0, 0});  // 4: the sample, 0.1 from both neighbours
  positions.push_back({0.2, 0, 0});  // 5: a corner-like fixed neighbour
  positions.push_back({0.9, 0.4, 0});
  const std::vector<Triangle> region = {{0, 4, 6}, {4, 5, 6}};
  std::vector<LoopSamples> samples = {{0, 1.0, {0, 4, 5, 1, 2, 3},
                                       {0.0, 0.1, 0.2, 1.0, 2.0, 3.0},
                                       {true, false, true, true, true, true}}};
  EXPECT_EQ(slideBoundarySamples(index, samples, region, positions), 0);
  EXPECT_EQ(positions[4], Eigen::Vector3d(0.1, 0, 0));
}

// A sample 0.3 spacings from a sharp corner, under a front vertex close to the corner: its
// smallest angle is 15.7° (the bunny's holes had such a triangle). Weighing the largest deviation
// from 60° on both sides alike kept it there (the other side's largest angle is 103.8°); weighed
// against the floors (20° and 130°), the slide trades: 24.3° and 117.8°.
TEST(BoundarySlides, RaiseASmallAngleAtACornerWithinTheFloors) {
  const std::vector<Eigen::Vector3d> rectangle = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
  const BoundaryIndex index({rectangle}, 0.5);
  std::vector<Eigen::Vector3d> positions = rectangle;
  positions.push_back({0.3, 0, 0});     // 4: the sample
  positions.push_back({0.03, 0.32, 0});  // 5, 6: front vertices
  positions.push_back({1.51, 0.6, 0});
  const std::vector<Triangle> region = {{0, 4, 5}, {4, 1, 6}, {4, 6, 5}};
  const auto angles = [&] {
    std::array<double, 2> range{180.0, 0.0};
    for (const auto& t : region) {
      const auto r = angleRange({positions[t[0]], positions[t[1]], positions[t[2]]});
      range = {std::min(range[0], r[0]), std::max(range[1], r[1])};
    }
    return range;
  };
  ASSERT_LT(angles()[0], 16.0);
  std::vector<LoopSamples> samples = {
      {0, 1.0, {0, 4, 1, 2, 3}, {0.0, 0.3, 2.0, 3.0, 5.0}, {true, false, true, true, true}}};
  EXPECT_GE(slideBoundarySamples(index, samples, region, positions), 1);
  EXPECT_GT(angles()[0], 20.0);
  EXPECT_LT(angles()[1], 130.0);
  EXPECT_NEAR(positions[4].y(), 0.0, 1e-12) << "on the boundary";
}

// The loop point farthest from a chord between two arc lengths, across the loop's start too.
TEST(BoundaryIndexChords, FindTheLoopPointFarthestFromAChord) {
  const std::vector<Eigen::Vector3d> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const BoundaryIndex index({square}, 0.5);
  const BoundaryIndex::Hit corner = index.farthestFromChord(0, 0.5, 1.5);  // (0.5,0)–(1,0.5)
  EXPECT_EQ(corner.loop, 0);
  EXPECT_NEAR(corner.distance, std::sqrt(0.125), 1e-12);
  EXPECT_NEAR(corner.arc, 1.0, 1e-12);
  const BoundaryIndex::Hit wrapped = index.farthestFromChord(0, 3.5, 4.5);  // around (0, 0)
  EXPECT_NEAR(wrapped.distance, std::sqrt(0.125), 1e-12);
  EXPECT_NEAR(wrapped.arc, 0.0, 1e-12);
  EXPECT_EQ(index.farthestFromChord(0, 0.25, 0.75).loop, -1) << "no loop point in between";
}

// Two unit squares 0.1 apart, of components 0 and 1: a point between them is nearest to the
// second, but the boundary of a component-0 point is the first square's.
TEST(BoundaryIndexComponents, FindTheNearestLoopOfAComponent) {
  const std::vector<Eigen::Vector3d> first = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<Eigen::Vector3d> second = first;
  for (auto& p : second) p.x() += 1.1;
  const BoundaryIndex index({first, second}, 0.5, {0, 1});
  const Eigen::Vector3d between(1.08, 0.5, 0.0);
  EXPECT_EQ(index.nearest(between, 0.5).loop, 1);
  EXPECT_EQ(index.nearestInComponent(between, 0.5, 1).loop, 1);
  const BoundaryIndex::Hit own = index.nearestInComponent(between, 0.5, 0);
  EXPECT_EQ(own.loop, 0);
  EXPECT_NEAR(own.distance, 0.08, 1e-12);
  EXPECT_EQ(index.nearestInComponent(between, 0.05, 0).loop, -1) << "only the other's is as near";
}

// A loop that bulges 0.4 spacings out between two corners, with a sample on the bulge's tip and
// a front vertex off to the left: the angles alone would slide the sample 0.34 spacings down
// the bulge's right side, and its edge from the left corner would cut 0.27 spacings into the
// bulge (venus_1k's base lost 0.35 edge lengths that way: 2.5% Hausdorff distance). The slide
// keeps the loop within 0.25 spacings of the sample's edges.
TEST(BoundarySlides, KeepTheLoopCloseToTheSamplesEdges) {
  const std::vector<Eigen::Vector3d> loop = {
      {0, 0, 0}, {0.5, -0.4, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const BoundaryIndex index({loop}, 0.5);
  std::vector<Eigen::Vector3d> positions = loop;
  positions.push_back({0.5, -0.4, 0});  // 5: the sample, on the tip
  positions.push_back({-0.2, 0.3, 0});  // 6: the front vertex
  const std::vector<Triangle> region = {{0, 5, 6}, {5, 2, 6}};
  const double tip = loop[1].norm();
  std::vector<LoopSamples> samples = {{0,
                                       1.0,
                                       {0, 5, 2, 3, 4},
                                       {0.0, tip, 2 * tip, 2 * tip + 1, 2 * tip + 2},
                                       {true, false, true, true, true}}};
  slideBoundarySamples(index, samples, region, positions);
  const double s = samples[0].arc[1];
  EXPECT_LE(index.farthestFromChord(0, 0.0, s).distance, 0.25 + 1e-12);
  EXPECT_LE(index.farthestFromChord(0, s, 2 * tip).distance, 0.25 + 1e-12);
  EXPECT_TRUE(positions[5].isApprox(index.pointAt(0, s))) << "on the boundary";
}

}  // namespace
}  // namespace hexcover::extract_detail
