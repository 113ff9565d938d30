// End to end: what operators and browsers see of the real binary: Prometheus exposition
// (validated by promtool when installed), health endpoints, the served OpenAPI document.

#include <gtest/gtest.h>

#include <cstdio>

#include "tests/server/e2e_helpers.h"
#include "tests/server/in_process_server.h"
#include "tests/server/server_process.h"

namespace hexcover::server::test {
namespace {

bool promtoolAvailable() { return std::system("command -v promtool >/dev/null 2>&1") == 0; }

TEST(EndToEndOperations, MetricsExpositionPassesPromtoolAndCountsRequestsAndJobs) {
  HEXCOVER_SERVER_OR_SKIP();
  TempDir dir;
  TempDir meshes;
  ServerProcess server(dir.path() / "data");
  ASSERT_TRUE(server.started()) << server.log();
  auto client = server.client();
  const auto posted =
      client.Post("/v1/jobs", readFile(writeIcosphere(meshes.path(), "s.obj", 1)), "model/obj");
  waitForJob(client, posted->get_header_value("Location"));
  client.Get("/v1/jobs/ffffffffffffffffffffffffffffffff");

  const auto res = client.Get("/metrics");
  ASSERT_EQ(res->status, 200);
  const std::string text = res->body;
  EXPECT_NE(
      text.find(
          "hexcover_http_requests_total{route=\"/v1/jobs\",method=\"POST\",status=\"202\"} 1"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("status=\"404\""), std::string::npos);
  EXPECT_NE(text.find("hexcover_jobs{state=\"succeeded\"} 1"), std::string::npos);
  EXPECT_NE(text.find("hexcover_job_duration_seconds_count{state=\"succeeded\"} 1"),
            std::string::npos);
  EXPECT_NE(text.find("hexcover_queue_jobs 0"), std::string::npos);
  EXPECT_NE(text.find("hexcover_workers_busy 0"), std::string::npos);
  EXPECT_NE(text.find("hexcover_memory_budget_bytes "), std::string::npos);
  EXPECT_NE(text.find("hexcover_memory_reserved_bytes 0\n"), std::string::npos)
      << "every job done, nothing reserved";
  EXPECT_EQ(text.find(nlohmann::json::parse(posted->body).at("id").get<std::string>()),
            std::string::npos)
      << "never a job id as a label";

  if (!promtoolAvailable())
    GTEST_SKIP()
        << "promtool (Debian package prometheus) is not installed: exposition not validated";
  const auto file = dir.path() / "metrics.txt";
  std::ofstream(file) << text;
  const std::string command = "promtool check metrics < " + file.string() + " > " +
                              (dir.path() / "promtool.out").string() + " 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << readFile(dir.path() / "promtool.out");
}

TEST(EndToEndOperations, HealthEndpointsAndOpenApiDocumentAreServed) {
  HEXCOVER_SERVER_OR_SKIP();
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  ASSERT_TRUE(server.started()) << server.log();
  auto client = server.client();
  EXPECT_EQ(client.Get("/livez")->status, 200);
  EXPECT_EQ(client.Get("/readyz")->status, 200);
  const auto res = client.Get("/v1/openapi.json");
  ASSERT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  const auto doc = nlohmann::json::parse(res->body);
  EXPECT_EQ(doc.at("openapi").get<std::string>().rfind("3.1", 0), 0u);
}

}  // namespace
}  // namespace hexcover::server::test
