// End to end: every ill-formed input of shared/meshes/nasty either becomes a repaired job or
// fails with a 422 problem document that says what is wrong; none disturbs the server.

#include <gtest/gtest.h>

#include "tests/common/test_meshes.h"
#include "tests/server/e2e_helpers.h"
#include "tests/server/in_process_server.h"
#include "tests/server/server_process.h"

namespace hexcover::server::test {
namespace {

TEST(EndToEnd, EveryNastyFileIsRepairedOrRefusedWith422NamingTheDefect) {
  HEXCOVER_SERVER_OR_SKIP();
  const auto files = hexcover::test::sharedMeshGroup("nasty");
  if (files.empty())
    GTEST_SKIP() << "no shared nasty/ meshes under " << hexcover::test::sharedMeshDir();
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--workers", "2"});
  ASSERT_TRUE(server.started()) << server.log();
  auto client = server.client();

  std::map<std::string, std::string> locations;
  for (const auto& file : files) {
    const auto res = upload(client, readFile(file), /*multipart=*/false);
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 202) << file << ": " << res->body;
    locations[file.filename().string()] = res->get_header_value("Location");
  }
  std::map<std::string, nlohmann::json> jobs;
  for (const auto& [name, location] : locations) {
    SCOPED_TRACE(name);
    const auto job = waitForJob(client, location, std::chrono::seconds(120));
    jobs[name] = job;
    const std::string state = job.value("state", "");
    ASSERT_TRUE(state == "succeeded" || state == "failed") << job.dump();
    const auto& report = job.at("input").at("report");
    if (state == "succeeded") {
      EXPECT_TRUE(report.at("repaired").get<bool>());
      EXPECT_TRUE(report.contains("repairs"));
      EXPECT_GT(
          nlohmann::json::parse(client.Get((location + "/metrics").c_str())->body).at("faces"), 0);
    } else {
      const auto& error = job.at("error");
      EXPECT_EQ(error.at("status"), 422) << error.dump();
      EXPECT_FALSE(error.at("detail").get<std::string>().empty());
      const std::string code = error.at("code");
      if (code == "invalid_mesh") {
        EXPECT_TRUE(error.contains("report")) << "a refused mesh comes with its report";
      }
      RecordProperty(name, code + ": " + error.at("detail").get<std::string>());
    }
  }
  // Known answers: the Moebius strip cannot be oriented; the non-manifold fan is split.
  const auto& moebius = jobs.at("gc_moebius_nonorientable.obj");
  EXPECT_EQ(moebius.at("state"), "failed");
  EXPECT_EQ(moebius.at("error").at("code"), "invalid_mesh");
  EXPECT_NE(moebius.at("error").at("detail").get<std::string>().find("orient"), std::string::npos);
  EXPECT_EQ(moebius.at("error").at("report").at("input").at("non_orientable_components"), 1);
  const auto& fan = jobs.at("gc_fan3_nonmanifold_edge.obj");
  EXPECT_EQ(fan.at("input").at("report").at("input").at("non_manifold_edges"), 1);
  EXPECT_GE(fan.at("input").at("report").at("repairs").at("split_non_manifold_edges"), 1);
  // The soup's loose triangles are too small for the lattice: copied, and the metrics say so.
  const auto soupMetrics = nlohmann::json::parse(
      client.Get((locations.at("trimesh_soup.stl") + "/metrics").c_str())->body);
  ASSERT_EQ(soupMetrics.at("warnings").size(), 1u) << soupMetrics.dump();
  EXPECT_NE(soupMetrics.at("warnings")[0].get<std::string>().find("copied unchanged"),
            std::string::npos);

  EXPECT_EQ(client.Get("/readyz")->status, 200) << "the server is still healthy";
}

}  // namespace
}  // namespace hexcover::server::test
