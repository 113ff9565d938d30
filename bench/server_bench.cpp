// Benchmark of the remeshing service (the real hexcover-server binary over loopback):
//  1. throughput: jobs per second for small meshes (icosphere, 320 faces) with the default
//     worker pool;
//  2. status latency: p50 and p99 of GET /v1/jobs/{id} under 100 concurrent pollers (one
//     connection per request, as httplib's default client) while jobs run;
//  3. memory: resident set size of the server with 100 queued jobs.
// Medians of 5 runs. Prints one JSON line for machines, then a table for people.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <thread>
#include <vector>

#include "core/mesh/io.h"  // Eigen before httplib (glibc's <resolv.h> defines `_res`)
#include "core/mesh/primitives.h"
#include "tests/server/server_process.h"

namespace {

using hexcover::server::test::ServerProcess;
using Clock = std::chrono::steady_clock;

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, std::size_t(p * double(values.size())))];
}

std::string meshText(int subdivisions, const std::filesystem::path& dir) {
  const auto path = dir / ("icosphere" + std::to_string(subdivisions) + ".obj");
  hexcover::writeMesh(hexcover::toPolygonSoup(hexcover::makeIcosphere(subdivisions)), path);
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string submit(httplib::Client& client, const std::string& mesh) {
  const auto res = client.Post("/v1/jobs", mesh, "model/obj");
  if (!res || res->status != 202) throw std::runtime_error("upload refused");
  return res->get_header_value("Location");
}

bool finished(httplib::Client& client, const std::string& location) {
  const auto res = client.Get(location.c_str());
  if (!res || res->status != 200) return false;
  const auto state = nlohmann::json::parse(res->body).value("state", "");
  if (state == "failed" || state == "canceled") throw std::runtime_error("job " + state);
  return state == "succeeded";
}

void waitAll(httplib::Client& client, const std::vector<std::string>& locations) {
  for (const auto& location : locations)
    while (!finished(client, location)) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

double residentMiB(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string key; status >> key;) {
    if (key == "VmRSS:") {
      double kib = 0.0;
      status >> kib;
      return kib / 1024.0;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0.0;
}

struct TempDir {
  std::filesystem::path path = std::filesystem::temp_directory_path() /
                               ("hexcover-server-bench-" + std::to_string(std::random_device{}()));
  TempDir() { std::filesystem::create_directories(path); }
  ~TempDir() { std::filesystem::remove_all(path); }
};

}  // namespace

int main() {
  if (hexcover::server::test::kServerBinary == nullptr) {
    std::cerr << "bench_server: hexcover-server was not built\n";
    return 1;
  }
  constexpr int kRuns = 5;
  constexpr int kThroughputJobs = 40;
  constexpr int kPollers = 100;
  constexpr int kQueued = 100;
  TempDir dir;
  const std::string small = meshText(2, dir.path);   // 320 faces
  const std::string medium = meshText(4, dir.path);  // 5120 faces
  const std::string large = meshText(5, dir.path);   // 20480 faces

  std::vector<double> jobsPerSecond, p50, p99, idleMiB, queuedMiB;
  int workers = 0;
  for (int run = 0; run < kRuns; ++run) {
    // 1. Throughput with the default pool.
    {
      ServerProcess server(dir.path / ("throughput" + std::to_string(run)), {"--drain-grace", "0"});
      auto client = server.client();
      const auto start = Clock::now();
      std::vector<std::string> locations;
      for (int i = 0; i < kThroughputJobs; ++i) locations.push_back(submit(client, small));
      waitAll(client, locations);
      jobsPerSecond.push_back(kThroughputJobs /
                              std::chrono::duration<double>(Clock::now() - start).count());
      const auto metrics = client.Get("/metrics")->body;
      const auto at = metrics.find("\nhexcover_workers ");
      workers = std::stoi(metrics.substr(at + 18));
    }
    // 2. Status latency under 100 pollers while medium jobs run.
    {
      ServerProcess server(dir.path / ("latency" + std::to_string(run)), {"--drain-grace", "0"});
      auto client = server.client();
      std::vector<std::string> locations;
      for (int i = 0; i < 8; ++i) locations.push_back(submit(client, medium));
      std::vector<std::vector<double>> samples(kPollers);
      std::vector<std::thread> pollers;
      const auto stop = Clock::now() + std::chrono::seconds(3);
      for (int p = 0; p < kPollers; ++p)
        pollers.emplace_back([&, p] {
          auto poller = server.client();
          const std::string& location = locations[std::size_t(p) % locations.size()];
          while (Clock::now() < stop) {
            const auto begin = Clock::now();
            const auto res = poller.Get(location.c_str());
            if (res && res->status == 200)
              samples[std::size_t(p)].push_back(
                  std::chrono::duration<double, std::milli>(Clock::now() - begin).count());
          }
        });
      for (auto& thread : pollers) thread.join();
      std::vector<double> all;
      for (const auto& s : samples) all.insert(all.end(), s.begin(), s.end());
      p50.push_back(percentile(all, 0.50));
      p99.push_back(percentile(all, 0.99));
    }
    // 3. Memory with 100 queued jobs (one worker busy with a large job).
    {
      ServerProcess server(dir.path / ("memory" + std::to_string(run)),
                           {"--workers", "1", "--drain-grace", "0"});
      auto client = server.client();
      idleMiB.push_back(residentMiB(server.pid()));
      const std::string running = submit(client, large);
      for (int i = 0; i < kQueued; ++i) submit(client, medium);
      queuedMiB.push_back(residentMiB(server.pid()));
      client.Delete(running.c_str());
    }
  }

  const nlohmann::json figures = {{"benchmark", "server"},
                                  {"runs", kRuns},
                                  {"workers", workers},
                                  {"jobs_per_second_small", median(jobsPerSecond)},
                                  {"status_p50_ms", median(p50)},
                                  {"status_p99_ms", median(p99)},
                                  {"pollers", kPollers},
                                  {"rss_idle_mib", median(idleMiB)},
                                  {"rss_100_queued_mib", median(queuedMiB)}};
  std::cout << figures.dump() << "\n\n";
  std::printf("%-48s %10s\n", "server benchmark (median of 5 runs)", "value");
  std::printf("%-48s %10.2f\n", "jobs/s, 320-face icospheres, default pool", median(jobsPerSecond));
  std::printf("%-48s %10d\n", "  workers", workers);
  std::printf("%-48s %10.2f\n", "GET /v1/jobs/{id} p50 ms, 100 pollers", median(p50));
  std::printf("%-48s %10.2f\n", "GET /v1/jobs/{id} p99 ms, 100 pollers", median(p99));
  std::printf("%-48s %10.1f\n", "server RSS MiB, idle", median(idleMiB));
  std::printf("%-48s %10.1f\n", "server RSS MiB, 100 queued jobs", median(queuedMiB));
  return 0;
}
