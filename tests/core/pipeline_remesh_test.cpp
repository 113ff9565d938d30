// The pipeline end to end: repair -> field -> parameterization -> extraction -> metrics.
// Quality floors of issue 5, measured at K = V/4 on generated meshes and on every clean/ mesh:
// topology kept, min angle >= 20°, max angle <= 130°, angle SD <= 6°, irregular interior vertices
// <= 2% of the vertices and no more than the field's singularities, each at a singularity, and the
// two-sided Hausdorff distance <= 1% of the bounding-box diagonal.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/mesh/io.h"
#include "core/mesh/primitives.h"
#include "core/pipeline/pipeline.h"
#include "tests/common/test_meshes.h"

namespace hexcover {
namespace {

RemeshOptions quarterOf(long long vertices) {
  RemeshOptions options;
  options.targetVertices = std::max<long long>(4, vertices / 4);
  return options;
}

long long referencedVertices(const PolygonSoup& soup) {
  std::vector<bool> used(soup.vertexCount(), false);
  for (const auto v : soup.cornerVertices) used[v] = true;
  return std::count(used.begin(), used.end(), true);
}

/// Interior vertices of valence ≠ 6 farther than `radius` from every singularity.
int irregularAwayFromSingularities(const RemeshResult& result, double radius) {
  const TriMesh& out = result.remesh.triangles;
  int count = 0;
  for (const auto v : out.vertices()) {
    if (out.is_boundary(v) || out.is_isolated(v) || out.valence(v) == 6) continue;
    const Eigen::Vector3d p = toEigen(out.point(v));
    const bool near = std::any_of(result.singularities.begin(), result.singularities.end(),
                                  [&](const Singularity& s) { return (s.position - p).norm() <= radius; });
    count += near ? 0 : 1;
  }
  return count;
}

/// Every floor of the issue, each as its own expectation so that a report lists all misses.
void expectQualityFloors(const RemeshResult& result, const std::string& name) {
  const QualityReport& m = result.metrics;
  SCOPED_TRACE(name + ": " + std::to_string(m.vertices) + " vertices, h = " +
               std::to_string(result.edgeLength));
  EXPECT_TRUE(m.topologyMatchesReference.value_or(false)) << "topology differs from the input";
  EXPECT_TRUE(m.topology.manifold);
  EXPECT_EQ(result.remesh.report.nonManifoldFacesDropped, 0);
  EXPECT_GE(m.angleMin, 20.0);
  EXPECT_LE(m.angleMax, 130.0);
  EXPECT_LE(m.angleSd, 6.0);
  EXPECT_LE(m.irregularInterior, 0.02 * m.vertices);
  EXPECT_LE(m.irregularInterior, static_cast<int>(result.singularities.size()));
  // "At a singularity": within two edge lengths of the field's singular vertex (the lattice
  // point of a ±1/6 singularity is within a unit of the vertex it is attached to).
  EXPECT_EQ(irregularAwayFromSingularities(result, 2.0 * result.edgeLength), 0);
  ASSERT_TRUE(m.distance.has_value());
  EXPECT_LE(m.distance->hausdorffPct, 1.0);
}

TEST(PipelineRemesh, IcosphereMeetsTheQualityFloors) {
  const PolygonSoup sphere = toPolygonSoup(makeIcosphere(4));
  const RemeshResult result = remesh(sphere, quarterOf(sphere.vertexCount()));
  expectQualityFloors(result, "icosphere(4)");
}

TEST(PipelineRemesh, TorusMeetsTheQualityFloors) {
  const PolygonSoup torus = toPolygonSoup(makeTorus(1.0, 0.4, 96, 36));
  const RemeshResult result = remesh(torus, quarterOf(torus.vertexCount()));
  expectQualityFloors(result, "torus");
  EXPECT_EQ(result.metrics.topology.genus(), 1);
}

TEST(PipelineRemesh, TubeKeepsItsTwoBoundaryLoopsOnTheInputBoundary) {
  const TriMesh tube = makeTube(0.5, 2.0, 64, 38);
  const RemeshResult result = remesh(toPolygonSoup(tube), quarterOf(tube.n_vertices()));
  expectQualityFloors(result, "tube");
  const TriMesh& out = result.remesh.triangles;
  EXPECT_EQ(result.metrics.topology.boundaryLoops, 2);
  // Boundary vertices lie on the two rims z = 0 and z = 2 (on the input's boundary polygon, whose
  // chords are within 0.5·(1 - cos(π/64)) of the circle).
  for (const auto v : out.vertices()) {
    if (!out.is_boundary(v)) continue;
    const auto p = out.point(v);
    EXPECT_TRUE(std::abs(p[2]) < 1e-9 || std::abs(p[2] - 2.0) < 1e-9) << "z = " << p[2];
    EXPECT_NEAR(std::hypot(p[0], p[1]), 0.5, 0.5 * (1 - std::cos(M_PI / 64)) + 1e-9);
  }
}

TEST(PipelineRemesh, TargetVertexCountIsMetWithinTenPercent) {
  const PolygonSoup sphere = toPolygonSoup(makeIcosphere(4));
  for (const long long target : {300LL, 1500LL}) {
    RemeshOptions options;
    options.targetVertices = target;
    const RemeshResult result = remesh(sphere, options);
    EXPECT_NEAR(static_cast<double>(result.remesh.triangles.n_vertices()), target, 0.1 * target);
  }
}

TEST(PipelineRemesh, ResultIsDeterministic) {
  const PolygonSoup torus = toPolygonSoup(makeTorus(1.0, 0.4, 48, 18));
  const RemeshResult a = remesh(torus, quarterOf(torus.vertexCount()));
  const RemeshResult b = remesh(torus, quarterOf(torus.vertexCount()));
  ASSERT_EQ(a.remesh.triangles.n_vertices(), b.remesh.triangles.n_vertices());
  ASSERT_EQ(a.remesh.triangles.n_faces(), b.remesh.triangles.n_faces());
  for (const auto v : a.remesh.triangles.vertices())
    ASSERT_EQ(a.remesh.triangles.point(v), b.remesh.triangles.point(v));
}

TEST(PipelineRemesh, ReportsProgressPerStageAndTimings) {
  const PolygonSoup sphere = toPolygonSoup(makeIcosphere(3));
  std::vector<std::string> stages;
  RunContext context;
  context.progress = [&](std::string_view stage, double fraction) {
    EXPECT_GE(fraction, 0.0);
    EXPECT_LE(fraction, 1.0);
    if (stages.empty() || stages.back() != stage) stages.emplace_back(stage);
  };
  const RemeshResult result = remesh(sphere, quarterOf(sphere.vertexCount()), context);
  for (const std::string stage : {"repair", "field", "parameterization", "extract", "metrics"})
    EXPECT_NE(std::find(stages.begin(), stages.end(), stage), stages.end()) << stage;
  for (const std::string step : {"repair", "field", "parameterization", "extraction", "metrics"})
    EXPECT_TRUE(std::any_of(result.timings.begin(), result.timings.end(),
                            [&](const StepTiming& t) { return t.step == step && t.seconds >= 0.0; }))
        << step;
  EXPECT_GT(result.peakMemoryMiB, 0.0);
  // The textured input has one texture coordinate per corner of the repaired input.
  EXPECT_EQ(result.textured.cornerTexcoords.size(), result.textured.cornerVertices.size());
  // The dual has one polygon per remesh vertex.
  EXPECT_EQ(result.remesh.hexDual.faceCount(), result.remesh.triangles.n_vertices());
}

TEST(PipelineRemesh, CancellationInsideAStageStopsTheRun) {
  const PolygonSoup sphere = toPolygonSoup(makeIcosphere(3));
  for (const std::string stop : {"field", "parameterization", "extract"}) {
    bool reached = false;
    RunContext context;
    context.progress = [&](std::string_view stage, double) { reached = reached || stage == stop; };
    context.cancelRequested = [&] { return reached; };
    try {
      remesh(sphere, quarterOf(sphere.vertexCount()), context);
      ADD_FAILURE() << "not canceled in " << stop;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::Canceled) << stop;
    }
  }
}

TEST(PipelineRemesh, ValidateNamesTheBadOption) {
  const auto code = [](const RemeshOptions& options) {
    try {
      options.validate();
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::Io;  // "no error"
  };
  RemeshOptions both;
  both.edgeLength = 0.1;
  both.targetVertices = 100;
  EXPECT_EQ(code(both), ErrorCode::InvalidOption);
  RemeshOptions negative;
  negative.edgeLength = -1.0;
  EXPECT_EQ(code(negative), ErrorCode::InvalidOption);
  RemeshOptions rosy;
  rosy.rosy = 5;
  EXPECT_EQ(code(rosy), ErrorCode::InvalidOption);
  EXPECT_EQ(code(RemeshOptions{}), ErrorCode::Io);
}

TEST(PipelineRemesh, RefusesAnEmptyMeshWithAnInputError) {
  try {
    remesh(PolygonSoup{}, {});
    FAIL() << "an empty mesh was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidMesh);
  }
}

class PipelineCleanMesh : public ::testing::TestWithParam<std::string> {};

TEST_P(PipelineCleanMesh, MeetsTheQualityFloorsAtAQuarterOfItsVertices) {
  HEXCOVER_SHARED_MESH_OR_SKIP(path, "clean/" + GetParam());
  const PolygonSoup soup = readMesh(path);
  const RemeshResult result = remesh(soup, quarterOf(referencedVertices(soup)));
  expectQualityFloors(result, GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Clean, PipelineCleanMesh,
    ::testing::Values("bunny_7k.off", "camelhead.off", "fandisk.obj", "feline.off",
                      "fertility_28k.obj", "icosphere.obj", "max-planck_decimated.obj",
                      "rocker-arm.obj", "schwarzp_cell_open.obj", "spot.obj",
                      "stanford-bunny.obj", "torus.off", "venus_1k.off"),
    [](const auto& info) {
      std::string name = info.param.substr(0, info.param.find('.'));
      std::replace_if(name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
      return name;
    });

}  // namespace
}  // namespace hexcover
