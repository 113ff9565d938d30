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

TEST(PipelineEngine, EveryStageAdvancesTheJobProgress) {
  test::TempDir dir;
  const auto meshFile = dir.path() / "sphere.obj";
  writeMesh(toPolygonSoup(makeIcosphere(3)), meshFile);
  const auto outputDir = dir.path() / "out";
  std::filesystem::create_directories(outputDir);
  const PipelineEngine engine;
  const JobInput input{meshFile, "obj", engine.normalizeOptions({{"vertices", 200}}), outputDir};

  std::vector<std::pair<std::string, double>> reports;
  RunContext context;
  context.progress = [&](std::string_view stage, double overall) {
    reports.emplace_back(std::string(stage), overall);
  };
  engine.run(input, context);

  ASSERT_FALSE(reports.empty());
  std::map<std::string, std::pair<double, double>> span;  // first and last progress per stage
  for (std::size_t k = 0; k < reports.size(); ++k) {
    const auto& [stage, overall] = reports[k];
    if (k > 0) {
      EXPECT_GE(overall, reports[k - 1].second) << stage;
    }
    const auto [it, inserted] = span.try_emplace(stage, overall, overall);
    if (!inserted) it->second.second = overall;
  }
  for (const std::string stage :
       {"repair", "field", "parameterization", "extraction", "metrics", "writing"}) {
    ASSERT_TRUE(span.count(stage)) << stage << " was not reported";
    EXPECT_GT(span[stage].second, span[stage].first) << stage << " left the progress where it was";
  }
  EXPECT_DOUBLE_EQ(reports.back().second, 1.0);
}

}  // namespace
}  // namespace hexcover::server
