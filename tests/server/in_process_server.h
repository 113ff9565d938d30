#pragma once
// The whole service in the test process (store, job service, HTTP server on a free loopback
// port) over a temporary data directory, with the stub engine.

#include <httplib.h>
#include <spdlog/sinks/null_sink.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include "server/http_server.h"
#include "server/job_service.h"
#include "server/sqlite_job_store.h"
#include "tests/server/stub_engine.h"

namespace hexcover::server::test {

/// A fresh, empty directory under the system temp dir, removed on destruction.
class TempDir {
 public:
  TempDir() {
    std::random_device device;
    path_ = std::filesystem::temp_directory_path() /
            ("hexcover-server-test-" + std::to_string(device()) + std::to_string(device()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// A log that writes nothing.
inline Log quietLog() {
  return Log(
      std::make_shared<spdlog::logger>("test", std::make_shared<spdlog::sinks::null_sink_mt>()));
}

/// The job once it has finished, or nothing after 10 s.
inline std::optional<api::JobRecord> waitFinished(const JobService& service,
                                                  const std::string& id) {
  for (int i = 0; i < 2000; ++i) {
    const auto view = service.find(id);
    if (view && api::isFinished(view->job.state)) return view->job;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return std::nullopt;
}

class InProcessServer {
 public:
  explicit InProcessServer(ServerConfig config = smallConfig(), int workers = 1)
      : config_(withDataDir(std::move(config), dir_.path())),
        log_(quietLog()),
        store_(dir_.path() / "jobs.sqlite"),
        jobs_(serviceOptions(config_, workers), store_, engine, metrics_, log_),
        http_(config_, jobs_, engine, metrics_, log_) {
    jobs_.start();
    port_ = http_.bind();
    thread_ = std::thread([this] { http_.run(); });
    while (!http_.running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    http_.setReady(true);
  }
  ~InProcessServer() {
    engine.gateOpen = true;
    http_.stop();
    thread_.join();
  }

  /// A small upload limit (1 MiB) so that the 413 tests stay fast.
  static ServerConfig smallConfig() {
    ServerConfig config;
    config.host = "127.0.0.1";
    config.port = 0;
    config.maxUploadBytes = 1 << 20;
    config.httpThreads = 4;
    config.keepAliveSeconds = 1;
    config.queueLimit = 100;
    return config;
  }

  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(20);
    return c;
  }
  int port() const { return port_; }
  JobService& jobs() { return jobs_; }
  HttpServer& http() { return http_; }
  const std::filesystem::path& dataDir() const { return dir_.path(); }

  StubEngine engine;

 private:
  static ServerConfig withDataDir(ServerConfig config, const std::filesystem::path& dir) {
    config.dataDir = dir;
    return config;
  }
  static JobServiceOptions serviceOptions(const ServerConfig& config, int workers) {
    JobServiceOptions options;
    options.dataDir = config.dataDir;
    options.workers = workers;
    options.queueLimit = config.queueLimit;
    options.jobTimeLimitSeconds = config.jobTimeLimitSeconds;
    options.retentionSeconds = config.retentionSeconds;
    options.maxAttempts = config.maxAttempts;
    return options;
  }

  TempDir dir_;
  ServerConfig config_;
  Log log_;
  ServiceMetrics metrics_;
  SqliteJobStore store_;
  JobService jobs_;
  HttpServer http_;
  int port_ = 0;
  std::thread thread_;
};

/// Polls GET /v1/jobs/{id} until the job is finished (or `timeout`); returns the last document.
inline nlohmann::json waitForJob(httplib::Client& client, const std::string& location,
                                 std::chrono::seconds timeout = std::chrono::seconds(60)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  nlohmann::json doc;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto res = client.Get(location.c_str());
    if (res && res->status == 200) {
      doc = nlohmann::json::parse(res->body);
      const std::string state = doc.value("state", "");
      if (state == "succeeded" || state == "failed" || state == "canceled") return doc;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return doc;
}

}  // namespace hexcover::server::test
