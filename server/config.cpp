#include "server/config.h"

#include <sched.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>

#include "server/memory_budget.h"

extern char** environ;

namespace hexcover::server {

namespace {

struct Setting {
  const char* flag;      ///< without the leading "--"
  const char* variable;  ///< environment variable
  const char* help;
  std::function<void(ServerConfig&, const std::string&)> apply;  ///< throws std::invalid_argument
};

long long parseInteger(const std::string& text, long long min, long long max) {
  long long value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size())
    throw std::invalid_argument("expected an integer");
  if (value < min || value > max)
    throw std::invalid_argument("expected an integer in [" + std::to_string(min) + ", " +
                                std::to_string(max) + "]");
  return value;
}

double parseSeconds(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value) || value < 0.0)
    throw std::invalid_argument("expected a non-negative number of seconds");
  return value;
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ','))
    if (!item.empty()) items.push_back(item);
  return items;
}

const std::vector<Setting>& settings() {
  static const std::vector<Setting> table = {
      {"host", "HEXCOVER_HOST", "address to listen on (default 0.0.0.0)",
       [](ServerConfig& c, const std::string& v) { c.host = v; }},
      {"port", "HEXCOVER_PORT", "TCP port, 0 for any free one (default 8080)",
       [](ServerConfig& c, const std::string& v) { c.port = int(parseInteger(v, 0, 65535)); }},
      {"data-dir", "HEXCOVER_DATA_DIR", "job store and mesh files (default ./data)",
       [](ServerConfig& c, const std::string& v) {
         if (v.empty()) throw std::invalid_argument("expected a directory");
         c.dataDir = v;
       }},
      {"workers", "HEXCOVER_WORKERS", "remeshing workers, 0 for one per usable CPU (default 0)",
       [](ServerConfig& c, const std::string& v) { c.workers = int(parseInteger(v, 0, 256)); }},
      {"http-threads", "HEXCOVER_HTTP_THREADS", "HTTP connection threads (default 8)",
       [](ServerConfig& c, const std::string& v) { c.httpThreads = int(parseInteger(v, 1, 256)); }},
      {"max-upload-bytes", "HEXCOVER_MAX_UPLOAD_BYTES", "largest upload (default 536870912)",
       [](ServerConfig& c, const std::string& v) {
         c.maxUploadBytes = std::uint64_t(parseInteger(v, 1, 1ll << 40));
       }},
      {"queue-limit", "HEXCOVER_QUEUE_LIMIT", "most queued jobs before 503 (default 1000)",
       [](ServerConfig& c, const std::string& v) {
         c.queueLimit = std::size_t(parseInteger(v, 1, 1'000'000));
       }},
      {"job-time-limit", "HEXCOVER_JOB_TIME_LIMIT", "seconds one job may run (default 3600)",
       [](ServerConfig& c, const std::string& v) { c.jobTimeLimitSeconds = parseSeconds(v); }},
      {"memory-budget", "HEXCOVER_MEMORY_BUDGET",
       "MiB of memory the running jobs may use together; a job waits for its estimated peak "
       "and one above the budget fails (default 0: 80% of the memory, or of the cgroup's limit)",
       [](ServerConfig& c, const std::string& v) {
         c.memoryBudgetMiB = double(parseInteger(v, 0, 1ll << 40));
       }},
      {"retention", "HEXCOVER_RETENTION", "seconds finished jobs are kept (default 604800)",
       [](ServerConfig& c, const std::string& v) { c.retentionSeconds = parseSeconds(v); }},
      {"drain-grace", "HEXCOVER_DRAIN_GRACE",
       "seconds running jobs may finish after SIGTERM before they are requeued (default 30)",
       [](ServerConfig& c, const std::string& v) { c.drainSeconds = parseSeconds(v); }},
      {"max-attempts", "HEXCOVER_MAX_ATTEMPTS",
       "runs of a job interrupted by crashes before it fails (default 3)",
       [](ServerConfig& c, const std::string& v) { c.maxAttempts = int(parseInteger(v, 1, 100)); }},
      {"keep-alive", "HEXCOVER_KEEP_ALIVE", "idle keep-alive seconds (default 5)",
       [](ServerConfig& c, const std::string& v) {
         c.keepAliveSeconds = int(parseInteger(v, 1, 300));
       }},
      {"cors-origins", "HEXCOVER_CORS_ORIGINS",
       "comma-separated origins allowed by CORS, * for any, empty for none (default *)",
       [](ServerConfig& c, const std::string& v) { c.corsOrigins = splitList(v); }},
      {"web-root", "HEXCOVER_WEB_ROOT",
       "folder of the web front-end served at / (default: web next to the executable)",
       [](ServerConfig& c, const std::string& v) { c.webRoot = v; }},
  };
  return table;
}

void apply(ServerConfig& config, const Setting& setting, const std::string& value,
           const std::string& source) {
  try {
    setting.apply(config, value);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(source + ": bad value '" + value + "': " + e.what());
  }
}

std::optional<int> cgroupCpuLimit() {
  // cgroup v2: "max 100000" or "<quota> <period>".
  if (std::ifstream v2("/sys/fs/cgroup/cpu.max"); v2) {
    std::string quota;
    double period = 0.0;
    if (v2 >> quota >> period && quota != "max" && period > 0.0)
      return int(std::ceil(std::stod(quota) / period));
    return std::nullopt;
  }
  std::ifstream quotaFile("/sys/fs/cgroup/cpu/cpu.cfs_quota_us");
  std::ifstream periodFile("/sys/fs/cgroup/cpu/cpu.cfs_period_us");
  double quota = -1.0, period = 0.0;
  if (quotaFile >> quota && periodFile >> period && quota > 0.0 && period > 0.0)
    return int(std::ceil(quota / period));
  return std::nullopt;
}

}  // namespace

int usableCpuCount() {
  int cpus = 1;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) cpus = std::max(1, CPU_COUNT(&set));
  if (const auto limit = cgroupCpuLimit()) cpus = std::min(cpus, std::max(1, *limit));
  return cpus;
}

int ServerConfig::effectiveWorkers() const { return workers > 0 ? workers : usableCpuCount(); }

double ServerConfig::effectiveMemoryBudgetMiB() const {
  return memoryBudgetMiB > 0.0 ? memoryBudgetMiB : kUsableMemoryShare * usableMemoryMiB();
}

ServerConfig parseConfig(int argc, const char* const* argv,
                         const std::map<std::string, std::string>& environment) {
  ServerConfig config;
  for (const auto& setting : settings())
    if (const auto it = environment.find(setting.variable); it != environment.end())
      apply(config, setting, it->second, setting.variable);

  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0) throw ConfigError("unexpected argument '" + arg + "'");
    std::string name = arg.substr(2), value;
    if (const auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name.resize(eq);
    } else {
      if (i + 1 >= argc) throw ConfigError("--" + name + " needs a value");
      value = argv[++i];
    }
    const auto& table = settings();
    const auto it =
        std::find_if(table.begin(), table.end(), [&](const Setting& s) { return name == s.flag; });
    if (it == table.end()) throw ConfigError("unknown flag --" + name);
    apply(config, *it, value, "--" + name);
  }
  return config;
}

std::map<std::string, std::string> hexcoverEnvironment() {
  std::map<std::string, std::string> variables;
  for (char** entry = environ; *entry; ++entry) {
    const std::string text = *entry;
    const auto eq = text.find('=');
    if (text.rfind("HEXCOVER_", 0) == 0 && eq != std::string::npos)
      variables[text.substr(0, eq)] = text.substr(eq + 1);
  }
  return variables;
}

std::string usage() {
  std::string text =
      "usage: hexcover-server [--flag value]...\n"
      "Remeshing service (HTTP API v1). Every flag can also be set by its environment "
      "variable.\n\n";
  for (const auto& s : settings())
    text += "  --" + std::string(s.flag) + " / " + s.variable + "\n      " + s.help + "\n";
  return text;
}

}  // namespace hexcover::server
