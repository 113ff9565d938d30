// End to end: durability and concurrency of the real binary. SIGKILL with jobs queued and
// running loses nothing; SIGTERM drains and exits 0; 50 concurrent uploads are each run once.

#include <gtest/gtest.h>

#include <set>
#include <thread>

#include "tests/server/e2e_helpers.h"
#include "tests/server/in_process_server.h"
#include "tests/server/server_process.h"

namespace hexcover::server::test {
namespace {

std::vector<nlohmann::json> allJobs(httplib::Client& client) {
  std::vector<nlohmann::json> jobs;
  std::string next = "/v1/jobs?limit=1000";
  while (!next.empty()) {
    const auto page = nlohmann::json::parse(client.Get(next.c_str())->body);
    for (const auto& job : page.at("jobs")) jobs.push_back(job);
    next = page.at("links").value("next", "");
  }
  return jobs;
}

TEST(EndToEndDurability, SigkillWithJobsQueuedAndRunningThenRestartFinishesEveryAcceptedJob) {
  HEXCOVER_SERVER_OR_SKIP();
  TempDir dir;
  TempDir meshes;
  const std::string large = readFile(writeIcosphere(meshes.path(), "large.obj", 5));
  const std::string small = readFile(writeIcosphere(meshes.path(), "small.obj", 2));
  std::vector<std::string> locations;
  {
    ServerProcess server(dir.path() / "data", {"--workers", "1"});
    ASSERT_TRUE(server.started()) << server.log();
    auto client = server.client();
    locations.push_back(client.Post("/v1/jobs", large, "model/obj")->get_header_value("Location"));
    for (int i = 0; i < 4; ++i)
      locations.push_back(
          client.Post("/v1/jobs", small, "model/obj")->get_header_value("Location"));
    for (int i = 0; i < 1000; ++i) {
      if (nlohmann::json::parse(client.Get(locations[0].c_str())->body).at("state") == "running")
        break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_EQ(nlohmann::json::parse(client.Get(locations[0].c_str())->body).at("state"), "running");
    ASSERT_EQ(nlohmann::json::parse(client.Get(locations[4].c_str())->body).at("state"), "queued");
    server.signal(SIGKILL);
    EXPECT_EQ(server.waitFor(std::chrono::seconds(10)), -2);
  }
  ServerProcess restarted(dir.path() / "data", {"--workers", "1"});
  ASSERT_TRUE(restarted.started()) << restarted.log();
  auto client = restarted.client();
  for (const auto& location : locations) {
    const auto job = waitForJob(client, location, std::chrono::seconds(120));
    EXPECT_EQ(job.value("state", ""), "succeeded") << job.dump();
  }
  EXPECT_EQ(nlohmann::json::parse(client.Get(locations[0].c_str())->body).at("attempts"), 2)
      << "the job that was running is run again";
  EXPECT_EQ(nlohmann::json::parse(client.Get(locations[4].c_str())->body).at("attempts"), 1);
  EXPECT_EQ(allJobs(client).size(), locations.size()) << "no job lost or duplicated";
}

TEST(EndToEndDurability, SigtermMarksNotReadyRequeuesTheRunningJobAndExitsZero) {
  HEXCOVER_SERVER_OR_SKIP();
  TempDir dir;
  TempDir meshes;
  const std::string large = readFile(writeIcosphere(meshes.path(), "large.obj", 5));
  std::string location;
  {
    ServerProcess server(dir.path() / "data", {"--workers", "1", "--drain-grace", "0"});
    ASSERT_TRUE(server.started()) << server.log();
    auto client = server.client();
    EXPECT_EQ(client.Get("/readyz")->status, 200);
    location = client.Post("/v1/jobs", large, "model/obj")->get_header_value("Location");
    for (int i = 0; i < 1000; ++i) {
      if (nlohmann::json::parse(client.Get(location.c_str())->body).at("state") == "running") break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    server.signal(SIGTERM);
    EXPECT_EQ(server.waitFor(std::chrono::seconds(30)), 0) << server.log();
    EXPECT_NE(server.log().find("\"event\":\"job_requeued\""), std::string::npos);
  }
  ServerProcess restarted(dir.path() / "data", {"--workers", "1"});
  ASSERT_TRUE(restarted.started());
  auto client = restarted.client();
  const auto job = waitForJob(client, location, std::chrono::seconds(120));
  EXPECT_EQ(job.value("state", ""), "succeeded") << job.dump();
  EXPECT_EQ(job.value("attempts", 0), 1) << "a run interrupted by a clean shutdown does not count";
}

TEST(EndToEndDurability, FiftyUploadsFromEightThreadsAllSucceedOnceEach) {
  HEXCOVER_SERVER_OR_SKIP();
  TempDir dir;
  TempDir meshes;
  const std::string mesh = readFile(writeIcosphere(meshes.path(), "tiny.obj", 1));
  ServerProcess server(dir.path() / "data");
  ASSERT_TRUE(server.started()) << server.log();

  constexpr int kThreads = 8, kUploads = 50;
  std::mutex mutex;
  std::vector<std::string> ids;
  std::atomic<int> next{0}, refused{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&] {
      auto client = server.client();
      for (int i; (i = next++) < kUploads;) {
        const auto res = upload(client, mesh, /*multipart=*/i % 2 == 1, "tiny.obj");
        if (!res || res->status != 202) {
          ++refused;
          continue;
        }
        const std::lock_guard lock(mutex);
        ids.push_back(nlohmann::json::parse(res->body).at("id"));
      }
    });
  for (auto& thread : threads) thread.join();
  ASSERT_EQ(refused, 0);
  ASSERT_EQ(ids.size(), std::size_t(kUploads));
  EXPECT_EQ(std::set<std::string>(ids.begin(), ids.end()).size(), std::size_t(kUploads));

  auto client = server.client();
  for (const auto& id : ids)
    EXPECT_EQ(waitForJob(client, "/v1/jobs/" + id, std::chrono::seconds(120)).value("state", ""),
              "succeeded")
        << id;
  const auto jobs = allJobs(client);
  EXPECT_EQ(jobs.size(), std::size_t(kUploads));
  for (const auto& job : jobs) EXPECT_EQ(job.at("state"), "succeeded");
  const std::string log = server.log();
  int runs = 0;
  for (auto at = log.find("\"event\":\"job_started\""); at != std::string::npos;
       at = log.find("\"event\":\"job_started\"", at + 1))
    ++runs;
  EXPECT_EQ(runs, kUploads) << "every job runs exactly once";
}

}  // namespace
}  // namespace hexcover::server::test
