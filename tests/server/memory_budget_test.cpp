// The memory budget that running jobs share: a job waits for its estimated peak, one above the
// whole budget is refused, a running job's larger estimate is granted at once; and the real
// engine's job announces its estimate through it.

#include "server/memory_budget.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <optional>
#include <string>
#include <thread>

#include "core/common/error.h"
#include "core/mesh/io.h"
#include "core/mesh/primitives.h"
#include "server/job_service.h"
#include "server/pipeline_engine.h"
#include "server/sqlite_job_store.h"
#include "tests/server/in_process_server.h"

namespace hexcover::server {
namespace {

const auto kNoStop = [] {};

TEST(MemoryBudget, RefusesAJobAboveTheWholeBudgetAndNamesTheFlag) {
  MemoryBudget budget(1000.0);
  MemoryBudget::Share share(budget);
  try {
    share.raise(1500.0, kNoStop);
    ADD_FAILURE() << "not refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::LimitExceeded);
    EXPECT_NE(std::string(e.what()).find("1500 MiB"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--memory-budget"), std::string::npos) << e.what();
  }
  EXPECT_EQ(budget.reservedMiB(), 0.0);
}

TEST(MemoryBudget, AJobWaitsUntilTheOthersLeaveItsPeakFree) {
  MemoryBudget budget(1000.0);
  std::optional<MemoryBudget::Share> first(std::in_place, budget);
  first->raise(600.0, kNoStop);
  std::atomic<bool> granted{false};
  std::thread second([&] {
    MemoryBudget::Share share(budget);
    share.raise(600.0, kNoStop);
    granted = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  EXPECT_FALSE(granted) << "600 + 600 MiB do not fit in 1000";
  first.reset();  // the first job ends
  second.join();
  EXPECT_TRUE(granted);
  EXPECT_EQ(budget.reservedMiB(), 0.0) << "both shares returned";
}

TEST(MemoryBudget, ARunningJobGrowsWithoutWaitingAndAWaitingOneCanStop) {
  MemoryBudget budget(1000.0);
  MemoryBudget::Share running(budget), other(budget);
  running.raise(500.0, kNoStop);
  other.raise(400.0, kNoStop);
  // Holding memory, it never waits for the other (no deadlock), up to the whole budget.
  running.raise(800.0, kNoStop);
  EXPECT_EQ(running.reservedMiB(), 800.0);
  EXPECT_EQ(budget.reservedMiB(), 1200.0);
  running.raise(700.0, kNoStop);  // a smaller estimate keeps the part
  EXPECT_EQ(running.reservedMiB(), 800.0);

  MemoryBudget::Share waiting(budget);
  int polls = 0;
  const auto stopAfterThreePolls = [&] {
    if (++polls == 3) throw Error(ErrorCode::Canceled, "canceled");
  };
  EXPECT_THROW(waiting.raise(300.0, stopAfterThreePolls), Error);
  EXPECT_EQ(waiting.reservedMiB(), 0.0);
  EXPECT_EQ(budget.reservedMiB(), 1200.0);
}

/// Queues a job whose input is `text` (the stub engine reads it) and returns its id.
std::string submitText(JobService& service, const std::filesystem::path& dir,
                       const std::string& name, const std::string& text) {
  const auto upload = dir / (name + ".obj");
  std::ofstream(upload) << text;
  Submission submission;
  submission.uploadFile = upload;
  submission.format = "obj";
  submission.options = nlohmann::json::object();
  return service.submit(std::move(submission)).job.id;
}

// Three workers and a budget of 100 MiB: of two jobs of 60 MiB the second waits (its stage says
// "memory") until the first is done; a job of 500 MiB fails at once with the reason.
TEST(MemoryBudget, JobsThatDoNotFitSideBySideRunOneAfterTheOther) {
  test::TempDir dir;
  SqliteJobStore store(dir.path() / "jobs.sqlite");
  test::StubEngine engine;
  engine.gateOpen = false;
  ServiceMetrics metrics;
  const Log log = test::quietLog();
  JobServiceOptions options;
  options.dataDir = dir.path();
  options.workers = 3;
  options.memoryBudgetMiB = 100.0;
  JobService service(options, store, engine, metrics, log);
  service.start();
  const std::string mesh = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::string first = submitText(service, dir.path(), "first", "# peak 60\n" + mesh);
  for (int i = 0; i < 1000 && service.find(first)->job.stage != "stub"; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  const std::string second = submitText(service, dir.path(), "second", "# peak 60\n" + mesh);
  for (int i = 0; i < 1000 && service.find(second)->job.stage != "memory"; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_EQ(service.find(second)->job.state, api::JobState::Running);
  EXPECT_EQ(service.find(second)->job.stage, "memory");
  EXPECT_EQ(engine.runs, 2);
  EXPECT_EQ(service.gauges().memoryReservedMiB, 60.0) << "the first job's part (/metrics)";
  EXPECT_EQ(service.gauges().memoryBudgetMiB, 100.0);

  const std::string huge = submitText(service, dir.path(), "huge", "# peak 500\n" + mesh);
  const auto refused = test::waitFinished(service, huge);
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->state, api::JobState::Failed);
  EXPECT_EQ(refused->error.at("code"), "limit_exceeded");

  engine.gateOpen = true;
  EXPECT_EQ(test::waitFinished(service, first)->state, api::JobState::Succeeded);
  EXPECT_EQ(test::waitFinished(service, second)->state, api::JobState::Succeeded);
}

// A server whose budget is below any remesh's estimate (the estimate's 50 MiB base): the job fails
// with the pipeline's estimate named, as an unprocessable input (422), and nothing else breaks.
TEST(MemoryBudget, AJobAboveTheServersBudgetFailsWithTheReason) {
  test::TempDir dir;
  SqliteJobStore store(dir.path() / "jobs.sqlite");
  const PipelineEngine engine;
  ServiceMetrics metrics;
  const Log log = test::quietLog();
  JobServiceOptions options;
  options.dataDir = dir.path();
  options.memoryBudgetMiB = 10.0;
  JobService service(options, store, engine, metrics, log);
  service.start();

  const auto upload = dir.path() / "sphere.obj";
  writeMesh(toPolygonSoup(makeIcosphere(2)), upload);
  Submission submission;
  submission.uploadFile = upload;
  submission.format = "obj";
  submission.options = engine.normalizeOptions({{"vertices", 100}});
  const std::string id = service.submit(std::move(submission)).job.id;
  const auto finished = test::waitFinished(service, id);
  ASSERT_TRUE(finished);
  EXPECT_EQ(finished->state, api::JobState::Failed);
  EXPECT_EQ(finished->error.at("status"), 422);
  EXPECT_EQ(finished->error.at("code"), "limit_exceeded");
  EXPECT_NE(finished->error.at("detail").get<std::string>().find("MiB of memory"),
            std::string::npos)
      << finished->error.dump();
}

}  // namespace
}  // namespace hexcover::server
