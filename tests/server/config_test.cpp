// Configuration: defaults that work out of the box, environment under flags, errors that name
// the flag or variable; the worker count follows the CPUs the process may use.

#include "server/config.h"

#include <gtest/gtest.h>
#include <sched.h>

#include <thread>

#include "server/memory_budget.h"

namespace hexcover::server {
namespace {

ServerConfig parse(std::vector<const char*> args,
                   const std::map<std::string, std::string>& env = {}) {
  args.insert(args.begin(), "hexcover-server");
  return parseConfig(int(args.size()), args.data(), env);
}

TEST(ServerConfig, DefaultsWorkOutOfTheBox) {
  const auto config = parse({});
  EXPECT_EQ(config.port, 8080);
  EXPECT_EQ(config.dataDir, "data");
  EXPECT_EQ(config.maxUploadBytes, 512ull << 20);
  EXPECT_GE(config.effectiveWorkers(), 1);
  // The memory budget: 80% of the memory this process may use (this machine has some GiB).
  EXPECT_DOUBLE_EQ(config.effectiveMemoryBudgetMiB(),
                   ServerConfig::kUsableMemoryShare * usableMemoryMiB());
  EXPECT_GT(config.effectiveMemoryBudgetMiB(), 256.0);
}

TEST(ServerConfig, FlagsOverrideEnvironmentVariables) {
  const std::map<std::string, std::string> env = {
      {"HEXCOVER_PORT", "9000"},
      {"HEXCOVER_WORKERS", "3"},
      {"HEXCOVER_CORS_ORIGINS", "https://a.example,https://b.example"}};
  const auto fromEnv = parse({}, env);
  EXPECT_EQ(fromEnv.port, 9000);
  EXPECT_EQ(fromEnv.effectiveWorkers(), 3);
  EXPECT_EQ(fromEnv.corsOrigins,
            (std::vector<std::string>{"https://a.example", "https://b.example"}));
  const auto fromFlags = parse({"--port", "9100", "--data-dir=/tmp/x", "--retention", "60"}, env);
  EXPECT_EQ(fromFlags.port, 9100);
  EXPECT_EQ(fromFlags.dataDir, "/tmp/x");
  EXPECT_EQ(fromFlags.retentionSeconds, 60.0);
  EXPECT_EQ(fromFlags.workers, 3);
  EXPECT_EQ(parse({"--memory-budget", "3000"}).effectiveMemoryBudgetMiB(), 3000.0);
  EXPECT_EQ(parse({}, {{"HEXCOVER_MEMORY_BUDGET", "2048"}}).effectiveMemoryBudgetMiB(), 2048.0);
}

TEST(ServerConfig, BadValuesNameTheFlagOrVariable) {
  const auto message = [](auto&& call) {
    try {
      call();
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message([] { parse({"--port", "99999"}); }).find("--port"), std::string::npos);
  EXPECT_NE(message([] { parse({"--workers", "two"}); }).find("--workers"), std::string::npos);
  EXPECT_NE(message([] { parse({"--colour", "red"}); }).find("--colour"), std::string::npos);
  EXPECT_NE(message([] { parse({"--port"}); }).find("--port"), std::string::npos);
  EXPECT_NE(message([] {
              parse({}, {{"HEXCOVER_MAX_UPLOAD_BYTES", "-5"}});
            }).find("HEXCOVER_MAX_UPLOAD_BYTES"),
            std::string::npos);
}

TEST(ServerConfig, UsableCpusFollowTheAffinityMask) {
  cpu_set_t set;
  CPU_ZERO(&set);
  ASSERT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
  const int affinity = CPU_COUNT(&set);
  EXPECT_GE(usableCpuCount(), 1);
  EXPECT_LE(usableCpuCount(), affinity);
  if (affinity < 2) GTEST_SKIP() << "one CPU: cannot narrow the mask";
  // Narrow this thread's mask to one CPU (the mask is per thread; sched_getaffinity(0) reads it).
  std::thread([&] {
    cpu_set_t one;
    CPU_ZERO(&one);
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
      if (CPU_ISSET(cpu, &set)) {
        CPU_SET(cpu, &one);
        break;
      }
    ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
    EXPECT_EQ(usableCpuCount(), 1);
  }).join();
}

}  // namespace
}  // namespace hexcover::server
