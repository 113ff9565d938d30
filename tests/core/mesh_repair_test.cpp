// Validation (core/mesh/validate.h) and repair (core/mesh/repair.h) on generated meshes with
// defects put in on purpose, so that every expected count is known.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "core/common/error.h"
#include "core/mesh/primitives.h"
#include "core/mesh/repair.h"
#include "core/mesh/validate.h"
#include "tests/common/mesh_expectations.h"
#include "tests/common/mesh_measures.h"

namespace hexcover {
namespace {

template <typename F>
std::string errorMessage(F run, ErrorCode code) {
  try {
    run();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(errorCodeName(e.code())), errorCodeName(code)) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected an Error(" << errorCodeName(code) << ")";
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Every triangle kept or counted: input triangles = result faces + dropped faces.
void expectFacesAccountedFor(const MeshReport& report) {
  EXPECT_EQ(report.input.triangles, report.result.faces + report.repairs.droppedFaces);
  EXPECT_EQ(report.repairs.droppedFaces, report.repairs.droppedDegenerateFaces +
                                             report.repairs.droppedDuplicateFaces +
                                             report.repairs.facesRefusedByMesh);
}

using test::expectManifoldAndOriented;

// Two tetrahedra (outward) that share vertex 0: a non-manifold vertex.
PolygonSoup twoTetrahedraSharingAVertex() {
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  for (const auto& f : std::vector<std::array<int, 3>>{
           {0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}})
    soup.addFace(f);
  return soup;
}

// A strip of `n` quads whose ends are glued with a half twist.
PolygonSoup moebiusStrip(int n) {
  PolygonSoup soup;
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * M_PI * i / n;
    for (const double s : {-0.3, 0.3}) {
      const double r = 1.0 + s * std::cos(t / 2);
      soup.positions.emplace_back(r * std::cos(t), r * std::sin(t), s * std::sin(t / 2));
    }
  }
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i, b = 2 * i + 1;
    const int c = i + 1 < n ? 2 * i + 3 : 0, d = i + 1 < n ? 2 * i + 2 : 1;  // twisted at the seam
    soup.addFace(std::array<int, 4>{a, d, c, b});
  }
  return soup;
}

TEST(MeshValidation, CleanGeneratedMeshesHaveTheirKnownTopology) {
  struct Case {
    const char* name;
    TriMesh mesh;
    long long chi;
    std::size_t loops;
    int genus;
  };
  const Case cases[] = {{"icosphere", makeIcosphere(3), 2, 0, 0},
                        {"torus", makeTorus(3, 1, 24, 12), 0, 0, 1},
                        {"tube", makeTube(1, 3, 20, 8), 0, 2, 0},
                        {"grid", makeEquilateralGrid(10, 8), 1, 1, 0},
                        {"Schwarz P cell", makeSchwarzPCell(20), -4, 6, 0}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const MeshStatistics s = validateMesh(toPolygonSoup(c.mesh)).input;
    EXPECT_EQ(s.vertices, c.mesh.n_vertices());
    EXPECT_EQ(s.faces, c.mesh.n_faces());
    EXPECT_EQ(s.components, 1u);
    EXPECT_EQ(s.eulerCharacteristic, c.chi);
    EXPECT_EQ(s.boundaryLoops, c.loops);
    ASSERT_EQ(s.componentTopology.size(), 1u);
    EXPECT_EQ(s.componentTopology[0].genus, c.genus);
    EXPECT_TRUE(s.componentTopology[0].manifold);
    expectManifoldAndOriented(s);
  }
}

// The marching tetrahedra orient every cut by the grid's integer determinants: each triangle
// faces towards positive cos x + cos y + cos z, i.e. along its gradient (−sin x, −sin y, −sin z),
// and none is degenerate (n = 47, as the remesh tests use it).
TEST(MeshValidation, SchwarzPCellFacesAlongTheGradient) {
  const TriMesh cell = makeSchwarzPCell(47);
  for (const auto f : cell.faces()) {
    const auto h = f.halfedge();
    const TriMesh::Point a = cell.point(h.from()), b = cell.point(h.to()),
                         c = cell.point(h.next().to());
    const TriMesh::Point centre = (a + b + c) / 3.0;
    const TriMesh::Point gradient(-std::sin(centre[0]), -std::sin(centre[1]), -std::sin(centre[2]));
    EXPECT_GT(((b - a) % (c - a)) | gradient, 0.0) << "face " << f.idx() << " at " << centre;
  }
}

TEST(MeshRepair, LeavesACleanMeshUnchanged) {
  const TriMesh sphere = makeIcosphere(3);
  const RepairedMesh repaired = repairMesh(toPolygonSoup(sphere));
  const RepairCounts& r = repaired.report.repairs;
  EXPECT_TRUE(repaired.report.repaired);
  EXPECT_EQ(r.weldedVertices + r.droppedFaces + r.droppedUnreferencedVertices + r.addedVertices +
                r.flippedFaces,
            0u);
  ASSERT_EQ(repaired.mesh.n_vertices(), sphere.n_vertices());
  ASSERT_EQ(repaired.mesh.n_faces(), sphere.n_faces());
  for (const auto vh : sphere.vertices()) EXPECT_EQ(repaired.mesh.point(vh), sphere.point(vh));
  EXPECT_EQ(toPolygonSoup(repaired.mesh).cornerVertices, toPolygonSoup(sphere).cornerVertices);
}

TEST(MeshRepair, WeldsCornersThatTheFileStoredSeparately) {
  // Every triangle with its own three vertices, each moved by less than the weld tolerance.
  const PolygonSoup shared = toPolygonSoup(makeIcosphere(2));
  PolygonSoup separate;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-1e-9, 1e-9);
  for (std::size_t f = 0; f < shared.faceCount(); ++f) {
    std::array<std::size_t, 3> corners{};
    for (int i = 0; i < 3; ++i) {
      corners[i] = separate.positions.size();
      separate.positions.push_back(shared.positions[shared.cornerVertices[3 * f + i]] +
                                   Eigen::Vector3d(jitter(random), jitter(random), jitter(random)));
    }
    separate.addFace(corners);
  }
  const MeshReport report = repairMesh(separate).report;
  EXPECT_EQ(report.input.components, shared.faceCount());  // nothing connected before welding
  EXPECT_EQ(report.repairs.weldedVertices, separate.vertexCount() - shared.vertexCount());
  EXPECT_EQ(report.result.vertices, shared.vertexCount());
  EXPECT_EQ(report.result.components, 1u);
  EXPECT_EQ(report.result.eulerCharacteristic, 2);
  expectManifoldAndOriented(report.result);

  // Far from the origin (cell indices relative to the bounding box) the same welds happen.
  PolygonSoup far = separate;
  for (auto& p : far.positions) p += Eigen::Vector3d(1e9, -3e9, 2e9);
  EXPECT_EQ(repairMesh(far).report.repairs.weldedVertices,
            separate.vertexCount() - shared.vertexCount());

  // With a zero tolerance only exact copies are welded.
  RepairOptions exact;
  exact.weldTolerance = 0.0;
  EXPECT_EQ(repairMesh(separate, exact).report.repairs.weldedVertices, 0u);
}

TEST(MeshRepair, DropsDegenerateAndDuplicateFacesAndCountsThem) {
  PolygonSoup soup = toPolygonSoup(makeIcosphere(1));
  const std::size_t clean = soup.faceCount();
  soup.positions.push_back((soup.positions[0] + soup.positions[1]) / 2);  // on edge 0-1
  const auto mid = static_cast<int>(soup.vertexCount() - 1);
  soup.addFace(std::array<int, 3>{0, 0, 1});    // repeated vertex
  soup.addFace(std::array<int, 3>{0, mid, 1});  // zero area
  soup.addFace(std::array<int, 2>{2, 3});       // fewer than three corners
  const auto first = std::array<std::uint32_t, 3>{soup.cornerVertices[0], soup.cornerVertices[1],
                                                  soup.cornerVertices[2]};
  soup.addFace(first);                                                       // duplicate
  soup.addFace(std::array<std::uint32_t, 3>{first[0], first[2], first[1]});  // reversed duplicate
  const MeshReport report = repairMesh(soup).report;
  EXPECT_EQ(report.input.degenerateFaces, 3u);
  EXPECT_EQ(report.input.duplicateFaces, 2u);
  EXPECT_EQ(report.repairs.droppedDegenerateFaces, 3u);
  EXPECT_EQ(report.repairs.droppedDuplicateFaces, 2u);
  EXPECT_EQ(report.repairs.droppedUnreferencedVertices,
            1u);  // the midpoint, used only by a dropped face
  EXPECT_EQ(report.result.faces, clean);
  EXPECT_EQ(report.result.eulerCharacteristic, 2);
  expectManifoldAndOriented(report.result);
  expectFacesAccountedFor(report);
}

TEST(MeshRepair, SplitsANonManifoldVertexIntoOneCopyPerFan) {
  const PolygonSoup soup = twoTetrahedraSharingAVertex();
  const MeshReport report = repairMesh(soup).report;
  EXPECT_EQ(report.input.nonManifoldVertices, 1u);
  EXPECT_EQ(report.input.nonManifoldEdges, 0u);
  EXPECT_EQ(report.input.components, 1u);
  EXPECT_EQ(report.repairs.splitNonManifoldVertices, 1u);
  EXPECT_EQ(report.repairs.addedVertices, 1u);
  EXPECT_EQ(report.result.vertices, 8u);
  EXPECT_EQ(report.result.components, 2u);
  EXPECT_EQ(report.result.eulerCharacteristic, 4);
  expectManifoldAndOriented(report.result);
  expectFacesAccountedFor(report);
}

TEST(MeshRepair, SplitsANonManifoldEdgeKeepingEveryFace) {
  // Four triangles on edge 0-1 (a book with four pages), alternating in direction.
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}, {0.5, 0, -1}};
  soup.addFace(std::array<int, 3>{0, 1, 2});
  soup.addFace(std::array<int, 3>{1, 0, 3});
  soup.addFace(std::array<int, 3>{0, 1, 4});
  soup.addFace(std::array<int, 3>{1, 0, 5});
  const MeshReport report = repairMesh(soup).report;
  EXPECT_EQ(report.input.nonManifoldEdges, 1u);
  EXPECT_EQ(report.repairs.splitNonManifoldEdges, 1u);
  EXPECT_EQ(report.repairs.addedVertices, 2u);  // both ends of the edge get a copy
  EXPECT_EQ(report.result.faces, 4u);
  EXPECT_EQ(report.result.components, 2u);  // two pairs of pages, each on its own edge
  EXPECT_EQ(report.repairs.droppedFaces, 0u);
  expectManifoldAndOriented(report.result);
  expectFacesAccountedFor(report);
}

TEST(MeshRepair, OrientsFlippedFacesConsistentlyAndClosedMeshesOutward) {
  PolygonSoup soup = toPolygonSoup(makeIcosphere(2));
  const std::size_t flipped = 17;
  for (std::size_t f = 0; f < flipped; ++f)
    std::swap(soup.cornerVertices[3 * f + 1], soup.cornerVertices[3 * f + 2]);
  const RepairedMesh repaired = repairMesh(soup);
  EXPECT_GT(repaired.report.input.inconsistentlyOrientedEdges, 0u);
  EXPECT_EQ(repaired.report.repairs.flippedFaces, flipped);
  expectManifoldAndOriented(repaired.report.result);
  EXPECT_GT(test::signedVolume(repaired.mesh), 0.0);

  // An inside-out sphere is consistent but faces inward: every face is turned.
  PolygonSoup insideOut = toPolygonSoup(makeIcosphere(2));
  for (std::size_t f = 0; f < insideOut.faceCount(); ++f)
    std::swap(insideOut.cornerVertices[3 * f + 1], insideOut.cornerVertices[3 * f + 2]);
  const RepairedMesh turned = repairMesh(insideOut);
  EXPECT_EQ(turned.report.input.inconsistentlyOrientedEdges, 0u);
  EXPECT_EQ(turned.report.repairs.flippedFaces, insideOut.faceCount());
  EXPECT_GT(test::signedVolume(turned.mesh), 0.0);
}

TEST(MeshRepair, TriangulatesConcavePolygonsInsideTheirOutline) {
  // An L-shaped hexagon: a fan from corner 0 would put a triangle outside the outline.
  PolygonSoup soup;
  soup.positions = {{1, 1, 0}, {0, 1, 0}, {0, 2, 0}, {2, 2, 0}, {2, 0, 0}, {1, 0, 0}};
  soup.addFace(std::array<int, 6>{0, 5, 4, 3, 2, 1});
  const RepairedMesh repaired = repairMesh(soup);
  EXPECT_EQ(repaired.report.repairs.polygonsTriangulated, 1u);
  ASSERT_EQ(repaired.mesh.n_faces(), 4u);
  double area = 0.0;
  for (const auto fh : repaired.mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int i = 0;
    for (const auto vh : fh.vertices()) p[i++] = toEigen(repaired.mesh.point(vh));
    const double signedArea = (p[1] - p[0]).cross(p[2] - p[0]).z() / 2;
    EXPECT_GT(signedArea,
              0.0);  // every triangle keeps the polygon's (counter-clockwise) orientation
    area += signedArea;
  }
  EXPECT_NEAR(area, 3.0, 1e-12);
}

TEST(MeshRepair, RefusesANonOrientableComponentNamingIt) {
  const PolygonSoup strip = moebiusStrip(20);
  const MeshStatistics found = validateMesh(strip).input;
  EXPECT_EQ(found.nonOrientableComponents, 1u);
  EXPECT_EQ(found.componentTopology[0].genus, -1);
  const std::string message = errorMessage([&] { repairMesh(strip); }, ErrorCode::InvalidMesh);
  EXPECT_TRUE(contains(message, "non-orientable")) << message;
  EXPECT_TRUE(contains(message, "input face")) << message;
}

TEST(MeshRepair, RefusesWhatCannotBeRepaired) {
  PolygonSoup nan = toPolygonSoup(makeIcosphere(1));
  nan.positions[3].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(validateMesh(nan).input.nonFiniteCoordinates, 1u);
  EXPECT_TRUE(contains(errorMessage([&] { repairMesh(nan); }, ErrorCode::InvalidMesh), "vertex 3"));

  PolygonSoup empty;
  empty.positions = {{0, 0, 0}};
  EXPECT_TRUE(contains(errorMessage([&] { repairMesh(empty); }, ErrorCode::InvalidMesh), "empty"));

  PolygonSoup outOfRange = toPolygonSoup(makeIcosphere(0));
  outOfRange.cornerVertices[5] = 99;
  EXPECT_TRUE(
      contains(errorMessage([&] { repairMesh(outOfRange); }, ErrorCode::InvalidMesh), "vertex 99"));

  RepairOptions small;
  small.maxFaces = 10;
  EXPECT_TRUE(contains(errorMessage([&] { repairMesh(toPolygonSoup(makeIcosphere(1)), small); },
                                    ErrorCode::LimitExceeded),
                       "limit"));

  PolygonSoup allDegenerate;
  allDegenerate.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  allDegenerate.addFace(std::array<int, 3>{0, 1, 2});
  EXPECT_TRUE(contains(errorMessage([&] { repairMesh(allDegenerate); }, ErrorCode::InvalidMesh),
                       "degenerate"));

  // Sizes whose areas underflow or overflow in double precision: refused with the size.
  for (const double scale : {1e-100, 1e100}) {
    PolygonSoup extreme = toPolygonSoup(makeIcosphere(1));
    for (auto& p : extreme.positions) p *= scale;
    EXPECT_TRUE(contains(errorMessage([&] { repairMesh(extreme); }, ErrorCode::InvalidMesh),
                         "bounding-box diagonal"));
  }
  for (const double scale : {1e-40, 1e40}) {  // inside the range
    PolygonSoup large = toPolygonSoup(makeIcosphere(1));
    for (auto& p : large.positions) p *= scale;
    EXPECT_EQ(repairMesh(large).mesh.n_faces(), 80u);
  }

  PolygonSoup inconsistent = toPolygonSoup(makeIcosphere(0));
  inconsistent.faceStarts.back() += 2;
  EXPECT_TRUE(contains(errorMessage([&] { validateMesh(inconsistent); }, ErrorCode::InvalidMesh),
                       "faceStarts"));
  errorMessage([&] { repairMesh(inconsistent); }, ErrorCode::InvalidMesh);

  RepairOptions bad;
  bad.weldTolerance = -1.0;
  errorMessage([&] { repairMesh(toPolygonSoup(makeIcosphere(0)), bad); }, ErrorCode::InvalidOption);
}

TEST(MeshRepair, WithRepairOffAcceptsCleanMeshesAndRefusesDefects) {
  RepairOptions off;
  off.repair = false;
  const MeshReport clean = repairMesh(toPolygonSoup(makeTorus(3, 1, 16, 8)), off).report;
  EXPECT_FALSE(clean.repaired);
  EXPECT_EQ(clean.result.faces, 256u);
  const std::string message =
      errorMessage([&] { repairMesh(twoTetrahedraSharingAVertex(), off); }, ErrorCode::InvalidMesh);
  EXPECT_TRUE(contains(message, "1 non-manifold vertices")) << message;
}

TEST(MeshRepair, EveryFaceIsAccountedForOnAMeshWithManyDefects) {
  // Two spheres glued at a vertex, plus duplicates, degenerate faces and flipped faces.
  PolygonSoup soup = twoTetrahedraSharingAVertex();
  const PolygonSoup sphere = toPolygonSoup(makeIcosphere(2));
  const auto offset = static_cast<std::uint32_t>(soup.vertexCount());
  for (const auto& p : sphere.positions) soup.positions.push_back(p + Eigen::Vector3d(5, 0, 0));
  for (std::size_t f = 0; f < sphere.faceCount(); ++f) {
    std::array<std::uint32_t, 3> t{sphere.cornerVertices[3 * f] + offset,
                                   sphere.cornerVertices[3 * f + 1] + offset,
                                   sphere.cornerVertices[3 * f + 2] + offset};
    if (f % 7 == 0) std::swap(t[1], t[2]);
    soup.addFace(t);
    if (f % 11 == 0) soup.addFace(t);
    if (f % 13 == 0) soup.addFace(std::array<std::uint32_t, 3>{t[0], t[0], t[1]});
  }
  const MeshReport report = repairMesh(soup).report;
  expectFacesAccountedFor(report);
  expectManifoldAndOriented(report.result);
  EXPECT_EQ(report.result.components, 3u);
  EXPECT_EQ(report.result.eulerCharacteristic, 6);

  // On one thread (two measure the input beside the repair): the same report and mesh.
  RepairOptions oneThread;
  oneThread.threads = 1;
  const RepairedMesh sequential = repairMesh(soup, oneThread);
  const MeshStatistics& input = sequential.report.input;
  EXPECT_GT(input.duplicateFaces, 0u);
  EXPECT_EQ(input.duplicateFaces, report.input.duplicateFaces);
  EXPECT_EQ(input.degenerateFaces, report.input.degenerateFaces);
  EXPECT_EQ(input.nonManifoldVertices, report.input.nonManifoldVertices);
  EXPECT_EQ(input.inconsistentlyOrientedEdges, report.input.inconsistentlyOrientedEdges);
  EXPECT_EQ(input.triangles, report.input.triangles);
  EXPECT_EQ(sequential.report.repairs.droppedFaces, report.repairs.droppedFaces);
  EXPECT_EQ(sequential.report.repairs.flippedFaces, report.repairs.flippedFaces);
  EXPECT_EQ(sequential.report.result.faces, report.result.faces);
  EXPECT_EQ(sequential.report.result.vertices, report.result.vertices);
  oneThread.threads = 0;
  errorMessage([&] { repairMesh(soup, oneThread); }, ErrorCode::InvalidOption);
}

}  // namespace
}  // namespace hexcover
