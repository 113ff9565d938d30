// API v1 over loopback against the in-process service with the stub engine: statuses, problem
// documents, headers, uploads and their limits, cancellation, idempotency, CORS.

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "tests/server/in_process_server.h"

namespace hexcover::server::test {
namespace {

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

void expectProblem(const httplib::Result& res, int status, const std::string& mention = "") {
  ASSERT_TRUE(res) << "no response";
  EXPECT_EQ(res->status, status) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/problem+json");
  const auto doc = nlohmann::json::parse(res->body);
  EXPECT_EQ(doc.at("status"), status);
  EXPECT_TRUE(doc.at("type").is_string());
  EXPECT_TRUE(doc.at("title").is_string());
  if (!mention.empty()) {
    EXPECT_NE(doc.at("detail").get<std::string>().find(mention), std::string::npos) << doc.dump();
  }
}

/// Sends raw bytes on a new connection and returns everything the server answers until it
/// closes or `timeoutMs` passes.
std::string rawExchange(int port, const std::string& request, int timeoutMs = 3000) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(std::uint16_t(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    close(fd);
    return {};
  }
  timeval tv{timeoutMs / 1000, (timeoutMs % 1000) * 1000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  std::string answer;
  char buffer[4096];
  for (ssize_t n; (n = recv(fd, buffer, sizeof buffer, 0)) > 0;)
    answer.append(buffer, std::size_t(n));
  close(fd);
  return answer;
}

TEST(HttpApi, RawUploadIsAcceptedWith202LocationAndRetryAfterThenSucceeds) {
  InProcessServer server;
  auto client = server.client();
  const auto res = client.Post("/v1/jobs", kTriangle, "model/obj");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 202) << res->body;
  const auto doc = nlohmann::json::parse(res->body);
  const std::string location = res->get_header_value("Location");
  EXPECT_EQ(location, "/v1/jobs/" + doc.at("id").get<std::string>());
  EXPECT_FALSE(res->get_header_value("Retry-After").empty());
  EXPECT_EQ(doc.at("input").at("format"), "obj");
  EXPECT_EQ(doc.at("input").at("bytes"), kTriangle.size());

  const auto done = waitForJob(client, location);
  ASSERT_EQ(done.at("state"), "succeeded") << done.dump();
  EXPECT_EQ(done.at("progress"), 1.0);
  EXPECT_TRUE(done.at("queue_position").is_null());
  ASSERT_EQ(done.at("links").at("results").size(), 1u);

  const auto result = client.Get((location + "/result?format=obj&mesh=triangles").c_str());
  ASSERT_TRUE(result);
  EXPECT_EQ(result->status, 200);
  EXPECT_EQ(result->body, kTriangle);
  EXPECT_EQ(result->get_header_value("Content-Type"), "model/obj");
  EXPECT_NE(result->get_header_value("Content-Disposition").find("attachment; filename="),
            std::string::npos);

  const auto metrics = client.Get((location + "/metrics").c_str());
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->status, 200);
  EXPECT_EQ(nlohmann::json::parse(metrics->body).at("faces"), 1);
}

TEST(HttpApi, MultipartUploadTakesTheMeshPartAndTheOptionsPart) {
  InProcessServer server;
  auto client = server.client();
  const httplib::MultipartFormDataItems items = {
      {"options", R"({"edge_length": 0.25})", "", "application/json"},
      {"mesh", kTriangle, "tri.obj", "model/obj"},
  };
  const auto res = client.Post("/v1/jobs?rosy=4", items);
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 202) << res->body;
  const auto doc = nlohmann::json::parse(res->body);
  EXPECT_EQ(doc.at("options").at("edge_length"), 0.25);
  EXPECT_EQ(doc.at("options").at("rosy"), 4);
  EXPECT_EQ(doc.at("input").at("filename"), "tri.obj");
  EXPECT_EQ(doc.at("input").at("bytes"), kTriangle.size());
  EXPECT_EQ(waitForJob(client, res->get_header_value("Location")).at("state"), "succeeded");
}

TEST(HttpApi, MultipartUploadWithoutMeshPartIs400) {
  InProcessServer server;
  auto client = server.client();
  const httplib::MultipartFormDataItems items = {{"file", kTriangle, "tri.obj", "model/obj"}};
  expectProblem(client.Post("/v1/jobs", items), 400, "'mesh'");
}

TEST(HttpApi, BadOptionIs400NamingTheOption) {
  InProcessServer server;
  auto client = server.client();
  expectProblem(client.Post("/v1/jobs?rosy=5", kTriangle, "model/obj"), 400, "rosy");
  expectProblem(client.Post("/v1/jobs?edgelength=1", kTriangle, "model/obj"), 400, "edgelength");
  const httplib::MultipartFormDataItems broken = {
      {"options", "{\"rosy\": ", "", "application/json"},
      {"mesh", kTriangle, "tri.obj", "model/obj"}};
  expectProblem(client.Post("/v1/jobs", broken), 400, "not valid JSON");
  // The connection stays usable after a refusal.
  const auto live = client.Get("/livez");
  ASSERT_TRUE(live);
  EXPECT_EQ(live->status, 200);
}

TEST(HttpApi, UnknownFormatIs415AndContentEncodingIs415) {
  InProcessServer server;
  auto client = server.client();
  expectProblem(client.Post("/v1/jobs", "PK\x03\x04 not a mesh", "application/octet-stream"), 415);
  httplib::Headers gzip = {{"Content-Encoding", "gzip"}};
  expectProblem(client.Post("/v1/jobs", gzip, kTriangle, "model/obj"), 415, "Content-Encoding");
}

TEST(HttpApi, EmptyBodyIs400) {
  InProcessServer server;
  auto client = server.client();
  expectProblem(client.Post("/v1/jobs", "", "model/obj"), 400, "empty");
}

TEST(HttpApi, UploadOverTheLimitWithContentLengthIs413) {
  InProcessServer server;  // limit 1 MiB
  auto client = server.client();
  const std::string big = "v 0 0 0\n" + std::string((1 << 20) + 100, '#');
  expectProblem(client.Post("/v1/jobs", big, "model/obj"), 413, "limit");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(server.dataDir() / "uploads"),
                          std::filesystem::directory_iterator()),
            0)
      << "the refused upload must not stay on disk";
}

TEST(HttpApi, ChunkedUploadOverTheLimitIs413) {
  InProcessServer server;  // limit 1 MiB
  auto client = server.client();
  const std::string chunk(64 << 10, '#');
  std::size_t sent = 0;
  const auto res = client.Post(
      "/v1/jobs",
      [&](std::size_t, httplib::DataSink& sink) {
        if (sent == 0) sink.write("v 0 0 0\n", 8);
        if (sent < (1u << 20) + chunk.size()) {
          sink.write(chunk.data(), chunk.size());
          sent += chunk.size();
        } else {
          sink.done();
        }
        return true;
      },
      "model/obj");
  expectProblem(res, 413, "limit");
  const auto live = server.client().Get("/livez");
  ASSERT_TRUE(live);
  EXPECT_EQ(live->status, 200);
}

TEST(HttpApi, ExpectContinueUploadOverTheLimitIsRefusedBeforeTheBodyIsSent) {
  InProcessServer server;
  const std::string answer =
      rawExchange(server.port(),
                  "POST /v1/jobs HTTP/1.1\r\nHost: localhost\r\nContent-Type: model/obj\r\n"
                  "Content-Length: 999999999\r\nExpect: 100-continue\r\n\r\n");
  EXPECT_EQ(answer.rfind("HTTP/1.1 413", 0), 0u) << answer;
  EXPECT_EQ(answer.find("100 Continue"), std::string::npos);
}

TEST(HttpApi, UnknownJobIs404AndUnknownRouteIs404) {
  InProcessServer server;
  auto client = server.client();
  expectProblem(client.Get("/v1/jobs/0123456789abcdef0123456789abcdef"), 404);
  expectProblem(client.Get("/v1/jobs/0123456789abcdef0123456789abcdef/metrics"), 404);
  expectProblem(client.Delete("/v1/jobs/nope"), 404);
  expectProblem(client.Get("/v2/anything"), 404);
}

TEST(HttpApi, WrongMethodIs405WithAllow) {
  InProcessServer server;
  auto client = server.client();
  const auto res = client.Put("/v1/jobs", "x", "text/plain");
  expectProblem(res, 405);
  EXPECT_EQ(res->get_header_value("Allow"), "POST, GET");
}

TEST(HttpApi, JobDocumentHasAnETagAndAnswers304WhenUnchanged) {
  InProcessServer server;
  auto client = server.client();
  const auto posted = client.Post("/v1/jobs", kTriangle, "model/obj");
  const std::string location = posted->get_header_value("Location");
  waitForJob(client, location);
  const auto first = client.Get(location.c_str());
  const std::string etag = first->get_header_value("ETag");
  ASSERT_FALSE(etag.empty());
  const auto second = client.Get(location.c_str(), {{"If-None-Match", etag}});
  ASSERT_TRUE(second);
  EXPECT_EQ(second->status, 304);
  EXPECT_TRUE(second->body.empty());
  const auto other = client.Get(location.c_str(), {{"If-None-Match", "W/\"other\""}});
  EXPECT_EQ(other->status, 200);
}

TEST(HttpApi, QueuedJobShowsItsQueuePositionAndCancelsWithDelete) {
  InProcessServer server;
  server.engine.gateOpen = false;  // the first job holds the only worker
  auto client = server.client();
  const auto first = client.Post("/v1/jobs", kTriangle, "model/obj");
  const auto second = client.Post("/v1/jobs", kTriangle, "model/obj");
  const auto third = client.Post("/v1/jobs", kTriangle, "model/obj");
  const std::string secondLocation = second->get_header_value("Location");
  const std::string thirdLocation = third->get_header_value("Location");
  const auto thirdDoc = nlohmann::json::parse(client.Get(thirdLocation.c_str())->body);
  EXPECT_EQ(thirdDoc.at("state"), "queued");
  EXPECT_EQ(thirdDoc.at("queue_position"), 1);

  const auto canceled = client.Delete(secondLocation.c_str());
  ASSERT_EQ(canceled->status, 200);
  EXPECT_EQ(nlohmann::json::parse(canceled->body).at("state"), "canceled");
  EXPECT_EQ(nlohmann::json::parse(client.Get(thirdLocation.c_str())->body).at("queue_position"), 0);

  server.engine.gateOpen = true;
  EXPECT_EQ(waitForJob(client, first->get_header_value("Location")).at("state"), "succeeded");
  EXPECT_EQ(waitForJob(client, thirdLocation).at("state"), "succeeded");
  EXPECT_EQ(waitForJob(client, secondLocation).at("state"), "canceled");
  EXPECT_EQ(server.engine.runs, 2) << "a canceled queued job never runs";
}

TEST(HttpApi, RunningJobStopsAtItsNextCancellationCheck) {
  InProcessServer server;
  server.engine.gateOpen = false;
  auto client = server.client();
  const std::string location =
      client.Post("/v1/jobs", kTriangle, "model/obj")->get_header_value("Location");
  // Running, and inside the engine (its first progress report names the stage).
  for (int i = 0; i < 500; ++i) {
    const auto job = nlohmann::json::parse(client.Get(location.c_str())->body);
    if (job.at("state") == "running" && job.at("stage") == "stub") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const auto running = nlohmann::json::parse(client.Get(location.c_str())->body);
  ASSERT_EQ(running.at("state"), "running");
  EXPECT_EQ(running.at("stage"), "stub");
  const auto res = client.Delete(location.c_str());
  EXPECT_EQ(res->status, 202);
  const auto done = waitForJob(client, location);
  EXPECT_EQ(done.at("state"), "canceled");
  expectProblem(client.Get((location + "/result").c_str()), 409, "canceled");
}

TEST(HttpApi, DeletingAFinishedJobRemovesItAndItsFiles) {
  InProcessServer server;
  auto client = server.client();
  const auto posted = client.Post("/v1/jobs", kTriangle, "model/obj");
  const std::string id = nlohmann::json::parse(posted->body).at("id");
  const std::string location = posted->get_header_value("Location");
  waitForJob(client, location);
  ASSERT_TRUE(
      std::filesystem::exists(server.dataDir() / "jobs" / id / "results" / "triangles.obj"));
  EXPECT_EQ(client.Delete(location.c_str())->status, 204);
  EXPECT_FALSE(std::filesystem::exists(server.dataDir() / "jobs" / id));
  expectProblem(client.Get(location.c_str()), 404);
}

TEST(HttpApi, IdempotencyKeyReplaysTheSameJobAndRefusesAnotherBody) {
  InProcessServer server;
  auto client = server.client();
  const httplib::Headers key = {{"Idempotency-Key", "upload-42"}};
  const auto first = client.Post("/v1/jobs", key, kTriangle, "model/obj");
  const auto again = client.Post("/v1/jobs", key, kTriangle, "model/obj");
  ASSERT_EQ(first->status, 202);
  ASSERT_EQ(again->status, 202);
  EXPECT_EQ(first->get_header_value("Location"), again->get_header_value("Location"));
  EXPECT_EQ(again->get_header_value("Idempotent-Replayed"), "true");
  expectProblem(client.Post("/v1/jobs", key, kTriangle + "f 1 2 3\n", "model/obj"), 422,
                "upload-42");
  expectProblem(client.Post("/v1/jobs?rosy=4", key, kTriangle, "model/obj"), 422);
  const auto list = nlohmann::json::parse(client.Get("/v1/jobs")->body);
  EXPECT_EQ(list.at("jobs").size(), 1u) << "a replay creates no job";
}

TEST(HttpApi, IdempotencyKeyStillBeingReceivedIs409) {
  InProcessServer server;
  ASSERT_TRUE(server.jobs().beginReceiving("busy-key"));  // as if a first upload were arriving
  auto client = server.client();
  expectProblem(client.Post("/v1/jobs", {{"Idempotency-Key", "busy-key"}}, kTriangle, "model/obj"),
                409, "still being received");
  server.jobs().endReceiving("busy-key");
  EXPECT_EQ(
      client.Post("/v1/jobs", {{"Idempotency-Key", "busy-key"}}, kTriangle, "model/obj")->status,
      202);
}

TEST(HttpApi, RefusedMeshFailsTheJobWithA422ProblemNamingTheDefectAndTheReport) {
  InProcessServer server;
  auto client = server.client();
  const auto posted = client.Post("/v1/jobs", kTriangle + "# refuse\n", "model/obj");
  const auto done = waitForJob(client, posted->get_header_value("Location"));
  ASSERT_EQ(done.at("state"), "failed");
  const auto& error = done.at("error");
  EXPECT_EQ(error.at("status"), 422);
  EXPECT_NE(error.at("detail").get<std::string>().find("non-manifold edge"), std::string::npos);
  EXPECT_EQ(error.at("report").at("input").at("non_manifold_edges"), 1);
  EXPECT_EQ(done.at("input").at("report").at("input").at("non_manifold_edges"), 1);
}

TEST(HttpApi, UnexpectedEngineExceptionFailsOnlyThatJobWithout500Internals) {
  InProcessServer server;
  auto client = server.client();
  const auto bad = client.Post("/v1/jobs", kTriangle + "# throw\n", "model/obj");
  const auto done = waitForJob(client, bad->get_header_value("Location"));
  ASSERT_EQ(done.at("state"), "failed");
  EXPECT_EQ(done.at("error").at("status"), 500);
  EXPECT_EQ(done.dump().find("deadbeef"), std::string::npos) << "internals leaked";
  const auto good = client.Post("/v1/jobs", kTriangle, "model/obj");
  EXPECT_EQ(waitForJob(client, good->get_header_value("Location")).at("state"), "succeeded");
}

TEST(HttpApi, FullQueueIs503WithRetryAfter) {
  ServerConfig config = InProcessServer::smallConfig();
  config.queueLimit = 1;
  InProcessServer server(config);
  server.engine.gateOpen = false;
  auto client = server.client();
  ASSERT_EQ(client.Post("/v1/jobs", kTriangle, "model/obj")->status, 202);  // runs
  for (int i = 0; i < 500 && server.jobs().gauges().busyWorkers == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_EQ(client.Post("/v1/jobs", kTriangle, "model/obj")->status, 202);  // waits
  const auto refused = client.Post("/v1/jobs", kTriangle, "model/obj");
  expectProblem(refused, 503, "queue");
  EXPECT_FALSE(refused->get_header_value("Retry-After").empty());
}

TEST(HttpApi, ResultQueryIsValidatedAndUnfinishedJobsHaveNoResults) {
  InProcessServer server;
  server.engine.gateOpen = false;
  auto client = server.client();
  const std::string location =
      client.Post("/v1/jobs", kTriangle, "model/obj")->get_header_value("Location");
  expectProblem(client.Get((location + "/result?format=fbx").c_str()), 400, "format");
  expectProblem(client.Get((location + "/result?mesh=pentagons").c_str()), 400, "mesh");
  expectProblem(client.Get((location + "/result").c_str()), 409);
  expectProblem(client.Get((location + "/metrics").c_str()), 409);
  server.engine.gateOpen = true;
  waitForJob(client, location);
  expectProblem(client.Get((location + "/result?format=glb&mesh=hexagons").c_str()), 404,
                "available");
}

TEST(HttpApi, JobListIsPagedNewestFirstAndFiltersByState) {
  InProcessServer server;
  auto client = server.client();
  std::vector<std::string> ids;
  for (int i = 0; i < 5; ++i)
    ids.push_back(
        nlohmann::json::parse(client.Post("/v1/jobs", kTriangle, "model/obj")->body).at("id"));
  for (const auto& id : ids) waitForJob(client, "/v1/jobs/" + id);

  std::vector<std::string> seen;
  std::string next = "/v1/jobs?limit=2";
  while (!next.empty()) {
    const auto page = nlohmann::json::parse(client.Get(next.c_str())->body);
    EXPECT_LE(page.at("jobs").size(), 2u);
    for (const auto& job : page.at("jobs")) seen.push_back(job.at("id"));
    next = page.at("links").value("next", "");
  }
  EXPECT_EQ(seen, std::vector<std::string>(ids.rbegin(), ids.rend()));
  EXPECT_EQ(nlohmann::json::parse(client.Get("/v1/jobs?state=succeeded")->body).at("jobs").size(),
            5u);
  EXPECT_EQ(nlohmann::json::parse(client.Get("/v1/jobs?state=failed")->body).at("jobs").size(), 0u);
  expectProblem(client.Get("/v1/jobs?state=done"), 400, "state");
  expectProblem(client.Get("/v1/jobs?limit=0"), 400, "limit");
}

TEST(HttpApi, CorsAllowsConfiguredOriginsAndExposesLocationETagRetryAfter) {
  ServerConfig config = InProcessServer::smallConfig();
  config.corsOrigins = {"https://viewer.example"};
  InProcessServer server(config);
  auto client = server.client();
  const auto allowed = client.Get("/livez", {{"Origin", "https://viewer.example"}});
  EXPECT_EQ(allowed->get_header_value("Access-Control-Allow-Origin"), "https://viewer.example");
  const std::string exposed = allowed->get_header_value("Access-Control-Expose-Headers");
  for (const char* header : {"Location", "ETag", "Retry-After"})
    EXPECT_NE(exposed.find(header), std::string::npos) << header;
  const auto other = client.Get("/livez", {{"Origin", "https://evil.example"}});
  EXPECT_FALSE(other->has_header("Access-Control-Allow-Origin"));
  const auto preflight = client.Options("/v1/jobs", {{"Origin", "https://viewer.example"},
                                                     {"Access-Control-Request-Method", "POST"}});
  EXPECT_EQ(preflight->status, 204);
  EXPECT_NE(preflight->get_header_value("Access-Control-Allow-Methods").find("POST"),
            std::string::npos);
  EXPECT_NE(preflight->get_header_value("Access-Control-Allow-Headers").find("Idempotency-Key"),
            std::string::npos);
  const auto notFound = client.Get("/v1/jobs/nope", {{"Origin", "https://viewer.example"}});
  EXPECT_EQ(notFound->get_header_value("Access-Control-Allow-Origin"), "https://viewer.example");
}

TEST(HttpApi, ReadyzIs503WhileDrainingAndNewUploadsAreRefused) {
  InProcessServer server;
  auto client = server.client();
  EXPECT_EQ(client.Get("/readyz")->status, 200);
  EXPECT_EQ(client.Get("/livez")->status, 200);
  server.http().setReady(false);
  ASSERT_TRUE(server.jobs().drain(std::chrono::seconds(1)));
  expectProblem(client.Get("/readyz"), 503);
  expectProblem(client.Post("/v1/jobs", kTriangle, "model/obj"), 503);
  EXPECT_EQ(client.Get("/livez")->status, 200);
}

TEST(HttpApi, ASecondServerCannotSilentlyShareTheSamePort) {
  InProcessServer first;
  ServerConfig config = InProcessServer::smallConfig();
  config.port = first.port();
  EXPECT_THROW(InProcessServer second(config), std::runtime_error)
      << "SO_REUSEPORT must be off: two servers on one port would split the requests";
}

}  // namespace
}  // namespace hexcover::server::test
