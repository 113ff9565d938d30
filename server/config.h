#pragma once
// Server configuration: command-line flags override HEXCOVER_* environment variables, which
// override the defaults. The defaults work out of the box (port 8080, ./data, one worker per
// usable CPU).

#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace hexcover::server {

/// A flag or variable with a bad value; main prints it with the usage and exits with status 2.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ServerConfig {
  std::string host = "0.0.0.0";            ///< --host, HEXCOVER_HOST
  int port = 8080;                         ///< --port, HEXCOVER_PORT (0: any free port)
  std::filesystem::path dataDir = "data";  ///< --data-dir, HEXCOVER_DATA_DIR (job store + files)
  int workers = 0;                         ///< --workers, HEXCOVER_WORKERS (0: usable CPUs)
  int httpThreads = 8;                     ///< --http-threads, HEXCOVER_HTTP_THREADS
  std::uint64_t maxUploadBytes = 512ull << 20;  ///< --max-upload-bytes, HEXCOVER_MAX_UPLOAD_BYTES
  std::size_t queueLimit = 1000;          ///< --queue-limit, HEXCOVER_QUEUE_LIMIT (queued jobs)
  double jobTimeLimitSeconds = 3600.0;    ///< --job-time-limit, HEXCOVER_JOB_TIME_LIMIT
  /// --memory-budget, HEXCOVER_MEMORY_BUDGET: MiB the running jobs may use together
  /// (memory_budget.h); 0: kUsableMemoryShare of usableMemoryMiB().
  double memoryBudgetMiB = 0.0;
  double retentionSeconds = 7 * 86400.0;  ///< --retention, HEXCOVER_RETENTION (finished jobs)
  double drainSeconds = 30.0;             ///< --drain-grace, HEXCOVER_DRAIN_GRACE (on SIGTERM)
  int maxAttempts = 3;                    ///< --max-attempts, HEXCOVER_MAX_ATTEMPTS (re-runs)
  int keepAliveSeconds = 5;  ///< --keep-alive, HEXCOVER_KEEP_ALIVE (idle, bounds stop())
  std::vector<std::string> corsOrigins = {
      "*"};  ///< --cors-origins, HEXCOVER_CORS_ORIGINS (comma list)
  /// --web-root, HEXCOVER_WEB_ROOT: the web front-end served at `/`; empty: the folder `web`
  /// next to the executable (server/web_assets.h).
  std::filesystem::path webRoot;

  /// The worker count to use: `workers`, or usableCpuCount() when it is 0.
  int effectiveWorkers() const;
  /// The memory budget to use: `memoryBudgetMiB`, or kUsableMemoryShare of usableMemoryMiB()
  /// when it is 0 (the rest for the server itself, uploads and results being written).
  double effectiveMemoryBudgetMiB() const;
  static constexpr double kUsableMemoryShare = 0.8;
};

/// Parses argv (flags `--name value` or `--name=value`) over `environment` (HEXCOVER_* entries).
/// Throws ConfigError naming the bad flag or variable.
ServerConfig parseConfig(int argc, const char* const* argv,
                         const std::map<std::string, std::string>& environment);

/// The HEXCOVER_* variables of this process's environment.
std::map<std::string, std::string> hexcoverEnvironment();

/// Usage text listing every flag, its variable and its default.
std::string usage();

/// CPUs this process may use: the affinity mask (sched_getaffinity), capped by the cgroup CPU
/// quota (cgroup v2 cpu.max, or v1 cpu.cfs_quota_us / cpu.cfs_period_us), rounded up; at least 1.
int usableCpuCount();

}  // namespace hexcover::server
