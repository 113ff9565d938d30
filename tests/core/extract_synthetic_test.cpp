// Extraction on parameterizations built by hand, where the right answer is known: planar patches
// (lattice points strictly inside triangles, on edges and on vertices), a flat torus with integer
// translations across its two cuts, and fans of 5 and 7 triangles whose 60° transition makes a
// singularity of index +1/6 or -1/6.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "core/extract/extract.h"
#include "core/mesh/primitives.h"
#include "core/mesh/topology.h"
#include "tests/common/lattice_parameterizations.h"
#include "tests/common/mesh_measures.h"

namespace hexcover {
namespace {

using test::coneFan;
using test::fillTransitions;
using test::flatTorusParameterization;

constexpr double kSqrt3 = 1.7320508075688772;

/// Lattice coordinates (a, b) of a point of the plane: x = a + b/2, y = b·√3/2.
Eigen::Vector2d latticeFromPlane(double x, double y) {
  const double b = y / (kSqrt3 / 2);
  return {x - b / 2, b};
}

/// A parameterization without cuts: lattice coordinates as a function of the vertex position.
Parameterization planarParameterization(const TriMesh& mesh,
                                        const std::function<Eigen::Vector2d(Eigen::Vector3d)>& map) {
  Parameterization param;
  param.edgeLength = 1.0;
  param.cornerCoords.assign(mesh.n_halfedges(), Eigen::Vector2d::Zero());
  for (const auto h : mesh.halfedges())
    if (!mesh.is_boundary(h)) param.cornerCoords[h.idx()] = map(toEigen(mesh.point(mesh.to_vertex_handle(h))));
  fillTransitions(mesh, param, [](auto) { return 0; });
  return param;
}

/// Interior vertices whose valence is not 6.
std::vector<int> irregularInteriorVertices(const TriMesh& mesh) {
  std::vector<int> irregular;
  for (const auto v : mesh.vertices())
    if (!mesh.is_boundary(v) && mesh.valence(v) != 6) irregular.push_back(v.idx());
  return irregular;
}

/// Pairs of vertices closer than tol.
int duplicateVertices(const TriMesh& mesh, double tol) {
  std::map<std::array<long long, 3>, int> cells;
  int duplicates = 0;
  for (const auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    std::array<long long, 3> key;
    for (int i = 0; i < 3; ++i) key[i] = std::llround(p[i] / tol);
    duplicates += cells[key]++ > 0;
  }
  return duplicates;
}

/// Faces with an angle below minDeg (a degenerate face has one near 0).
std::pair<double, double> angleRange(const TriMesh& mesh) {
  double lo = 180.0, hi = 0.0;
  for (const auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int k = 0;
    for (const auto v : mesh.fv_range(f)) p[k++] = toEigen(mesh.point(v));
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d a = p[(i + 1) % 3] - p[i], b = p[(i + 2) % 3] - p[i];
      const double angle = std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
      lo = std::min(lo, angle), hi = std::max(hi, angle);
    }
  }
  return {lo, hi};
}

/// Every face normal of a planar mesh points to +z (consistent orientation with the input).
bool allFacesUp(const TriMesh& mesh) {
  for (const auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int k = 0;
    for (const auto v : mesh.fv_range(f)) p[k++] = toEigen(mesh.point(v));
    if ((p[1] - p[0]).cross(p[2] - p[0]).z() <= 0.0) return false;
  }
  return true;
}

/// Distance from p to the boundary polyline of `mesh`.
double distanceToBoundary(const TriMesh& mesh, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto e : mesh.edges()) {
    if (!mesh.is_boundary(e)) continue;
    const auto h = mesh.halfedge_handle(e, 0);
    const Eigen::Vector3d a = toEigen(mesh.point(mesh.from_vertex_handle(h)));
    const Eigen::Vector3d b = toEigen(mesh.point(mesh.to_vertex_handle(h)));
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * (b - a) - p).norm());
  }
  return best;
}

/// Number of integer lattice points whose plane position lies in the closed planar mesh, for a
/// parameterization z = map(x): counted by inverting the map at each candidate.
long long bruteForceLatticePoints(const TriMesh& mesh,
                                  const std::function<Eigen::Vector2d(Eigen::Vector3d)>& map) {
  // Bounding box of the mesh in lattice coordinates.
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto v : mesh.vertices()) {
    const Eigen::Vector2d z = map(toEigen(mesh.point(v)));
    lo = lo.cwiseMin(z), hi = hi.cwiseMax(z);
  }
  long long count = 0;
  for (long long a = std::floor(lo.x()) - 1; a <= std::ceil(hi.x()) + 1; ++a)
    for (long long b = std::floor(lo.y()) - 1; b <= std::ceil(hi.y()) + 1; ++b) {
      const Eigen::Vector2d z(a, b);
      bool inside = false;
      for (const auto f : mesh.faces()) {
        std::array<Eigen::Vector2d, 3> q;
        int k = 0;
        for (const auto v : mesh.fv_range(f)) q[k++] = map(toEigen(mesh.point(v)));
        const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& w) {
          return u.x() * w.y() - u.y() * w.x();
        };
        const double area = cross(q[1] - q[0], q[2] - q[0]);
        const double tol = 1e-9 * std::abs(area);
        if (cross(q[1] - q[0], z - q[0]) >= -tol && cross(q[2] - q[1], z - q[1]) >= -tol &&
            cross(q[0] - q[2], z - q[2]) >= -tol) {
          inside = true;
          break;
        }
      }
      count += inside;
    }
  return count;
}

ExtractOptions latticeBoundary() {
  ExtractOptions options;
  options.boundary = BoundaryMode::Lattice;
  return options;
}

TEST(ExtractSynthetic, IdentityParameterizationOfAnEquilateralGridGivesTheGridBack) {
  const TriMesh grid = makeEquilateralGrid(9, 8, 1.0);
  const auto param = planarParameterization(grid, [](Eigen::Vector3d p) { return latticeFromPlane(p.x(), p.y()); });
  const Remesh remesh = extractRemesh(grid, param, latticeBoundary());
  EXPECT_EQ(remesh.report.latticePoints, static_cast<long long>(grid.n_vertices()));
  EXPECT_EQ(remesh.triangles.n_vertices(), grid.n_vertices());
  EXPECT_EQ(remesh.triangles.n_faces(), grid.n_faces());
  EXPECT_EQ(remesh.report.transitionsCorrected, 0);
  const auto [lo, hi] = angleRange(remesh.triangles);
  EXPECT_NEAR(lo, 60.0, 1e-6);
  EXPECT_NEAR(hi, 60.0, 1e-6);
  EXPECT_TRUE(irregularInteriorVertices(remesh.triangles).empty());
}

TEST(ExtractSynthetic, ScaledGridEmitsPointsOnVerticesEdgesAndInsideExactlyOnce) {
  // Each input triangle becomes a lattice triangle of side 3: 3 corner points, 2 points inside
  // each edge and 1 strictly inside; 9 unit triangles.
  const TriMesh grid = makeEquilateralGrid(7, 6, 1.0);
  const auto map = [](Eigen::Vector3d p) { return Eigen::Vector2d(3.0 * latticeFromPlane(p.x(), p.y())); };
  const Remesh remesh = extractRemesh(grid, planarParameterization(grid, map), latticeBoundary());
  const long long expected = grid.n_vertices() + 2 * grid.n_edges() + grid.n_faces();
  EXPECT_EQ(remesh.report.latticePoints, expected);
  EXPECT_EQ(bruteForceLatticePoints(grid, map), expected);
  EXPECT_EQ(static_cast<long long>(remesh.triangles.n_vertices()), expected);
  EXPECT_EQ(remesh.triangles.n_faces(), 9 * grid.n_faces());
  EXPECT_EQ(duplicateVertices(remesh.triangles, 1e-6), 0);
  EXPECT_TRUE(allFacesUp(remesh.triangles));
  const auto [lo, hi] = angleRange(remesh.triangles);
  EXPECT_NEAR(lo, 60.0, 1e-6);
  EXPECT_NEAR(hi, 60.0, 1e-6);
  EXPECT_TRUE(irregularInteriorVertices(remesh.triangles).empty());
  const MeshTopology topology = computeTopology(remesh.triangles);
  EXPECT_TRUE(topology.sameAs(computeTopology(grid)));
}

TEST(ExtractSynthetic, RotatedScaledLatticeIsEmittedOnceAndRegularInside) {
  const TriMesh grid = makeEquilateralGrid(12, 11, 1.0);
  const double angle = 0.31, scale = 1.0 / 0.37;
  const auto map = [&](Eigen::Vector3d p) {
    const double x = scale * (std::cos(angle) * p.x() - std::sin(angle) * p.y()) + 0.123;
    const double y = scale * (std::sin(angle) * p.x() + std::cos(angle) * p.y()) + 0.456;
    return latticeFromPlane(x, y);
  };
  const Remesh remesh = extractRemesh(grid, planarParameterization(grid, map), latticeBoundary());
  EXPECT_EQ(remesh.report.latticePoints, bruteForceLatticePoints(grid, map));
  EXPECT_EQ(remesh.report.uncoveredTriangles, 0);
  EXPECT_EQ(remesh.report.overlappingTriangles, 0);
  EXPECT_EQ(remesh.report.nonManifoldFacesDropped, 0);
  EXPECT_EQ(duplicateVertices(remesh.triangles, 1e-6), 0);
  EXPECT_TRUE(allFacesUp(remesh.triangles));
  // Unit lattice triangles map to equilateral triangles of side 0.37 (up to the fixed-point
  // grid of extraction, 2^-24 lattice units).
  const auto [lo, hi] = angleRange(remesh.triangles);
  EXPECT_NEAR(lo, 60.0, 1e-4);
  EXPECT_NEAR(hi, 60.0, 1e-4);
  for (const auto e : remesh.triangles.edges())
    ASSERT_NEAR(remesh.triangles.calc_edge_length(e), 0.37, 1e-7);
  EXPECT_TRUE(irregularInteriorVertices(remesh.triangles).empty());
}

/// A flat parallelogram patch under a lattice turned by 0.31 rad against its sides, without
/// singularities.
Remesh remeshOfTurnedPatch(const TriMesh& grid, const ExtractOptions& options = {}) {
  const double angle = 0.31, scale = 1.0 / 0.37;
  const auto map = [&](Eigen::Vector3d p) {
    const double x = scale * (std::cos(angle) * p.x() - std::sin(angle) * p.y()) + 0.123;
    const double y = scale * (std::sin(angle) * p.x() + std::cos(angle) * p.y()) + 0.456;
    return latticeFromPlane(x, y);
  };
  return extractRemesh(grid, planarParameterization(grid, map), options);
}

TEST(ExtractSynthetic, FollowedBoundaryLiesOnTheInputBoundaryAndKeepsTopology) {
  const TriMesh grid = makeEquilateralGrid(12, 11, 1.0);
  const Remesh remesh = remeshOfTurnedPatch(grid);
  const TriMesh& out = remesh.triangles;
  EXPECT_TRUE(computeTopology(out).sameAs(computeTopology(grid)));
  EXPECT_EQ(remesh.report.nonManifoldFacesDropped, 0);
  EXPECT_EQ(remesh.report.unmatchedBoundaryLoops, 0);
  EXPECT_EQ(duplicateVertices(out, 1e-6), 0);
  EXPECT_TRUE(allFacesUp(out));
  for (const auto v : out.vertices())
    if (out.is_boundary(v)) {
      ASSERT_LT(distanceToBoundary(grid, toEigen(out.point(v))), 1e-9);
    }
  // The four corners of the patch (sharp boundary corners) are output vertices.
  for (const auto v : grid.vertices()) {
    if (grid.valence(v) > 3) continue;  // corners of the parallelogram have valence 2 or 3
    EXPECT_LT(test::distanceToNearestVertex(out, toEigen(grid.point(v))), 1e-9)
        << "corner " << v.idx();
  }
  const auto [lo, hi] = angleRange(out);
  EXPECT_GT(lo, 15.0);
  EXPECT_LT(hi, 140.0);
}

TEST(ExtractSynthetic, BoundaryStripLeavesEveryInteriorVertexRegular) {
  // Without singularities every interior vertex of the remesh, also those next to the boundary,
  // has valence 6 (the strip gives each front vertex 6 − a samples; the old zip left 35). Step 8
  // is off: it trades valences for angles at the parallelogram's 60° corners (next test).
  ExtractOptions options;
  options.sliverAngle = 0.0;
  const Remesh remesh = remeshOfTurnedPatch(makeEquilateralGrid(12, 11, 1.0), options);
  const TriMesh& out = remesh.triangles;
  int interior = 0;
  for (const auto v : out.vertices()) interior += out.is_boundary(v) ? 0 : 1;
  EXPECT_GT(interior, 100);
  EXPECT_TRUE(irregularInteriorVertices(out).empty());
}

// Step 8 at the parallelogram's 60° corners: boundary samples collapsed and edges flipped, each
// at the cost of at most two interior valences.
TEST(ExtractSynthetic, BoundarySliversAreCollapsedOrFlippedAtTheCostOfTwoValencesEach) {
  const TriMesh grid = makeEquilateralGrid(12, 11, 1.0);
  ExtractOptions off;
  off.sliverAngle = 0.0;
  const Remesh without = remeshOfTurnedPatch(grid, off);
  const Remesh with = remeshOfTurnedPatch(grid);
  const double before = angleRange(without.triangles).first;
  ASSERT_LT(before, 20.0) << "the patch's corners leave slivers in the strip";
  const long long changes = with.report.boundarySliverCollapses + with.report.boundarySliverFlips;
  EXPECT_GT(changes, 0);
  EXPECT_GT(angleRange(with.triangles).first, before);
  EXPECT_LE(static_cast<long long>(irregularInteriorVertices(with.triangles).size()), 2 * changes);
  EXPECT_TRUE(computeTopology(with.triangles).sameAs(computeTopology(grid)));
  EXPECT_TRUE(allFacesUp(with.triangles));
}

TEST(ExtractSynthetic, FlatTorusGivesAClosedRegularGenusOneMeshWithOneVertexPerLatticePoint) {
  const int around = 50, tube = 8;
  const TriMesh torus = makeTorus(10.0, 1.0, around, tube);
  // P1 = (63, 0) along the major circle (length 63 ≈ 2π·10), P2 = (-3, 7) around the tube
  // (plane vector (0.5, 6.06), length ≈ 2π·1): the period lattice has 63·7 = 441 points.
  const auto param = flatTorusParameterization(torus, around, tube, {63, 0}, {-3, 7});
  const Remesh remesh = extractRemesh(torus, param);
  const TriMesh& out = remesh.triangles;
  EXPECT_EQ(remesh.report.transitionsCorrected, 0);
  EXPECT_EQ(remesh.report.inconsistentVertices, 0);
  EXPECT_EQ(remesh.report.latticePoints, 441);
  EXPECT_EQ(out.n_vertices(), 441u);
  EXPECT_EQ(out.n_faces(), 882u);
  EXPECT_EQ(remesh.report.holesFilled, 0);
  const MeshTopology topology = computeTopology(out);
  EXPECT_EQ(topology.components, 1);
  EXPECT_EQ(topology.boundaryLoops, 0);
  EXPECT_EQ(topology.genus(), 1);
  EXPECT_TRUE(topology.manifold);
  EXPECT_TRUE(irregularInteriorVertices(out).empty());
  EXPECT_EQ(duplicateVertices(out, 1e-6), 0);
  // The flat metric differs from the torus's by at most ±10% along the major circle
  // ((R ± r)/R) and ~4% around the tube, so angles stay within about ±8° of 60°.
  const auto [lo, hi] = angleRange(out);
  EXPECT_GT(lo, 50.0);
  EXPECT_LT(hi, 72.0);
  // Outward orientation is kept: normals point away from the tube's core circle.
  for (const auto f : out.faces()) {
    const Eigen::Vector3d c = toEigen(out.calc_face_centroid(f));
    const Eigen::Vector3d core = 10.0 * Eigen::Vector3d(c.x(), c.y(), 0).normalized();
    ASSERT_GT(toEigen(out.calc_face_normal(f)).dot(c - core), 0.0);
  }
}

TEST(ExtractSynthetic, PositiveConeHasValenceFiveAtItsSingularityOnly) {
  const auto [mesh, param] = coneFan(5, 4);
  const Remesh remesh = extractRemesh(mesh, param, latticeBoundary());
  const TriMesh& out = remesh.triangles;
  // 1 center + 5 spokes × 4 + 5 outer edges × 3 + 5 faces × 3 interior points.
  EXPECT_EQ(remesh.report.latticePoints, 51);
  EXPECT_EQ(out.n_vertices(), 51u);
  EXPECT_EQ(out.n_faces(), 80u);
  EXPECT_EQ(remesh.report.inconsistentVertices, 0);
  const auto irregular = irregularInteriorVertices(out);
  ASSERT_EQ(irregular.size(), 1u);
  EXPECT_EQ(out.valence(TriMesh::VertexHandle(irregular[0])), 5u);
  EXPECT_LT(out.point(TriMesh::VertexHandle(irregular[0])).norm(), 1e-12);
  EXPECT_TRUE(computeTopology(out).sameAs(computeTopology(mesh)));
  EXPECT_EQ(duplicateVertices(out, 1e-6), 0);
  EXPECT_TRUE(allFacesUp(out));
}

TEST(ExtractSynthetic, NegativeConeHasValenceSevenAtItsSingularityOnly) {
  const auto [mesh, param] = coneFan(7, 4);
  const Remesh remesh = extractRemesh(mesh, param, latticeBoundary());
  const TriMesh& out = remesh.triangles;
  EXPECT_EQ(out.n_vertices(), 1u + 7 * 4 + 7 * 3 + 7 * 3);
  EXPECT_EQ(out.n_faces(), 7u * 16);
  const auto irregular = irregularInteriorVertices(out);
  ASSERT_EQ(irregular.size(), 1u);
  EXPECT_EQ(out.valence(TriMesh::VertexHandle(irregular[0])), 7u);
  EXPECT_TRUE(computeTopology(out).sameAs(computeTopology(mesh)));
  EXPECT_TRUE(allFacesUp(out));
}

TEST(ExtractSynthetic, ConeSingularityIsSnappedToItsFixedPointWhenTheInputIsOff) {
  auto [mesh, param] = coneFan(5, 4);
  // Move the center's coordinates in every face by the same small offset: the transitions do not
  // change, and the center's holonomy still has the lattice point 0 as its fixed point.
  const auto center = TriMesh::VertexHandle(0);
  for (const auto h : mesh.vih_range(center)) param.cornerCoords[h.idx()] += Eigen::Vector2d(0.2, -0.1);
  const Remesh remesh = extractRemesh(mesh, param, latticeBoundary());
  const auto irregular = irregularInteriorVertices(remesh.triangles);
  ASSERT_EQ(irregular.size(), 1u);
  EXPECT_LT(remesh.triangles.point(TriMesh::VertexHandle(irregular[0])).norm(), 1e-12);
  EXPECT_EQ(remesh.triangles.n_vertices(), 51u);
}

TEST(ExtractSynthetic, FlippedParameterTriangleLeavesAFilledManifoldPatch) {
  const TriMesh grid = makeEquilateralGrid(9, 8, 1.0);
  auto param = planarParameterization(grid, [](Eigen::Vector3d p) {
    return Eigen::Vector2d(2.0 * latticeFromPlane(p.x(), p.y()));
  });
  // Drag one interior vertex across its neighbours: its fan folds over.
  const TriMesh::VertexHandle v(4 * 9 + 4);
  for (const auto h : grid.vih_range(v)) param.cornerCoords[h.idx()] += Eigen::Vector2d(2.6, 0.3);
  const Remesh remesh = extractRemesh(grid, param, latticeBoundary());
  EXPECT_GT(remesh.report.flippedParamTriangles, 0);
  EXPECT_GT(remesh.report.uncoveredTriangles + remesh.report.overlappingTriangles, 0);
  EXPECT_EQ(remesh.report.nonManifoldFacesDropped, 0);
  const MeshTopology topology = computeTopology(remesh.triangles);
  EXPECT_TRUE(topology.manifold);
  EXPECT_TRUE(topology.sameAs(computeTopology(grid)));
}

TEST(ExtractSynthetic, EachComponentIsRemeshedAndOneTooSmallForTheLatticeIsKept) {
  // Two patches side by side (one mesh), and a third so small that no lattice triangle fits.
  TriMesh mesh;
  const auto addPatch = [&](double dx, double size) {
    const TriMesh g = makeEquilateralGrid(6, 5, size);
    std::vector<TriMesh::VertexHandle> handles;
    for (const auto v : g.vertices()) handles.push_back(mesh.add_vertex(g.point(v) + TriMesh::Point(dx, 0, 0)));
    for (const auto f : g.faces()) {
      std::vector<TriMesh::VertexHandle> face;
      for (const auto v : g.fv_range(f)) face.push_back(handles[v.idx()]);
      mesh.add_face(face);
    }
  };
  addPatch(0.0, 1.0);
  addPatch(20.0, 1.0);
  addPatch(40.0, 0.01);
  const auto param = planarParameterization(mesh, [](Eigen::Vector3d p) {
    return Eigen::Vector2d(1.3 * latticeFromPlane(p.x(), p.y()) + Eigen::Vector2d(0.1, 0.2));
  });
  const Remesh remesh = extractRemesh(mesh, param);
  EXPECT_EQ(remesh.report.componentsKept, 1);
  const MeshTopology topology = computeTopology(remesh.triangles);
  EXPECT_TRUE(topology.sameAs(computeTopology(mesh)));
  EXPECT_EQ(topology.components, 3);

  // With the input as given (here: the small patch lifted by 1 in z), the kept component is
  // copied from it, and no other vertex is.
  TriMesh given = mesh;
  for (const auto v : given.vertices())
    if (given.point(v)[0] > 30.0) given.point(v)[2] += 1.0;
  const Remesh fromGiven = extractRemesh(mesh, param, {}, {}, &given);
  EXPECT_EQ(fromGiven.report.componentsKept, 1);
  int lifted = 0;
  for (const auto v : fromGiven.triangles.vertices()) {
    const auto& p = fromGiven.triangles.point(v);
    EXPECT_EQ(p[0] > 30.0, p[2] == 1.0) << p;
    lifted += p[2] == 1.0 ? 1 : 0;
  }
  EXPECT_EQ(lifted, 30);  // the 6 × 5 vertices of the small patch

  TriMesh larger = mesh;
  larger.add_vertex({0, 0, 0});
  EXPECT_THROW(extractRemesh(mesh, param, {}, {}, &larger), Error);
}

TEST(ExtractSynthetic, HexagonalDualHasOneHexagonPerInteriorVertexOfARegularTorus) {
  const int around = 50, tube = 8;
  const TriMesh torus = makeTorus(10.0, 1.0, around, tube);
  const Remesh remesh =
      extractRemesh(torus, flatTorusParameterization(torus, around, tube, {63, 0}, {-3, 7}));
  const PolygonSoup& dual = remesh.hexDual;
  EXPECT_EQ(dual.faceCount(), remesh.triangles.n_vertices());
  EXPECT_EQ(dual.vertexCount(), remesh.triangles.n_faces());
  for (std::size_t f = 0; f < dual.faceCount(); ++f) ASSERT_EQ(dual.faceSize(f), 6u);
  // Every dual vertex (a triangle centroid) is a corner of exactly three hexagons.
  std::vector<int> uses(dual.vertexCount(), 0);
  for (const auto v : dual.cornerVertices) ++uses[v];
  EXPECT_TRUE(std::all_of(uses.begin(), uses.end(), [](int u) { return u == 3; }));
}

TEST(ExtractSynthetic, HexagonalDualHasAPentagonAtAPositiveCone) {
  const auto [mesh, param] = coneFan(5, 4);
  const Remesh remesh = extractRemesh(mesh, param, latticeBoundary());
  std::map<std::size_t, int> sizes;
  for (const auto v : remesh.triangles.vertices()) {
    if (remesh.triangles.is_boundary(v)) continue;
    ++sizes[remesh.hexDual.faceSize(v.idx())];
  }
  EXPECT_EQ(sizes[5], 1);
  EXPECT_EQ(sizes.size(), 2u);  // pentagon and hexagons only
}

TEST(ExtractSynthetic, RejectsAParameterizationOfAnotherMesh) {
  const TriMesh grid = makeEquilateralGrid(5, 5, 1.0);
  Parameterization param;
  EXPECT_THROW(extractRemesh(grid, param), Error);
}

}  // namespace
}  // namespace hexcover
