// hexcover-server: the remeshing service (HTTP API v1). See server/http_server.h for the API and
// server/config.h for the flags and HEXCOVER_* variables.
//
// Threads: the HTTP pool (config.httpThreads), the remeshing workers (config.workers jobs compute
// at once, one per usable CPU by default, on two threads each: server/job_queue.h), the retention
// sweeper, and this main thread, which waits for SIGTERM or
// SIGINT (sigwait) and then drains: /readyz answers 503, new uploads get 503, running jobs get
// the grace period and are then put back in the queue; exit status 0.

#include <signal.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <thread>

#include "core/common/memory.h"
#include "server/config.h"
#include "server/health_probe.h"
#include "server/http_server.h"
#include "server/job_service.h"
#include "server/log.h"
#include "server/pipeline_engine.h"
#include "server/sqlite_job_store.h"

int main(int argc, char** argv) {
  using namespace hexcover::server;
  for (int i = 1; i < argc; ++i)
    if (std::string_view(argv[i]) == "--help" || std::string_view(argv[i]) == "-h") {
      std::cout << usage();
      return 0;
    }
  // `--health-check [flags]`: probe the running server's /readyz (the container's HEALTHCHECK).
  const int healthCheck = argc > 1 && std::string_view(argv[1]) == "--health-check" ? 1 : 0;
  ServerConfig config;
  try {
    config = parseConfig(argc - healthCheck, argv + healthCheck, hexcoverEnvironment());
  } catch (const ConfigError& e) {
    std::cerr << "hexcover-server: " << e.what() << "\n\n" << usage();
    return 2;
  }
  if (healthCheck) return probeHealth(config);

  // Each worker runs one job; linear algebra libraries must not start threads of their own.
  for (const char* variable : {"OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"})
    setenv(variable, "1", 0);
  // Freed memory stays for the next allocations of a job; each job hands it back at its end.
  hexcover::keepFreedMemoryForReuse();

  // Block the termination signals in every thread; this one takes them with sigwait.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  signal(SIGPIPE, SIG_IGN);

  const Log log;
  try {
    std::filesystem::create_directories(config.dataDir);
    SqliteJobStore store(config.dataDir / "jobs.sqlite");
    const PipelineEngine engine;
    ServiceMetrics metrics;
    JobServiceOptions options;
    options.dataDir = config.dataDir;
    options.workers = config.effectiveWorkers();
    options.queueLimit = config.queueLimit;
    options.jobTimeLimitSeconds = config.jobTimeLimitSeconds;
    options.memoryBudgetMiB = config.effectiveMemoryBudgetMiB();
    options.retentionSeconds = config.retentionSeconds;
    options.maxAttempts = config.maxAttempts;
    JobService jobs(options, store, engine, metrics, log);
    HttpServer http(config, jobs, engine, metrics, log);

    jobs.start();
    const int port = http.bind();
    std::thread serving([&] { http.run(); });
    while (!http.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    http.setReady(true);
    const std::string host = config.host == "0.0.0.0" ? "localhost" : config.host;
    log.info("listening", {{"port", port},
                           {"url", "http://" + host + ":" + std::to_string(port)},
                           {"data_dir", std::filesystem::absolute(config.dataDir).string()},
                           {"workers", options.workers},
                           {"memory_budget_mib", std::lround(options.memoryBudgetMiB)},
                           {"http_threads", config.httpThreads}});

    int received = 0;
    sigwait(&signals, &received);
    log.info("shutdown", {{"signal", received == SIGTERM ? "SIGTERM" : "SIGINT"}});
    http.setReady(false);
    const bool drained = jobs.drain(std::chrono::duration<double>(config.drainSeconds));
    http.stop();
    serving.join();
    log.info("stopped", {{"drained", drained}});
    if (!drained) std::_Exit(0);  // a worker did not stop: its job is re-run at the next start
    return 0;
  } catch (const std::exception& e) {
    log.error("fatal", {{"error", e.what()}});
    return 1;
  }
}
