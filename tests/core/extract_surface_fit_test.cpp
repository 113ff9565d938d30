// Fitting the remesh to the input surface (core/extract/surface_fit.h): feature snapping onto a
// sharp ridge (its threshold, part-way moves, points sampled along a crease), smoothing of a poor
// triangle on a sphere, relaxation and balancing about the input surface, on meshes generated here.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "core/extract/fan_geometry.h"
#include "core/extract/surface_fit.h"
#include "core/geometry/closest_point.h"
#include "core/mesh/primitives.h"
#include "core/metrics/hausdorff.h"
#include "core/param/hexcover.h"

namespace hexcover::extract_detail {
namespace {

using Vec3 = Eigen::Vector3d;

constexpr double kRidgeX = 2.35;

/// Height of a roof with a sharp ridge along x = kRidgeX (slopes ±1: a 90° dihedral angle).
double roof(double x) { return -std::abs(x - kRidgeX); }

/// The roof over [0, 5.5] × [0, 5.2] as a fine regular grid (110 × 104 cells) with a row of
/// vertices on the ridge.
TriMesh makeRoof() {
  TriMesh mesh;
  constexpr int nx = 110, ny = 104;
  std::vector<TriMesh::VertexHandle> handle;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = 5.5 * i / nx, y = 5.2 * j / ny;
      handle.push_back(mesh.add_vertex({x, y, roof(x)}));
    }
  const auto at = [&](int i, int j) { return handle[j * (nx + 1) + i]; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return mesh;
}

/// The fit's options with snapping at `featureSnapDistance` edge lengths and creases of
/// `creaseAngle` degrees.
SurfaceFitOptions fitOptions(double featureSnapDistance,
                             double creaseAngle = kDefaultFeatureAngle) {
  SurfaceFitOptions options;
  options.featureSnapDistance = featureSnapDistance;
  options.creaseAngle = creaseAngle;
  return options;
}

/// The same without balancing (every vertex stays on the input).
SurfaceFitOptions withoutBalancing(double featureSnapDistance,
                                   double creaseAngle = kDefaultFeatureAngle) {
  SurfaceFitOptions options = fitOptions(featureSnapDistance, creaseAngle);
  options.balanceDeviation = false;
  return options;
}

/// Distance from each point to the mesh.
std::vector<double> distances(const std::vector<Vec3>& points, const TriMesh& mesh) {
  const ClosestPointQuery query(mesh);
  std::vector<double> result;
  for (const Vec3& p : points) result.push_back(query.closest(p).distance);
  return result;
}

double meanDistance(const std::vector<Vec3>& points, const TriMesh& mesh) {
  const std::vector<double> d = distances(points, mesh);
  return std::accumulate(d.begin(), d.end(), 0.0) / static_cast<double>(d.size());
}

double largestDistance(const std::vector<Vec3>& points, const TriMesh& mesh) {
  const std::vector<double> d = distances(points, mesh);
  return *std::max_element(d.begin(), d.end());
}

std::vector<std::array<int, 3>> faceCorners(const TriMesh& mesh) {
  std::vector<std::array<int, 3>> corners;
  for (const auto f : mesh.faces()) {
    const auto h = f.halfedge();
    corners.push_back({h.from().idx(), h.to().idx(), h.next().to().idx()});
  }
  return corners;
}

double smallestAngleDegrees(const TriMesh& mesh) {
  double smallest = 180.0;
  for (const auto f : mesh.faces())
    smallest = std::min(
        smallest, angleRange(facePositions(mesh, f, OpenMesh::VertexHandle(), Vec3::Zero()))[0]);
  return smallest;
}

TEST(SurfaceFit, SnapsVerticesOntoASharpRidgeThatTheCoarseMeshCutsOff) {
  const TriMesh input = makeRoof();
  // A coarse equilateral grid (edge 1) lifted onto the roof: its vertices lie on the surface but
  // none on the ridge, so its triangles cut the ridge off.
  TriMesh remesh = makeEquilateralGrid(6, 7);
  for (const auto v : remesh.vertices()) {
    auto p = remesh.point(v);
    p[2] = roof(p[0]);
    remesh.set_point(v, p);
  }
  const TriMesh before = remesh;
  // The ridge away from the remesh's jagged boundary.
  std::vector<Vec3> ridge;
  for (const auto v : input.vertices()) {
    const Vec3 p = toEigen(input.point(v));
    if (std::abs(p.x() - kRidgeX) < 1e-9 && p.y() > 1.0 && p.y() < 4.2) ridge.push_back(p);
  }
  ASSERT_FALSE(ridge.empty());
  const double cutOff = largestDistance(ridge, remesh);
  ASSERT_GT(cutOff, 0.1) << "the coarse mesh should miss the ridge";

  TriMesh withoutCreases = remesh;
  const SurfaceFitCounts counts =
      fitRemeshToSurface(input, ClosestPointQuery(input), remesh, withoutBalancing(0.1));
  EXPECT_GT(counts.snapped, 0);
  EXPECT_LT(largestDistance(ridge, remesh), 0.5 * cutOff);
  // Without crease vertices, relaxation evens out the angles at the ridge's expense (within
  // kRelaxDeviation = 0.2 edge lengths).
  fitRemeshToSurface(input, ClosestPointQuery(input), withoutCreases,
                     withoutBalancing(0.1, /*creaseAngle=*/0.0));
  EXPECT_GT(largestDistance(ridge, withoutCreases), largestDistance(ridge, remesh) + 0.02);
  // Same triangles; every vertex still on the roof; boundary vertices where they were.
  EXPECT_EQ(faceCorners(remesh), faceCorners(before));
  for (const auto v : remesh.vertices()) {
    const auto p = remesh.point(v);
    EXPECT_NEAR(p[2], roof(p[0]), 1e-12);
    if (remesh.is_boundary(v)) {
      EXPECT_EQ(p, before.point(v));
    }
  }
  EXPECT_GE(smallestAngleDegrees(remesh), 20.0);
}

// The same ridge on a roof of four triangles: the input has no vertex on the ridge between its
// ends, so only points sampled along the crease edge can pull the remesh onto it. The coarse
// grid's rows cross the ridge (vertices 0.05 beside it on every other row, 0.45 on the others),
// so its triangles cut the ridge off, by more than the snap distance of 0.35 edge lengths between
// rows; vertices beside it snap onto it (its closest point), and the ridge comes closer on
// average (the rows in between still cut it off).
/// Smallest and largest angle over all triangles (degrees).
std::array<double, 2> angleExtremes(const TriMesh& mesh) {
  std::array<double, 2> extremes{180.0, 0.0};
  for (const auto f : mesh.faces()) {
    const auto range = angleRange(facePositions(mesh, f, OpenMesh::VertexHandle(), Vec3::Zero()));
    extremes = {std::min(extremes[0], range[0]), std::max(extremes[1], range[1])};
  }
  return extremes;
}

TEST(SurfaceFit, MovesCornersOfAnglesThatSnappingLeftOutsideTheGoalWindow) {
  // The coarse grid on the roof again: the vertices that snap onto the ridge leave two angles
  // of about 25° that relaxation keeps (its descent would shrink them further or pull the
  // vertices off the ridge). The outlier-angle moves open them to at least 30°.
  const TriMesh input = makeRoof();
  const ClosestPointQuery onInput(input);
  TriMesh remesh = makeEquilateralGrid(6, 7);
  for (const auto v : remesh.vertices()) {
    auto p = remesh.point(v);
    p[2] = roof(p[0]);
    remesh.set_point(v, p);
  }
  std::vector<Vec3> ridge;
  for (const auto v : input.vertices())
    if (const Vec3 p = toEigen(input.point(v)); std::abs(p.x() - kRidgeX) < 1e-9)
      ridge.push_back(p);

  SurfaceFitOptions options = withoutBalancing(0.1);
  options.openOutlierAngles = false;
  TriMesh left = remesh;
  EXPECT_EQ(fitRemeshToSurface(input, onInput, left, options).outliers, 0);
  ASSERT_LT(angleExtremes(left)[0], 30.0) << "snapping should leave an angle below the window";

  options.openOutlierAngles = true;
  const SurfaceFitCounts counts = fitRemeshToSurface(input, onInput, remesh, options);
  EXPECT_GT(counts.outliers, 0);
  const auto [smallest, largest] = angleExtremes(remesh);
  EXPECT_GE(smallest, 30.0) << "was " << angleExtremes(left)[0];
  EXPECT_LE(largest, std::max(100.0, angleExtremes(left)[1]));
  EXPECT_LE(largestDistance(ridge, remesh), largestDistance(ridge, left) + 1e-9)
      << "the ridge is no farther from the remesh";
  for (const auto v : remesh.vertices())
    EXPECT_LT(onInput.closest(toEigen(remesh.point(v))).distance, 1e-12) << "on the roof";
}

TEST(SurfaceFit, SnapsVerticesBesideACreaseOntoItBetweenTheInputsVertices) {
  TriMesh input;
  std::vector<TriMesh::VertexHandle> corner;
  for (const double y : {0.0, 5.2})
    for (const double x : {0.0, kRidgeX, 5.5}) corner.push_back(input.add_vertex({x, y, roof(x)}));
  input.add_face(corner[0], corner[1], corner[4]);
  input.add_face(corner[0], corner[4], corner[3]);
  input.add_face(corner[1], corner[2], corner[5]);
  input.add_face(corner[1], corner[5], corner[4]);
  TriMesh remesh = makeEquilateralGrid(6, 7);
  for (const auto v : remesh.vertices()) {
    auto p = remesh.point(v);
    p[0] -= 0.1;
    p[2] = roof(p[0]);
    remesh.set_point(v, p);
  }
  std::vector<Vec3> ridge;
  for (double y = 1.0; y <= 4.2; y += 0.05) ridge.emplace_back(kRidgeX, y, 0.0);
  TriMesh withoutCreases = remesh;
  const SurfaceFitCounts counts =
      fitRemeshToSurface(input, ClosestPointQuery(input), remesh, withoutBalancing(0.35));
  fitRemeshToSurface(input, ClosestPointQuery(input), withoutCreases,
                     withoutBalancing(0.35, /*creaseAngle=*/0.0));
  const auto onRidge = [](const TriMesh& mesh) {
    int count = 0;
    for (const auto v : mesh.vertices())
      count += std::abs(mesh.point(v)[0] - kRidgeX) < 1e-9 && !mesh.is_boundary(v) ? 1 : 0;
    return count;
  };
  EXPECT_GT(counts.snapped, 0);
  EXPECT_GE(onRidge(remesh), 2);
  EXPECT_EQ(onRidge(withoutCreases), 0);
  EXPECT_LT(meanDistance(ridge, remesh), 0.9 * meanDistance(ridge, withoutCreases));
  EXPECT_GE(smallestAngleDegrees(remesh), 20.0);
}

/// The coarse grid of the ridge test (edge 1) lifted onto the roof, and optionally a second
/// component far away: a fine grid (edge 0.1) that pulls the remesh's mean edge length down.
TriMesh liftedGridOnTheRoof(bool withFineComponent) {
  TriMesh remesh = makeEquilateralGrid(6, 7);
  for (const auto v : remesh.vertices()) {
    auto p = remesh.point(v);
    p[2] = roof(p[0]);
    remesh.set_point(v, p);
  }
  if (!withFineComponent) return remesh;
  const TriMesh fine = makeEquilateralGrid(30, 30, 0.1);
  std::vector<TriMesh::VertexHandle> copy;
  for (const auto v : fine.vertices()) {
    const auto p = fine.point(v);
    copy.push_back(remesh.add_vertex({p[0] + 100.0, p[1], p[2]}));
  }
  for (const auto f : fine.faces()) {
    std::vector<TriMesh::VertexHandle> corners;
    for (const auto v : f.vertices()) corners.push_back(copy[v.idx()]);
    remesh.add_face(corners);
  }
  return remesh;
}

TEST(SurfaceFit, MeasuresTheSnapThresholdAgainstTheMeanEdgeLengthWhereTrianglesAreLarger) {
  // The ridge is at most 0.4 edge lengths from the coarse grid: under a snap threshold of 0.45
  // when the grid is the whole remesh. With a fine component elsewhere the mean edge length is
  // far smaller, and the threshold, 0.45 × the smaller of the two, lets the ridge pull vertices.
  const TriMesh input = makeRoof();
  std::vector<Vec3> ridge;
  for (const auto v : input.vertices()) {
    const Vec3 p = toEigen(input.point(v));
    if (std::abs(p.x() - kRidgeX) < 1e-9 && p.y() > 1.0 && p.y() < 4.2) ridge.push_back(p);
  }
  TriMesh alone = liftedGridOnTheRoof(false);
  const double cutOff = largestDistance(ridge, alone);
  ASSERT_LT(cutOff, 0.45) << "the ridge should be within the threshold of the coarse grid alone";
  EXPECT_EQ(
      fitRemeshToSurface(input, ClosestPointQuery(input), alone, withoutBalancing(0.45)).snapped,
      0);

  TriMesh withFine = liftedGridOnTheRoof(true);
  const SurfaceFitCounts counts =
      fitRemeshToSurface(input, ClosestPointQuery(input), withFine, withoutBalancing(0.45));
  EXPECT_GT(counts.snapped, 0);
  EXPECT_LT(largestDistance(ridge, withFine), 0.5 * cutOff);
}

TEST(SurfaceFit, MovesPartWayToARidgeWhenAFullSnapWouldOpenAnAngleTooFar) {
  // A roof with slopes ±0.5 and its ridge along y = 0.6, and a unit hexagon fan on it centred at
  // the origin: the ring is the remesh's boundary (fixed), the centre may move. All the way onto
  // the ridge its fan would have a 118.5° angle (the snap allows 115°); 0.7 of the way, 96°.
  constexpr double kRidge = 0.6;
  const auto height = [](double y) { return -0.5 * std::abs(y - kRidge); };
  // The input: a fine grid over [−0.4, 0.4] × [−0.6, 0.8] (inside the fan, so that every input
  // point is near it), with a row of vertices on the ridge.
  TriMesh input;
  constexpr int nx = 16, ny = 28;
  std::vector<TriMesh::VertexHandle> grid;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = -0.4 + 0.05 * i, y = -0.6 + 0.05 * j;
      grid.push_back(input.add_vertex({x, y, height(y)}));
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const auto at = [&](int a, int b) { return grid[b * (nx + 1) + a]; };
      input.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      input.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  TriMesh fan;
  const auto centre = fan.add_vertex({0.0, 0.0, height(0.0)});
  std::vector<TriMesh::VertexHandle> ring;
  for (int k = 0; k < 6; ++k) {
    const double x = std::cos(k * M_PI / 3.0), y = std::sin(k * M_PI / 3.0);
    ring.push_back(fan.add_vertex({x, y, height(y)}));
  }
  for (int k = 0; k < 6; ++k) fan.add_face(centre, ring[k], ring[(k + 1) % 6]);
  const std::vector<Vec3> ridgePoint{Vec3(0.0, kRidge, 0.0)};
  const double before = largestDistance(ridgePoint, fan);

  const SurfaceFitCounts counts =
      fitRemeshToSurface(input, ClosestPointQuery(input), fan, withoutBalancing(0.1));
  EXPECT_GE(counts.snapped, 1);  // part-way moves may go on in later rounds
  const auto moved = fan.point(centre);
  EXPECT_GT(moved[1], 0.3);
  EXPECT_LT(moved[1], kRidge - 0.05) << "the centre should stop short of the ridge";
  EXPECT_NEAR(moved[2], height(moved[1]), 1e-12);
  EXPECT_LT(largestDistance(ridgePoint, fan), 0.6 * before);
  EXPECT_GE(smallestAngleDegrees(fan), 25.0);
}

TEST(SurfaceFit, SmoothsAPoorTriangleAndKeepsTheVertexOnTheSurface) {
  const TriMesh input = makeIcosphere(5);
  TriMesh remesh = makeIcosphere(2);
  const ClosestPointQuery onInput(input);
  for (const auto v : remesh.vertices())
    remesh.set_point(v, toOpenMesh(onInput.closest(toEigen(remesh.point(v))).point));
  // Pull one regular vertex 60% of the way towards a neighbour (back onto the input surface).
  const auto moved = *std::find_if(remesh.vertices().begin(), remesh.vertices().end(),
                                   [&](auto v) { return v.valence() == 6; });
  const Vec3 from = toEigen(remesh.point(moved));
  const Vec3 towards = toEigen(remesh.point(*moved.vertices().begin()));
  remesh.set_point(moved, toOpenMesh(onInput.closest(from + 0.6 * (towards - from)).point));
  const double poor = smallestAngleDegrees(remesh);
  ASSERT_LT(poor, 25.0);

  const SurfaceFitCounts counts =
      fitRemeshToSurface(input, onInput, remesh, withoutBalancing(/*featureSnapDistance=*/0.0));
  EXPECT_EQ(counts.snapped, 0) << "snapping is off";
  EXPECT_EQ(counts.balanced, 0) << "balancing is off";
  EXPECT_GT(counts.smoothed, 0);
  EXPECT_GT(smallestAngleDegrees(remesh), 40.0) << "was " << poor;
  for (const auto v : remesh.vertices())
    EXPECT_LT(onInput.closest(toEigen(remesh.point(v))).distance, 1e-12);
}

/// Standard deviation of all corner angles (degrees).
double angleSd(const TriMesh& mesh) {
  double sum = 0.0, sumSquares = 0.0, count = 0.0;
  for (const auto f : mesh.faces()) {
    const auto p = facePositions(mesh, f, OpenMesh::VertexHandle(), Vec3::Zero());
    for (int j = 0; j < 3; ++j) {
      const double a = angleAt(p[j], p[(j + 1) % 3], p[(j + 2) % 3]);
      sum += a, sumSquares += a * a, count += 1.0;
    }
  }
  return std::sqrt(sumSquares / count - (sum / count) * (sum / count));
}

/// An equilateral grid (edge 1) with its interior vertices jittered in the plane by up to 0.2
/// edge lengths (a fixed pattern).
TriMesh jitteredGrid(int columns, int rows) {
  TriMesh grid = makeEquilateralGrid(columns, rows);
  int k = 0;
  for (const auto v : grid.vertices()) {
    if (grid.is_boundary(v)) continue;
    ++k;
    grid.set_point(
        v, grid.point(v) + TriMesh::Point(0.2 * std::sin(1.7 * k), 0.2 * std::cos(2.3 * k), 0.0));
  }
  return grid;
}

TEST(SurfaceFit, RelaxesAJitteredGridInItsPlane) {
  const TriMesh input = makeEquilateralGrid(12, 12);
  TriMesh remesh = jitteredGrid(12, 12);
  const TriMesh jittered = remesh;
  const double before = angleSd(remesh);
  ASSERT_GT(before, 8.0);

  const SurfaceFitCounts counts =
      fitRemeshToSurface(input, ClosestPointQuery(input), remesh, fitOptions(0.35));
  EXPECT_EQ(counts.snapped, 0) << "the grid has no feature";
  EXPECT_GT(counts.relaxed, 0);
  EXPECT_LT(angleSd(remesh), 0.7 * before);
  for (const auto v : remesh.vertices()) {
    EXPECT_EQ(remesh.point(v)[2], 0.0) << "stays in the plane";
    if (remesh.is_boundary(v)) {
      EXPECT_EQ(remesh.point(v), jittered.point(v));
    }
  }
}

TEST(SurfaceFit, RelaxationGivesTheSameMeshForAnyThreadCount) {
  // Large enough that each independent class spans several chunks of work.
  const TriMesh input = makeEquilateralGrid(40, 40);
  const ClosestPointQuery onInput(input);
  TriMesh one = jitteredGrid(40, 40), two = one;
  SurfaceFitOptions options = withoutBalancing(0.0);
  const auto counts = fitRemeshToSurface(input, onInput, one, options);
  options.threads = 2;
  fitRemeshToSurface(input, onInput, two, options);
  EXPECT_GT(counts.relaxed, 1000);
  for (const auto v : one.vertices()) EXPECT_EQ(one.point(v), two.point(v));
}

TEST(SurfaceFit, OnlyRelaxesAMeshThatMatchesTheInput) {
  // An icosphere against itself: no input point is away from the remesh and no triangle is poor,
  // so nothing snaps or smooths; relaxation may even out the angles (54°-72°) near the 12
  // valence-5 vertices, over the input surface.
  const TriMesh input = makeIcosphere(3);
  TriMesh remesh = input;
  const ClosestPointQuery onInput(input);
  const SurfaceFitCounts counts = fitRemeshToSurface(input, onInput, remesh, fitOptions(0.35));
  EXPECT_EQ(counts.snapped, 0);
  EXPECT_EQ(counts.smoothed, 0);
  EXPECT_LE(angleSd(remesh), angleSd(input));
  for (const auto v : remesh.vertices())
    EXPECT_LT(onInput.closest(toEigen(remesh.point(v))).distance, 1e-12);
}

TEST(SurfaceFit, BalancesACoarseSphereAboutTheInputSurface) {
  // An icosphere of 42 vertices on a finely tessellated unit sphere: its triangles lie inside
  // the sphere by up to their sagitta (0.1 edge lengths). Lifting the vertices by about half of
  // it balances the two sides, so the two-sided distance drops by about half; angles barely
  // change.
  const TriMesh input = makeIcosphere(5);
  const ClosestPointQuery onInput(input);
  TriMesh remesh = makeIcosphere(1);
  const TwoSidedDistance before = twoSidedDistance(input, remesh);
  const double sdBefore = angleSd(remesh);

  TriMesh unbalanced = remesh;
  EXPECT_EQ(fitRemeshToSurface(input, onInput, unbalanced, withoutBalancing(0.35)).balanced, 0);
  EXPECT_NEAR(twoSidedDistance(input, unbalanced).hausdorff(), before.hausdorff(),
              1e-3 * before.hausdorff())
      << "without balancing nothing moves off the sphere";

  const SurfaceFitCounts counts = fitRemeshToSurface(input, onInput, remesh, fitOptions(0.35));
  EXPECT_GE(counts.balanced, 42);
  const TwoSidedDistance after = twoSidedDistance(input, remesh);
  EXPECT_LT(after.hausdorff(), 0.65 * before.hausdorff());
  EXPECT_LT(after.aToB.max, 0.65 * before.aToB.max) << "the sphere comes closer to the remesh";
  EXPECT_GT(after.bToA.max, 0.2 * before.hausdorff()) << "the vertices leave the sphere";
  for (const auto v : remesh.vertices())
    EXPECT_GT(toEigen(remesh.point(v)).norm(), 1.0) << "lifted outwards";
  EXPECT_LT(angleSd(remesh), sdBefore + 0.5);
}

}  // namespace
}  // namespace hexcover::extract_detail
