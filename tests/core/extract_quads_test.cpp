// The quad remesh of the Gauss lattice (N = 4): extraction on parameterizations built by hand (a
// flat torus, fans of 3 and 5 quarter planes whose 90° transition makes a cone of index +1/4 or
// -1/4), and the metrics of a polygon mesh.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "core/extract/extract.h"
#include "core/extract/quad_mesh.h"
#include "core/extract/surface_fit.h"
#include "core/geometry/closest_point.h"
#include "core/mesh/primitives.h"
#include "core/mesh/topology.h"
#include "core/metrics/metrics.h"
#include "tests/common/lattice_parameterizations.h"

namespace hexcover {
namespace {

using test::coneFan;
using test::facesOfSize;
using test::flatTorusParameterization;
using test::polygonValences;
using test::PolygonValences;

TEST(ExtractQuads, FlatTorusGivesOneQuadPerLatticePointAllOfValenceFour) {
  const int around = 50, tube = 8;
  const TriMesh torus = makeTorus(10.0, 1.0, around, tube);
  // Periods (63, 0) along the major circle (2π·10 ≈ 63) and (0, 6) around the tube (2π ≈ 6):
  // 63·6 = 378 lattice points, and as many unit squares.
  const auto param = flatTorusParameterization(torus, around, tube, {63, 0}, {0, 6}, 4);
  const Remesh remesh = extractRemesh(torus, param);
  EXPECT_EQ(remesh.report.inconsistentVertices, 0);
  EXPECT_EQ(remesh.report.transitionsCorrected, 0);
  EXPECT_EQ(remesh.report.latticePoints, 378);
  EXPECT_EQ(remesh.report.latticeSquares, 378);
  const PolygonSoup& quads = remesh.quads;
  EXPECT_EQ(quads.vertexCount(), 378u);
  EXPECT_EQ(quads.faceCount(), 378u);
  EXPECT_EQ(facesOfSize(quads, 4), 378);
  const PolygonValences valences = polygonValences(quads);
  for (std::size_t v = 0; v < quads.vertexCount(); ++v) {
    EXPECT_FALSE(valences.onBoundary[v]);
    EXPECT_EQ(valences.valence[v], 4) << "vertex " << v;
  }
  // The triangles behind the quads: two per square, a closed torus.
  EXPECT_EQ(remesh.triangles.n_faces(), 756u);
  const MeshTopology topology = computeTopology(remesh.triangles);
  EXPECT_EQ(topology.genus(), 1);
  EXPECT_EQ(topology.boundaryLoops, 0);
  EXPECT_TRUE(topology.manifold);
  EXPECT_TRUE(remesh.hexDual.positions.empty());
  // Squares on a torus whose flat metric is off by at most ±10% (major circle) and 5% (tube):
  // corners within a few degrees of 90°.
  const QualityReport metrics = measurePolygonQuality(quads, remesh.triangles);
  EXPECT_EQ(metrics.quads, 378);
  EXPECT_EQ(metrics.irregularInterior, 0);
  EXPECT_GT(metrics.angleMin, 80.0);
  EXPECT_LT(metrics.angleMax, 100.0);
}

void expectConeOfValence(int n) {
  const auto [mesh, param] = coneFan(n, 4, 4);
  ExtractOptions options;
  options.boundary = BoundaryMode::Lattice;
  const Remesh remesh = extractRemesh(mesh, param, options);
  EXPECT_EQ(remesh.report.inconsistentVertices, 0);
  // Each sector holds the squares (a, b) with a, b ≥ 0 and a + b ≤ 2 whole: 6.
  EXPECT_EQ(remesh.report.latticeSquares, 6 * n);
  const PolygonSoup& quads = remesh.quads;
  EXPECT_EQ(facesOfSize(quads, 4), 6 * n);
  EXPECT_EQ(quads.faceCount(), static_cast<std::size_t>(6 * n));
  const PolygonValences valences = polygonValences(quads);
  int cones = 0;
  for (std::size_t v = 0; v < quads.vertexCount(); ++v) {
    if (valences.onBoundary[v]) continue;
    if (valences.valence[v] == 4) continue;
    ++cones;
    EXPECT_EQ(valences.valence[v], n);
    EXPECT_LT(quads.positions[v].norm(), 1e-12) << "the cone is the fan's center";
  }
  EXPECT_EQ(cones, 1);
  EXPECT_TRUE(computeTopology(remesh.triangles).sameAs(computeTopology(mesh)));
}

TEST(ExtractQuads, PositiveConeHasValenceThreeAtItsSingularityOnly) { expectConeOfValence(3); }

TEST(ExtractQuads, NegativeConeHasValenceFiveAtItsSingularityOnly) { expectConeOfValence(5); }

/// An n × n grid of unit squares in the plane z = 0, as quads and as the triangle mesh behind them
/// (square i split into faces 2i and 2i + 1 along its diagonal (i, j)-(i+1, j+1)).
std::pair<PolygonSoup, TriMesh> squareGrid(int n) {
  PolygonSoup soup;
  TriMesh triangles;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      soup.positions.emplace_back(i, j, 0.0);
      triangles.add_vertex(OpenMesh::Vec3d(i, j, 0.0));
    }
  const auto at = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::array<int, 4> q{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
      soup.addFace(q);
      const auto v = [](int k) { return TriMesh::VertexHandle(k); };
      triangles.add_face(v(q[0]), v(q[1]), v(q[2]));
      triangles.add_face(v(q[0]), v(q[2]), v(q[3]));
    }
  return {std::move(soup), std::move(triangles)};
}

TEST(ExtractQuads, PolygonMetricsOfAUnitSquareGrid) {
  const int n = 4;
  const auto [grid, triangles] = squareGrid(n);
  const QualityReport report = measurePolygonQuality(grid, triangles, &triangles);
  EXPECT_EQ(report.quads, n * n);
  EXPECT_EQ(report.faces, n * n);
  EXPECT_DOUBLE_EQ(report.angleMin, 90.0);
  EXPECT_DOUBLE_EQ(report.angleMax, 90.0);
  EXPECT_NEAR(report.angleSd, 0.0, 1e-9);
  EXPECT_EQ(report.irregularInterior, 0);
  EXPECT_EQ(report.valenceInterior.at(4), (n - 1) * (n - 1));
  // Boundary: valence 3 along the sides, 2 at the four corners.
  EXPECT_EQ(report.valenceBoundary.at(3), 4 * (n - 1));
  EXPECT_EQ(report.irregularBoundary, 4);
  EXPECT_DOUBLE_EQ(report.edgeLengthMean, 1.0);
  EXPECT_NEAR(report.distance->hausdorffPct, 0.0, 1e-9);
}

TEST(QuadMesh, TrianglePairsOfAGridBecomeItsSquaresAgain) {
  const TriMesh triangles = squareGrid(3).second;
  std::vector<int> partner(triangles.n_faces(), extract_detail::kUnpaired);
  // The first square's triangles belong to a component copied unchanged.
  partner[0] = partner[1] = extract_detail::kKeptAsIs;
  EXPECT_EQ(extract_detail::pairTriangles(triangles, partner), 8);
  const PolygonSoup soup = extract_detail::pairSquares(triangles, partner);
  EXPECT_EQ(soup.faceCount(), 10u);
  EXPECT_EQ(facesOfSize(soup, 4), 8);
  EXPECT_EQ(facesOfSize(soup, 3), 2);
  const QualityReport report = measurePolygonQuality(soup, triangles);
  EXPECT_NEAR(report.angleMax, 90.0, 1e-9);
}

TEST(QuadMesh, TrianglePairWhoseQuadWouldBeFarFromSquareStaysTwoTriangles) {
  // A kite: the quad (0, 1, 2, 3) has corners of 30° and 150°.
  TriMesh kite;
  for (const OpenMesh::Vec3d p : {OpenMesh::Vec3d(0, 0, 0), OpenMesh::Vec3d(1, -0.27, 0),
                                  OpenMesh::Vec3d(3.7, 0, 0), OpenMesh::Vec3d(1, 0.27, 0)})
    kite.add_vertex(p);
  const auto v = [](int k) { return TriMesh::VertexHandle(k); };
  kite.add_face(v(0), v(1), v(2));
  kite.add_face(v(0), v(2), v(3));
  std::vector<int> partner(2, extract_detail::kUnpaired);
  EXPECT_EQ(extract_detail::pairTriangles(kite, partner), 0);
  EXPECT_EQ(facesOfSize(extract_detail::pairSquares(kite, partner), 3), 2);
}

TEST(QuadMesh, FitMovesThatBendAQuadCornerPastTheBoundAreTakenBack) {
  auto [quads, triangles] = squareGrid(2);
  std::vector<Eigen::Vector3d> unfitted = quads.positions;
  // The centre vertex (1, 1) moved by the fit to (1.8, 1.8): the squares beside it open their
  // corners at (2, 1) and (1, 2) to 166°.
  const int centre = 4;
  const Eigen::Vector3d moved(1.8, 1.8, 0.0);
  quads.positions[centre] = moved;
  triangles.set_point(TriMesh::VertexHandle(centre), toOpenMesh(moved));
  EXPECT_GT(measurePolygonQuality(quads, triangles).angleMax, 150.0);
  EXPECT_EQ(extract_detail::restoreQuadCorners(quads, triangles, unfitted), 1);
  const QualityReport after = measurePolygonQuality(quads, triangles);
  EXPECT_LE(after.angleMax, 135.0);
  EXPECT_GE(after.angleMin, 45.0);
  EXPECT_EQ(toEigen(triangles.point(TriMesh::VertexHandle(centre))), quads.positions[centre]);
  // A grid within the bound is left alone.
  EXPECT_EQ(extract_detail::restoreQuadCorners(quads, triangles, unfitted), 0);
}

/// The fit's options as extraction sets them (snapping at 0.35 edge lengths, the default crease
/// angle).
extract_detail::SurfaceFitOptions fitOptions() {
  extract_detail::SurfaceFitOptions options;
  options.featureSnapDistance = 0.35;
  options.creaseAngle = kDefaultFeatureAngle;
  return options;
}

/// The triangles of an n × n square grid with the interior vertices jittered in the plane by up
/// to 0.2 edge lengths (a fixed pattern).
TriMesh jitteredSquareGrid(int n) {
  TriMesh triangles = squareGrid(n).second;
  int k = 0;
  for (const auto v : triangles.vertices()) {
    if (triangles.is_boundary(v)) continue;
    ++k;
    triangles.set_point(v, triangles.point(v) + OpenMesh::Vec3d(0.2 * std::sin(1.7 * k),
                                                                0.2 * std::cos(2.3 * k), 0.0));
  }
  return triangles;
}

/// squareGrid splits square i into faces 2i and 2i + 1: each one's partner.
std::vector<int> gridPartners(const TriMesh& triangles) {
  std::vector<int> partner(triangles.n_faces());
  for (std::size_t f = 0; f < partner.size(); ++f) partner[f] = static_cast<int>(f ^ 1);
  return partner;
}

// Step 8 for quads: in a 4 × 4 grid whose bottom boundary vertex (1, 0) sits at (1.9, 0), the
// unpaired triangles of the first two squares around it are slivers; the vertex is collapsed,
// which renumbers the faces, and every other square's two triangles are still partners.
TEST(QuadMesh, SliverRepairsBesideSquaresKeepEverySquarePaired) {
  TriMesh triangles = squareGrid(4).second;
  triangles.set_point(TriMesh::VertexHandle(1), OpenMesh::Vec3d(1.9, 0.0, 0.0));
  std::vector<int> partner = gridPartners(triangles);
  for (int f = 0; f < 4; ++f) partner[f] = extract_detail::kUnpaired;
  const auto done =
      extract_detail::repairSliversBesideSquares(triangles, partner, 20.0, 120.0, 30.0);
  EXPECT_EQ(done.collapses, 1);
  ASSERT_EQ(partner.size(), triangles.n_faces());
  int paired = 0;
  for (const auto f : triangles.faces()) {
    const int other = partner[f.idx()];
    if (other < 0) continue;
    ++paired;
    ASSERT_EQ(partner[other], f.idx());
    // The pair's corners span one unit square of the grid.
    std::set<std::pair<double, double>> corners;
    for (const auto face : {f, OpenMesh::make_smart(TriMesh::FaceHandle(other), triangles)})
      for (const auto v : face.vertices())
        corners.emplace(triangles.point(v)[0], triangles.point(v)[1]);
    ASSERT_EQ(corners.size(), 4u) << "faces " << f.idx() << " and " << other;
    const auto [low, high] = std::minmax_element(corners.begin(), corners.end());
    EXPECT_EQ(high->first - low->first, 1.0);
    EXPECT_EQ(high->second - low->second, 1.0);
  }
  EXPECT_EQ(paired, 2 * 14);
}

TEST(QuadMesh, FitRelaxesTheCornersOfAJitteredSquareGridTowardsRightAngles) {
  const int n = 10;
  const TriMesh inputTriangles = squareGrid(n).second;
  const TriMesh triangles = jitteredSquareGrid(n);
  const std::vector<int> partner = gridPartners(triangles);
  const auto quadSd = [&](const TriMesh& mesh) {
    return measurePolygonQuality(extract_detail::pairSquares(mesh, partner), mesh).angleSd;
  };
  const double before = quadSd(triangles);
  ASSERT_GT(before, 8.0);
  TriMesh asQuads = triangles, asTriangles = triangles;
  const ClosestPointQuery onInput(inputTriangles);
  const auto counts =
      extract_detail::fitRemeshToSurface(inputTriangles, onInput, asQuads, fitOptions(), partner);
  EXPECT_GT(counts.relaxed, 0);
  EXPECT_EQ(counts.smoothed, 0) << "smoothing aims at 60° triangles";
  EXPECT_LT(quadSd(asQuads), 0.5 * before);
  // Without the squares, relaxation aims at 60° triangles, which bends the squares further.
  extract_detail::fitRemeshToSurface(inputTriangles, onInput, asTriangles, fitOptions());
  EXPECT_GT(quadSd(asTriangles), quadSd(asQuads) + 5.0);
}

TEST(QuadMesh, RelaxationOfQuadsGivesTheSameMeshForAnyThreadCount) {
  // Large enough for each colour class to be split between the threads; a class must not hold
  // two corners of one quad, whose far corner is no neighbour in the triangles.
  const int n = 40;
  const TriMesh input = squareGrid(n).second;
  const ClosestPointQuery onInput(input);
  TriMesh one = jitteredSquareGrid(n), two = one;
  const std::vector<int> partner = gridPartners(one);
  for (auto* mesh : {&one, &two}) {
    extract_detail::SurfaceFitOptions options;
    options.creaseAngle = kDefaultFeatureAngle;
    options.balanceDeviation = false;
    options.threads = mesh == &one ? 1 : 2;
    extract_detail::fitRemeshToSurface(input, onInput, *mesh, options, partner);
  }
  for (const auto v : one.vertices()) ASSERT_EQ(one.point(v), two.point(v)) << "vertex " << v.idx();
}

TEST(QuadMesh, FitSnapsQuadsToARidgeWithTheirCornersWithinTheWindow) {
  // A roof z = −2|x − 2.5| (slopes ±2: its faces meet at 53°) sampled finely, and a coarse grid
  // of unit squares on it whose columns miss the ridge by half a square. The fit judges the
  // quads' corners (within 45° of 90°), not their triangles' angles (25-115° each, which no
  // move onto the ridge keeps): vertices snap or balance, and the corners stay in the window.
  TriMesh input;
  const int fine = 100;
  const auto roof = [](double x, double y) {
    return OpenMesh::Vec3d(x, y, -2.0 * std::abs(x - 2.5));
  };
  for (int j = 0; j <= fine; ++j)
    for (int i = 0; i <= fine; ++i) input.add_vertex(roof(5.0 * i / fine, 5.0 * j / fine));
  const auto at = [&](int i, int j) { return TriMesh::VertexHandle(j * (fine + 1) + i); };
  for (int j = 0; j < fine; ++j)
    for (int i = 0; i < fine; ++i) {
      input.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      input.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  TriMesh remesh = squareGrid(5).second;
  for (const auto v : remesh.vertices()) {
    const auto p = remesh.point(v);
    remesh.set_point(v, roof(p[0], p[1]));
  }
  const std::vector<int> partner = gridPartners(remesh);
  const auto counts = extract_detail::fitRemeshToSurface(input, ClosestPointQuery(input), remesh,
                                                         fitOptions(), partner);
  EXPECT_GT(counts.snapped + counts.balanced, 0);
  const QualityReport report =
      measurePolygonQuality(extract_detail::pairSquares(remesh, partner), remesh);
  EXPECT_GE(report.angleMin, 45.0);
  EXPECT_LE(report.angleMax, 135.0);
}

}  // namespace
}  // namespace hexcover
