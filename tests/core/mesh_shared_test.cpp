// Every shared test mesh (../shared/meshes, see its README): clean/ meshes load with the listed
// topology; each nasty/ mesh is repaired with the expected repairs in its report, or refused with
// an error that names the defect.

#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <string>

#include "core/common/error.h"
#include "core/mesh/load.h"
#include "core/mesh/validate.h"
#include "tests/common/mesh_expectations.h"
#include "tests/common/test_meshes.h"

namespace hexcover {
namespace {

using test::expectManifoldAndOriented;

// V, F, χ, boundary loops and genus after repair, from shared/meshes/README.md (F in triangles).
struct Expected {
  std::size_t vertices;
  std::size_t faces;
  long long chi;
  std::size_t loops;
  int genus;
};

TEST(SharedMeshes, CleanMeshesLoadWithTheirListedTopology) {
  const std::map<std::string, Expected> expected = {
      {"bunny_7k.off", {3485, 6966, 2, 0, 0}},
      {"camelhead.off", {11381, 22704, 1, 1, 0}},
      {"fandisk.obj", {6475, 12946, 2, 0, 0}},
      {"feline.off", {49864, 99732, -2, 0, 2}},
      {"fertility_28k.obj", {13971, 27954, -6, 0, 4}},
      {"icosphere.obj", {10242, 20480, 2, 0, 0}},
      {"max-planck_decimated.obj", {5272, 10540, 2, 0, 0}},
      {"rocker-arm.obj", {10044, 20088, 0, 0, 1}},
      {"schwarzp_cell_open.obj", {11760, 22880, -4, 6, 0}},
      {"spot.obj", {2930, 5856, 2, 0, 0}},
      {"stanford-bunny.obj", {35947 - 1113, 69451, -3, 5, 0}},
      {"torus.off", {10080, 20160, 0, 0, 1}},
      {"venus_1k.off", {711, 1396, 1, 1, 0}},
  };
  HEXCOVER_SHARED_MESH_OR_SKIP(probe, "clean/spot.obj");
  const auto files = test::sharedMeshGroup("clean");
  EXPECT_EQ(files.size(), expected.size())
      << "a clean mesh was added or removed: update this table";
  for (const auto& path : files) {
    SCOPED_TRACE(path.filename().string());
    const auto it = expected.find(path.filename().string());
    ASSERT_NE(it, expected.end()) << "no expectation for this file";
    const Expected& e = it->second;
    const RepairedMesh loaded = loadRepairedMesh(path);
    const MeshStatistics& result = loaded.report.result;
    EXPECT_EQ(loaded.mesh.n_vertices(), e.vertices);
    EXPECT_EQ(loaded.mesh.n_faces(), e.faces);
    EXPECT_EQ(result.components, 1u);
    EXPECT_EQ(result.eulerCharacteristic, e.chi);
    EXPECT_EQ(result.boundaryLoops, e.loops);
    ASSERT_EQ(result.componentTopology.size(), 1u);
    EXPECT_EQ(result.componentTopology[0].genus, e.genus);
    expectManifoldAndOriented(result);
    EXPECT_EQ(loaded.report.repairs.droppedFaces, 0u);
    EXPECT_EQ(loaded.report.repairs.weldedVertices, 0u);
    EXPECT_EQ(loaded.report.repairs.flippedFaces, 0u);
  }
}

TEST(SharedMeshes, StanfordBunnyDropsItsUnreferencedVertices) {
  HEXCOVER_SHARED_MESH_OR_SKIP(path, "clean/stanford-bunny.obj");
  const MeshReport report = loadRepairedMesh(path).report;
  EXPECT_EQ(report.input.vertices, 35947u);
  EXPECT_EQ(report.input.unreferencedVertices, 1113u);
  EXPECT_EQ(report.repairs.droppedUnreferencedVertices, 1113u);
}

// As found (validateMesh, before repair): V, F (polygons), components, boundary loops and χ
// exactly as shared/meshes/README.md lists them.
TEST(SharedMeshes, NastyMeshesAsFoundMatchTheReadme) {
  struct AsFound {
    std::size_t vertices, faces, components, loops;
    long long chi;
  };
  const std::map<std::string, AsFound> readme = {
      {"gc_fan3_nonmanifold_edge.obj", {5, 3, 1, 1, 1}},
      {"gc_hourglass_nonmanifold_vertex.obj", {23, 40, 1, 0, 3}},
      {"gc_moebius_nonorientable.obj", {280, 224, 1, 1, 0}},
      {"gc_platonic_shelf_multicomp.obj", {50, 50, 5, 0, 10}},
      {"libigl_horse_quad.obj", {2400, 2398, 1, 0, 2}},
      {"nasty_ascii_props_crlf.ply", {5, 5, 1, 0, 2}},
      {"nasty_flipped_patch.obj", {642, 1280, 1, 0, 2}},
      {"nasty_zero_area_dup.obj", {122, 203, 1, 1, 2}},
      {"openmesh_cube_minimal_quads.ply", {8, 6, 1, 0, 2}},
      {"trimesh_comments.off", {8, 6, 1, 0, 2}},
      {"trimesh_negative_indices.obj", {8, 6, 1, 0, 2}},
      {"trimesh_soup.stl", {300, 100, 100, 100, 100}},
      {"trimesh_two_solids_ascii.stl", {16, 24, 2, 0, 4}},
  };
  HEXCOVER_SHARED_MESH_OR_SKIP(probe, "nasty/gc_fan3_nonmanifold_edge.obj");
  for (const auto& path : test::sharedMeshGroup("nasty")) {
    SCOPED_TRACE(path.filename().string());
    const auto it = readme.find(path.filename().string());
    ASSERT_NE(it, readme.end()) << "no README row for this file";
    const MeshStatistics found = validateMesh(readMesh(path)).input;
    EXPECT_EQ(found.vertices, it->second.vertices);
    EXPECT_EQ(found.faces, it->second.faces);
    EXPECT_EQ(found.components, it->second.components);
    EXPECT_EQ(found.boundaryLoops, it->second.loops);
    EXPECT_EQ(found.eulerCharacteristic, it->second.chi);
  }
  HEXCOVER_SHARED_MESH_OR_SKIP(moebius, "nasty/gc_moebius_nonorientable.obj");
  const MeshStatistics strip = validateMesh(readMesh(moebius)).input;
  EXPECT_EQ(strip.inconsistentlyOrientedEdges, 4u);
  EXPECT_EQ(strip.nonOrientableComponents, 1u);
  EXPECT_EQ(strip.nonTriangleFaces, 224u);
}

using Check = std::function<void(const RepairedMesh&)>;

// What each nasty/ file must give: a check of its repaired report, or the words the refusal
// must contain.
struct NastyCase {
  Check repaired;
  std::string refusal;
};

std::map<std::string, NastyCase> nastyExpectations() {
  std::map<std::string, NastyCase> cases;
  cases["gc_fan3_nonmanifold_edge.obj"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.nonManifoldEdges, 1u);
    EXPECT_EQ(m.report.repairs.splitNonManifoldEdges, 1u);
    EXPECT_GT(m.report.repairs.addedVertices, 0u);
    EXPECT_EQ(m.mesh.n_faces(), 3u);  // no face lost
  };
  cases["gc_hourglass_nonmanifold_vertex.obj"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.nonManifoldVertices, 1u);
    EXPECT_EQ(m.report.input.eulerCharacteristic, 3);
    EXPECT_EQ(m.report.repairs.splitNonManifoldVertices, 1u);
    EXPECT_EQ(m.report.repairs.addedVertices, 1u);
    EXPECT_EQ(m.mesh.n_vertices(), 24u);
    EXPECT_EQ(m.report.result.components, 2u);
    EXPECT_EQ(m.report.result.eulerCharacteristic, 4);
  };
  cases["gc_moebius_nonorientable.obj"].refusal = "non-orientable";
  cases["gc_platonic_shelf_multicomp.obj"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.nonTriangleFaces, 18u);
    EXPECT_EQ(m.report.repairs.polygonsTriangulated, 18u);
    EXPECT_EQ(m.report.result.components, 5u);
    EXPECT_EQ(m.report.result.eulerCharacteristic, 10);
    EXPECT_EQ(m.mesh.n_vertices(), 50u);
  };
  cases["libigl_horse_quad.obj"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.repairs.polygonsTriangulated, 2398u);
    EXPECT_EQ(m.mesh.n_faces(), 2u * 2398u);
    EXPECT_EQ(m.report.result.eulerCharacteristic, 2);
  };
  cases["nasty_ascii_props_crlf.ply"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.vertices, 5u);
    EXPECT_EQ(m.report.input.faces, 5u);
    EXPECT_EQ(m.report.repairs.polygonsTriangulated, 1u);
    EXPECT_EQ(m.mesh.n_faces(), 6u);
    EXPECT_EQ(m.report.result.eulerCharacteristic, 2);
  };
  cases["nasty_flipped_patch.obj"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.inconsistentlyOrientedEdges, 36u);
    EXPECT_GT(m.report.repairs.flippedFaces, 0u);
    EXPECT_LT(m.report.repairs.flippedFaces, 1280u / 2);
    EXPECT_EQ(m.report.result.eulerCharacteristic, 2);
  };
  cases["nasty_zero_area_dup.obj"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.degenerateFaces, 2u);
    EXPECT_EQ(m.report.input.duplicateFaces, 1u);
    EXPECT_EQ(m.report.input.unreferencedVertices, 1u);
    EXPECT_EQ(m.report.input.nonManifoldEdges, 3u);
    EXPECT_EQ(m.report.repairs.droppedDegenerateFaces, 2u);
    EXPECT_EQ(m.report.repairs.droppedDuplicateFaces, 1u);
    EXPECT_EQ(m.report.repairs.droppedUnreferencedVertices, 1u);
    EXPECT_EQ(m.mesh.n_faces(), 200u);
  };
  cases["openmesh_cube_minimal_quads.ply"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.repairs.polygonsTriangulated, 6u);
    EXPECT_EQ(m.mesh.n_faces(), 12u);
    EXPECT_EQ(m.report.result.eulerCharacteristic, 2);
  };
  cases["trimesh_comments.off"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.vertices, 8u);
    EXPECT_EQ(m.report.repairs.polygonsTriangulated, 6u);
    EXPECT_EQ(m.report.result.eulerCharacteristic, 2);
  };
  cases["trimesh_negative_indices.obj"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.vertices, 8u);
    EXPECT_EQ(m.mesh.n_faces(), 12u);
    EXPECT_EQ(m.report.result.eulerCharacteristic, 2);
  };
  cases["trimesh_soup.stl"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.vertices, 300u);  // welded by exact position while reading
    EXPECT_EQ(m.report.result.components, 100u);
    EXPECT_EQ(m.report.result.boundaryLoops, 100u);
  };
  cases["trimesh_two_solids_ascii.stl"].repaired = [](const RepairedMesh& m) {
    EXPECT_EQ(m.report.input.vertices, 16u);
    EXPECT_EQ(m.report.result.components, 2u);
    EXPECT_EQ(m.report.result.eulerCharacteristic, 4);
  };
  return cases;
}

TEST(SharedMeshes, EveryNastyMeshIsRepairedOrRefusedWithANamedDefect) {
  HEXCOVER_SHARED_MESH_OR_SKIP(probe, "nasty/gc_fan3_nonmanifold_edge.obj");
  const auto cases = nastyExpectations();
  const auto files = test::sharedMeshGroup("nasty");
  EXPECT_EQ(files.size(), cases.size())
      << "a nasty mesh was added or removed: update the expectations";
  for (const auto& path : files) {
    SCOPED_TRACE(path.filename().string());
    const auto it = cases.find(path.filename().string());
    ASSERT_NE(it, cases.end()) << "no expectation for this file";
    if (!it->second.refusal.empty()) {
      try {
        loadRepairedMesh(path);
        ADD_FAILURE() << "expected a refusal";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(it->second.refusal), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos)
            << e.what();
      }
      continue;
    }
    const RepairedMesh repaired = loadRepairedMesh(path);
    it->second.repaired(repaired);
    const MeshReport& report = repaired.report;
    expectManifoldAndOriented(report.result);
    EXPECT_EQ(report.input.triangles, report.result.faces + report.repairs.droppedFaces);
    EXPECT_EQ(report.repairs.facesRefusedByMesh, 0u);
  }
}

}  // namespace
}  // namespace hexcover
