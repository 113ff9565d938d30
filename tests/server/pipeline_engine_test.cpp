// The real engine's job progress: every stage of the pipeline moves it forward, and it ends at 1.

#include "server/pipeline_engine.h"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh/io.h"
#include "core/mesh/primitives.h"
#include "tests/server/in_process_server.h"

namespace hexcover::server {
namespace {

/// The first and last job progress of each stage reported by the real engine remeshing `mesh` to
/// `vertices`, checked never to go back and to end at 1.
std::map<std::string, std::pair<double, double>> progressSpans(const TriMesh& mesh, int vertices) {
  test::TempDir dir;
  const auto meshFile = dir.path() / "input.obj";
  writeMesh(toPolygonSoup(mesh), meshFile);
  const auto outputDir = dir.path() / "out";
  std::filesystem::create_directories(outputDir);
  const PipelineEngine engine;
  const JobInput input{meshFile, "obj", engine.normalizeOptions({{"vertices", vertices}}),
                       outputDir};

  std::vector<std::pair<std::string, double>> reports;
  RunContext context;
  context.progress = [&](std::string_view stage, double overall) {
    reports.emplace_back(std::string(stage), overall);
  };
  engine.run(input, context);

  std::map<std::string, std::pair<double, double>> span;
  EXPECT_FALSE(reports.empty());
  if (reports.empty()) return span;
  for (std::size_t k = 0; k < reports.size(); ++k) {
    const auto& [stage, overall] = reports[k];
    if (k > 0) {
      EXPECT_GE(overall, reports[k - 1].second) << stage;
    }
    const auto [it, inserted] = span.try_emplace(stage, overall, overall);
    if (!inserted) it->second.second = overall;
  }
  EXPECT_DOUBLE_EQ(reports.back().second, 1.0);
  return span;
}

void expectAdvances(const std::map<std::string, std::pair<double, double>>& spans,
                    const std::string& stage) {
  const auto it = spans.find(stage);
  ASSERT_NE(it, spans.end()) << stage << " was not reported";
  EXPECT_GT(it->second.second, it->second.first) << stage << " left the progress where it was";
}

TEST(PipelineEngine, EveryStageAdvancesTheJobProgress) {
  const auto spans = progressSpans(makeIcosphere(3), 200);
  for (const std::string stage :
       {"repair", "field", "parameterization", "extraction", "metrics", "writing"})
    expectAdvances(spans, stage);
}

// A box's corners make the pipeline remesh it along a second field too: that run moves the job's
// progress on (it had stood still at the first run's end).
TEST(PipelineEngine, ARerunAdvancesTheJobProgress) {
  const auto spans = progressSpans(makeBox(1.0, 0.8, 0.6, 12), 300);
  for (const std::string stage : {"parameterization", "extraction", "rerun", "metrics"})
    expectAdvances(spans, stage);
}

}  // namespace
}  // namespace hexcover::server
