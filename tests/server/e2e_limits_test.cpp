// End to end: refusals with the right status and problem document (413 with and without
// Content-Length, 415, 404, 405, 400 naming the option), cancellation and idempotency against
// the real binary.

#include <gtest/gtest.h>

#include "tests/server/e2e_helpers.h"
#include "tests/server/in_process_server.h"
#include "tests/server/server_process.h"

namespace hexcover::server::test {
namespace {

nlohmann::json problemOf(const httplib::Result& res, int status) {
  EXPECT_TRUE(res);
  if (!res) return {};
  EXPECT_EQ(res->status, status) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/problem+json");
  return nlohmann::json::parse(res->body);
}

class EndToEndLimits : public ::testing::Test {
 protected:
  void SetUp() override {
    if (kServerBinary == nullptr) GTEST_SKIP() << "hexcover-server was not built";
    server_ = std::make_unique<ServerProcess>(
        dir_.path() / "data",
        std::vector<std::string>{"--max-upload-bytes", "1048576", "--workers", "1"});
    ASSERT_TRUE(server_->started()) << server_->log();
  }
  TempDir dir_;
  std::unique_ptr<ServerProcess> server_;
};

TEST_F(EndToEndLimits, UploadOverTheLimitIs413WithContentLength) {
  auto client = server_->client();
  const std::string big = "v 0 0 0\n" + std::string(3 << 20, '#');
  const auto doc = problemOf(client.Post("/v1/jobs", big, "model/obj"), 413);
  EXPECT_EQ(doc.at("limit_bytes"), 1048576);
}

TEST_F(EndToEndLimits, ChunkedUploadOverTheLimitIs413) {
  auto client = server_->client();
  const std::string chunk(32 << 10, '#');
  std::size_t sent = 0;
  const auto res = client.Post(
      "/v1/jobs",
      [&](std::size_t, httplib::DataSink& sink) {
        if (sent < (3u << 20)) {
          sink.write(chunk.data(), chunk.size());
          sent += chunk.size();
        } else {
          sink.done();
        }
        return true;
      },
      "model/obj");
  problemOf(res, 413);
  EXPECT_EQ(server_->client().Get("/livez")->status, 200);
}

TEST_F(EndToEndLimits, UnknownFormatIs415) {
  auto client = server_->client();
  const auto doc = problemOf(
      client.Post("/v1/jobs", std::string("\x89PNG\r\n\x1a\n....", 12), "image/png"), 415);
  EXPECT_EQ(doc.at("code"), "unknown_format");
}

TEST_F(EndToEndLimits, UnknownJobIs404AndWrongMethodIs405) {
  auto client = server_->client();
  problemOf(client.Get("/v1/jobs/ffffffffffffffffffffffffffffffff"), 404);
  problemOf(client.Get("/v1/jobs/ffffffffffffffffffffffffffffffff/result"), 404);
  const auto res =
      client.Patch("/v1/jobs/ffffffffffffffffffffffffffffffff", "{}", "application/json");
  problemOf(res, 405);
  EXPECT_EQ(res->get_header_value("Allow"), "GET, DELETE");
}

TEST_F(EndToEndLimits, BadOptionIs400NamingTheOption) {
  auto client = server_->client();
  TempDir meshes;
  const std::string mesh = readFile(writeIcosphere(meshes.path(), "s.obj", 1));
  const auto detailOf = [](const nlohmann::json& doc) {
    return doc.at("detail").get<std::string>();
  };
  EXPECT_NE(
      detailOf(problemOf(client.Post("/v1/jobs?rosy=5", mesh, "model/obj"), 400)).find("rosy"),
      std::string::npos);
  EXPECT_NE(detailOf(problemOf(client.Post("/v1/jobs?sizing=fancy", mesh, "model/obj"), 400))
                .find("sizing"),
            std::string::npos);
  EXPECT_NE(detailOf(problemOf(client.Post("/v1/jobs?edge_length=abc", mesh, "model/obj"), 400))
                .find("edge_length"),
            std::string::npos);
  const httplib::MultipartFormDataItems items = {
      {"options", R"({"speed": 11})", "", "application/json"},
      {"mesh", mesh, "s.obj", "model/obj"}};
  EXPECT_NE(detailOf(problemOf(client.Post("/v1/jobs", items), 400)).find("speed"),
            std::string::npos);
}

TEST_F(EndToEndLimits, DeleteCancelsQueuedAndRunningJobs) {
  auto client = server_->client();
  TempDir meshes;
  const std::string large = readFile(writeIcosphere(meshes.path(), "large.obj", 5));  // 20480 faces
  const std::string small = readFile(writeIcosphere(meshes.path(), "small.obj", 1));
  const std::string running =
      client.Post("/v1/jobs", large, "model/obj")->get_header_value("Location");
  const std::string queued =
      client.Post("/v1/jobs", small, "model/obj")->get_header_value("Location");
  for (int i = 0; i < 1000; ++i) {
    if (nlohmann::json::parse(client.Get(running.c_str())->body).at("state") == "running") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const auto queuedDoc = nlohmann::json::parse(client.Get(queued.c_str())->body);
  ASSERT_EQ(queuedDoc.at("state"), "queued");
  EXPECT_EQ(queuedDoc.at("queue_position"), 0);
  const auto canceledQueued = client.Delete(queued.c_str());
  EXPECT_EQ(canceledQueued->status, 200);
  EXPECT_EQ(nlohmann::json::parse(canceledQueued->body).at("state"), "canceled");

  const auto canceledRunning = client.Delete(running.c_str());
  ASSERT_EQ(canceledRunning->status, 202) << "the large job must still be running";
  const auto done = waitForJob(client, running);
  EXPECT_EQ(done.at("state"), "canceled");
  EXPECT_EQ(client.Delete(running.c_str())->status, 204);
  problemOf(client.Get(running.c_str()), 404);
}

TEST_F(EndToEndLimits, IdempotencyKeyReplaysTheJobAndRefusesAnotherBodyWith422) {
  auto client = server_->client();
  TempDir meshes;
  const std::string mesh = readFile(writeIcosphere(meshes.path(), "s.obj", 1));
  const httplib::Headers key = {{"Idempotency-Key", "farm-batch-7"}};
  const auto first = client.Post("/v1/jobs", key, mesh, "model/obj");
  ASSERT_EQ(first->status, 202);
  waitForJob(client, first->get_header_value("Location"));
  const auto replay = client.Post("/v1/jobs", key, mesh, "model/obj");
  ASSERT_EQ(replay->status, 202);
  EXPECT_EQ(replay->get_header_value("Location"), first->get_header_value("Location"));
  EXPECT_EQ(nlohmann::json::parse(replay->body).at("state"), "succeeded");
  problemOf(client.Post("/v1/jobs", key, mesh + "\n", "model/obj"), 422);
}

}  // namespace
}  // namespace hexcover::server::test
