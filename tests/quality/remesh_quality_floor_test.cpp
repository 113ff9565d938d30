// The quality floors of issue 5 (tests/common/quality_floors.h) at K = V/4 on every clean/ mesh
// and on a generated torus without singularities (label quality_floor; run them alone with
// `ctest --test-dir build -L quality_floor`). Three clean meshes do not meet them yet (issue 5
// is open; docs/QUALITY.md says why): their instantiation of every floor, NotYetMet, carries the
// label quality_floor_not_met instead, which `scripts/test` leaves out unless
// HEXCOVER_QUALITY_FLOORS=1; the floors they do meet are checked with the others.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "core/mesh/io.h"
#include "core/mesh/primitives.h"
#include "core/pipeline/pipeline.h"
#include "tests/common/quality_floors.h"
#include "tests/common/test_meshes.h"

namespace hexcover {
namespace {

using test::expectQualityFloors;
using test::expectTopologyAndAngleFloors;
using test::quarterOf;
using test::referencedVertices;

TEST(PipelineRemesh, TorusMeetsTheQualityFloors) {
  const PolygonSoup torus = toPolygonSoup(makeTorus(1.0, 0.4, 96, 36));
  const RemeshResult result = remesh(torus, quarterOf(torus.vertexCount()));
  expectQualityFloors(result, "torus");
  EXPECT_EQ(result.metrics.topology.genus(), 1);
}

// The mesh file at `path` remeshed at K = V/4.
RemeshResult remeshAtAQuarter(const std::filesystem::path& path) {
  const PolygonSoup soup = readMesh(path);
  return remesh(soup, quarterOf(referencedVertices(soup)));
}

class PipelineCleanMesh : public ::testing::TestWithParam<std::string> {};

TEST_P(PipelineCleanMesh, MeetsTheQualityFloorsAtAQuarterOfItsVertices) {
  HEXCOVER_SHARED_MESH_OR_SKIP(path, "clean/" + GetParam());
  expectQualityFloors(remeshAtAQuarter(path), GetParam());
}

std::string testNameOf(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param.substr(0, info.param.find('.'));
  std::replace_if(
      name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
  return name;
}

// These met every floor when they were added here (fertility has genus 4 and 52 singularities;
// feline, genus 2 and 140, since the surface fit of extraction; camelhead and the open Schwarz P
// cell since the strip gives the front vertices valence 6; the Stanford bunny, with 5 holes,
// since boundary samples weigh angles against the floors; the rocker arm, genus 1 with sharp
// creases, since feature snapping moves part of the way; the Max Planck bust, a scan with folds
// narrower than an edge, since balancing and the bound on the conformal scale's growth; fandisk,
// a CAD model with 24 crease corners, since creases lie on lattice lines and relaxation descends
// on the angles within its deviation bounds).
INSTANTIATE_TEST_SUITE_P(Met, PipelineCleanMesh,
                         ::testing::Values("camelhead.off", "fandisk.obj", "feline.off",
                                           "fertility_28k.obj", "icosphere.obj",
                                           "max-planck_decimated.obj", "rocker-arm.obj",
                                           "schwarzp_cell_open.obj", "stanford-bunny.obj",
                                           "torus.off"),
                         testNameOf);

// Too few vertices at K = V/4 (187-883) for their ears, horns and boundary: more irregular
// vertices than 2%, an angle SD just above 6° and a Hausdorff distance above 1%.
const std::vector<std::string> kFewVertexMeshes{"bunny_7k.off", "spot.obj", "venus_1k.off"};

INSTANTIATE_TEST_SUITE_P(NotYetMet, PipelineCleanMesh, ::testing::ValuesIn(kFewVertexMeshes),
                         testNameOf);

// The same three against the floors they meet; the three they miss are recorded (the XML report
// of `ctest --output-junit`) to follow them.
class PipelineFewVerticesMesh : public ::testing::TestWithParam<std::string> {};

TEST_P(PipelineFewVerticesMesh, MeetsTheTopologyAndAngleFloorsAtAQuarterOfItsVertices) {
  HEXCOVER_SHARED_MESH_OR_SKIP(path, "clean/" + GetParam());
  const RemeshResult result = remeshAtAQuarter(path);
  expectTopologyAndAngleFloors(result, GetParam());
  const QualityReport& m = result.metrics;
  RecordProperty("angle_sd", std::to_string(m.angleSd));
  RecordProperty("irregular_pct", std::to_string(100.0 * m.irregularInterior / m.vertices));
  if (m.distance) RecordProperty("hausdorff_pct", std::to_string(m.distance->hausdorffPct));
}

INSTANTIATE_TEST_SUITE_P(FewVertices, PipelineFewVerticesMesh,
                         ::testing::ValuesIn(kFewVertexMeshes), testNameOf);

}  // namespace
}  // namespace hexcover
