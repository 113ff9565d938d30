// The quality floors of issue 5 (tests/common/quality_floors.h) at K = V/4 on every clean/ mesh
// and on a generated torus without singularities (label quality_floor; run them alone with
// `ctest --test-dir build -L quality_floor`). Three clean meshes do not meet them yet (issue 5
// is open; docs/QUALITY.md says why): their instantiation, NotYetMet, carries the label
// quality_floor_not_met instead, which `scripts/test` leaves out unless HEXCOVER_QUALITY_FLOORS=1.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <string>

#include "core/mesh/io.h"
#include "core/mesh/primitives.h"
#include "core/pipeline/pipeline.h"
#include "tests/common/quality_floors.h"
#include "tests/common/test_meshes.h"

namespace hexcover {
namespace {

using test::expectQualityFloors;
using test::quarterOf;
using test::referencedVertices;

TEST(PipelineRemesh, TorusMeetsTheQualityFloors) {
  const PolygonSoup torus = toPolygonSoup(makeTorus(1.0, 0.4, 96, 36));
  const RemeshResult result = remesh(torus, quarterOf(torus.vertexCount()));
  expectQualityFloors(result, "torus");
  EXPECT_EQ(result.metrics.topology.genus(), 1);
}

class PipelineCleanMesh : public ::testing::TestWithParam<std::string> {};

TEST_P(PipelineCleanMesh, MeetsTheQualityFloorsAtAQuarterOfItsVertices) {
  HEXCOVER_SHARED_MESH_OR_SKIP(path, "clean/" + GetParam());
  const PolygonSoup soup = readMesh(path);
  const RemeshResult result = remesh(soup, quarterOf(referencedVertices(soup)));
  expectQualityFloors(result, GetParam());
}

std::string testNameOf(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param.substr(0, info.param.find('.'));
  std::replace_if(
      name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
  return name;
}

INSTANTIATE_TEST_SUITE_P(Met, PipelineCleanMesh,
                         ::testing::Values("camelhead.off", "fandisk.obj", "feline.off",
                                           "fertility_28k.obj", "icosphere.obj",
                                           "max-planck_decimated.obj", "rocker-arm.obj",
                                           "schwarzp_cell_open.obj", "stanford-bunny.obj",
                                           "torus.off"),
                         testNameOf);

// Too few vertices at K = V/4 (187-883) for their ears, horns and boundary: more irregular
// vertices than 2%, an angle SD just above 6° and a Hausdorff distance above 1%.
INSTANTIATE_TEST_SUITE_P(NotYetMet, PipelineCleanMesh,
                         ::testing::Values("bunny_7k.off", "spot.obj", "venus_1k.off"), testNameOf);

}  // namespace
}  // namespace hexcover
