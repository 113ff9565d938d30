// The memory budget that running jobs share: a job waits for its estimated peak, one above the
// whole budget is refused, a running job's larger estimate is granted at once, small jobs pass a
// large waiting one without starving it; a job waiting for memory gives its worker to the next
// queued job; and the real engine's job announces its estimate through it.

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

/// A job on its own thread that raises its part to `peakMiB` and holds it until release().
class HoldingJob {
 public:
  HoldingJob(MemoryBudget& budget, double peakMiB)
      : thread_([this, &budget, peakMiB] {
          MemoryBudget::Share share(budget);
          try {
            share.raise(peakMiB, [this] {
              waiting_ = true;
              if (cancel_) throw Error(ErrorCode::Canceled, "canceled");
            });
          } catch (const Error&) {
            return;
          }
          granted_ = true;
          while (!release_) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }) {}
  ~HoldingJob() {
    release();
    if (thread_.joinable()) thread_.join();
  }
  bool granted() const { return granted_; }
  /// Whether the job polls while waiting for its part, once it does or has the part (up to 2 s).
  bool waits() const {
    for (int i = 0; i < 1000 && !waiting_ && !granted_; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return waiting_ && !granted_;
  }
  void release() { release_ = true; }
  void cancel() { cancel_ = true; }
  void join() { thread_.join(); }

 private:
  std::atomic<bool> waiting_{false}, granted_{false}, release_{false}, cancel_{false};
  std::thread thread_;
};

/// Waits up to 2 s for `job` to get its part.
bool grantedSoon(const HoldingJob& job) {
  for (int i = 0; i < 1000 && !job.granted(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  return job.granted();
}

TEST(MemoryBudget, ASmallJobStartsWhileALargeOneWaits) {
  MemoryBudget budget(100.0);
  std::optional<MemoryBudget::Share> running(std::in_place, budget);
  running->raise(60.0, kNoStop);
  HoldingJob large(budget, 70.0);
  ASSERT_TRUE(large.waits()) << "60 + 70 MiB do not fit in 100";
  MemoryBudget::Share small(budget);
  small.raise(30.0, kNoStop);  // fits beside the running job: no wait behind the large one
  EXPECT_EQ(budget.reservedMiB(), 90.0);
  running.reset();
  EXPECT_TRUE(grantedSoon(large)) << "70 fits beside the small job's 30";
  EXPECT_EQ(budget.reservedMiB(), 100.0);
}

/// A budget of 100 MiB of which two running jobs hold 50 and 40 MiB (reset() one to end it).
struct TwoRunningJobs {
  TwoRunningJobs() {
    first->raise(50.0, kNoStop);
    second->raise(40.0, kNoStop);
  }
  MemoryBudget budget{100.0};
  std::optional<MemoryBudget::Share> first{std::in_place, budget}, second{std::in_place, budget};
};

// Without the set-aside, the 50 MiB that the first job frees would let a 20 MiB job in beside the
// other 40, and a stream of such jobs would keep the 70 MiB one waiting for ever.
TEST(MemoryBudget, MemoryFreedWhileAJobWaitsIsSetAsideForIt) {
  TwoRunningJobs running;
  MemoryBudget& budget = running.budget;
  HoldingJob large(budget, 70.0);
  ASSERT_TRUE(large.waits());
  running.first.reset();  // 50 MiB free, set aside for the large job, which needs 20 more
  HoldingJob small(budget, 20.0);
  ASSERT_TRUE(small.waits()) << "only 10 MiB are free and not set aside";
  EXPECT_FALSE(large.granted());
  EXPECT_EQ(budget.reservedMiB(), 40.0);
  running.second.reset();
  EXPECT_TRUE(grantedSoon(large));
  EXPECT_TRUE(grantedSoon(small)) << "the other 20 MiB of the second job's";
  EXPECT_EQ(budget.reservedMiB(), 90.0);
}

TEST(MemoryBudget, AJobThatStopsWaitingPassesWhatWasSetAsideForItOn) {
  TwoRunningJobs running;
  MemoryBudget& budget = running.budget;
  HoldingJob oldest(budget, 70.0);
  ASSERT_TRUE(oldest.waits());
  HoldingJob next(budget, 60.0);
  ASSERT_TRUE(next.waits());
  running.first.reset();  // the oldest waiter's 50 MiB
  oldest.cancel();
  oldest.join();
  EXPECT_FALSE(oldest.granted());
  EXPECT_TRUE(grantedSoon(next)) << "its 50 MiB set aside and 10 free";
  EXPECT_EQ(budget.reservedMiB(), 100.0);
}

/// A job service on the stub engine with its gate closed (jobs run until the gate opens) and a
/// memory budget of 100 MiB.
class GatedService {
 public:
  explicit GatedService(int workers) : store_(dir_.path() / "jobs.sqlite") {
    engine.gateOpen = false;
    JobServiceOptions options;
    options.dataDir = dir_.path();
    options.workers = workers;
    options.memoryBudgetMiB = 100.0;
    service.emplace(options, store_, engine, metrics_, log_);
    service->start();
  }

  /// Queues a job that announces a peak of `peakMiB` and returns its id.
  std::string submit(const std::string& name, double peakMiB) {
    const auto upload = dir_.path() / (name + ".obj");
    std::ofstream(upload) << "# peak " << peakMiB << "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    Submission submission;
    submission.uploadFile = upload;
    submission.format = "obj";
    submission.options = nlohmann::json::object();
    return service->submit(std::move(submission)).job.id;
  }

  /// The stage of job `id` once it is `stage`, or after 2 s.
  std::string stageSoon(const std::string& id, const std::string& stage) const {
    for (int i = 0; i < 1000 && service->find(id)->job.stage != stage; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return service->find(id)->job.stage;
  }

 private:
  test::TempDir dir_;
  SqliteJobStore store_;
  ServiceMetrics metrics_;
  const Log log_ = test::quietLog();

 public:
  test::StubEngine engine;
  std::optional<JobService> service;
};

// Three workers: of two jobs of 60 MiB the second waits (its stage says "memory") until the first
// is done; a job of 500 MiB fails at once with the reason.
TEST(MemoryBudget, JobsThatDoNotFitSideBySideRunOneAfterTheOther) {
  GatedService jobs(3);
  JobService& service = *jobs.service;
  const std::string first = jobs.submit("first", 60);
  EXPECT_EQ(jobs.stageSoon(first, "stub"), "stub");
  const std::string second = jobs.submit("second", 60);
  EXPECT_EQ(jobs.stageSoon(second, "memory"), "memory");
  EXPECT_EQ(service.find(second)->job.state, api::JobState::Running);
  EXPECT_EQ(jobs.engine.runs, 2);
  EXPECT_EQ(service.gauges().memoryReservedMiB, 60.0) << "the first job's part (/metrics)";
  EXPECT_EQ(service.gauges().memoryBudgetMiB, 100.0);

  const std::string huge = jobs.submit("huge", 500);
  const auto refused = test::waitFinished(service, huge);
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->state, api::JobState::Failed);
  EXPECT_EQ(refused->error.at("code"), "limit_exceeded");

  jobs.engine.gateOpen = true;
  EXPECT_EQ(test::waitFinished(service, first)->state, api::JobState::Succeeded);
  EXPECT_EQ(test::waitFinished(service, second)->state, api::JobState::Succeeded);
}

// Two workers: while a job of 60 MiB waits for the one running, it gives its worker to a queued
// job of 30 MiB, which fits beside the running one.
TEST(MemoryBudget, AJobWaitingForMemoryLetsTheNextQueuedJobRun) {
  GatedService jobs(2);
  JobService& service = *jobs.service;
  const std::string first = jobs.submit("first", 60);
  EXPECT_EQ(jobs.stageSoon(first, "stub"), "stub");
  const std::string second = jobs.submit("second", 60);
  EXPECT_EQ(jobs.stageSoon(second, "memory"), "memory");
  const std::string third = jobs.submit("third", 30);
  EXPECT_EQ(jobs.stageSoon(third, "stub"), "stub") << "queued behind the waiting job";
  EXPECT_EQ(service.gauges().busyWorkers, 2u) << "the first and the third job";
  EXPECT_EQ(service.gauges().memoryReservedMiB, 90.0);

  jobs.engine.gateOpen = true;
  for (const auto& id : {first, second, third})
    EXPECT_EQ(test::waitFinished(service, id)->state, api::JobState::Succeeded);
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
