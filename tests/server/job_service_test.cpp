// The job service's durability rules with the stub engine: recovery after a crash re-runs
// running jobs and runs queued ones, gives up after maxAttempts, removes orphaned files;
// retention expires finished jobs; drain requeues running jobs.

#include <gtest/gtest.h>

#include "tests/server/in_process_server.h"

namespace hexcover::server::test {
namespace {

/// Stores a job as a crashed server would have left it, with its input file.
void leaveJob(SqliteJobStore& store, const std::filesystem::path& dataDir, const std::string& id,
              api::JobState state, int attempts) {
  api::JobRecord job;
  job.id = id;
  job.state = state;
  job.attempts = attempts;
  job.inputFormat = "obj";
  job.createdAt = unixNow();
  ASSERT_TRUE(store.insert(job));
  std::filesystem::create_directories(dataDir / "jobs" / id);
  std::ofstream(dataDir / "jobs" / id / "input.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
}

TEST(JobService, StartRunsQueuedJobsReRunsRunningOnesAndFailsThoseInterruptedTooOften) {
  TempDir dir;
  SqliteJobStore store(dir.path() / "jobs.sqlite");
  leaveJob(store, dir.path(), "queued", api::JobState::Queued, 0);
  leaveJob(store, dir.path(), "running", api::JobState::Running, 1);
  leaveJob(store, dir.path(), "poison", api::JobState::Running, 3);
  std::filesystem::create_directories(dir.path() / "jobs" / "orphan");
  std::filesystem::create_directories(dir.path() / "uploads");
  std::ofstream(dir.path() / "uploads" / "half.part") << "v 0";

  StubEngine engine;
  ServiceMetrics metrics;
  const Log log = quietLog();
  JobServiceOptions options;
  options.dataDir = dir.path();
  options.maxAttempts = 3;
  JobService service(options, store, engine, metrics, log);
  service.start();

  EXPECT_EQ(waitFinished(service, "queued")->state, api::JobState::Succeeded);
  const auto rerun = waitFinished(service, "running");
  EXPECT_EQ(rerun->state, api::JobState::Succeeded);
  EXPECT_EQ(rerun->attempts, 2);
  const auto poison = waitFinished(service, "poison");
  EXPECT_EQ(poison->state, api::JobState::Failed);
  EXPECT_EQ(poison->error.at("code"), "interrupted");
  EXPECT_EQ(engine.runs, 2) << "the poison job is not run a fourth time";
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "jobs" / "orphan"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "uploads" / "half.part"));
}

TEST(JobService, RetentionExpiresFinishedJobsWithTheirFiles) {
  TempDir dir;
  SqliteJobStore store(dir.path() / "jobs.sqlite");
  leaveJob(store, dir.path(), "done", api::JobState::Queued, 0);
  StubEngine engine;
  ServiceMetrics metrics;
  const Log log = quietLog();
  JobServiceOptions options;
  options.dataDir = dir.path();
  options.retentionSeconds = 0.5;
  JobService service(options, store, engine, metrics, log);
  service.start();
  ASSERT_EQ(waitFinished(service, "done")->state, api::JobState::Succeeded);
  for (int i = 0;
       i < 400 && (service.find("done") || std::filesystem::exists(dir.path() / "jobs" / "done"));
       ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_FALSE(service.find("done"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "jobs" / "done"));
}

TEST(JobService, DrainPutsARunningJobBackInTheQueueForTheNextStart) {
  TempDir dir;
  SqliteJobStore store(dir.path() / "jobs.sqlite");
  leaveJob(store, dir.path(), "long", api::JobState::Queued, 0);
  StubEngine engine;
  engine.gateOpen = false;
  ServiceMetrics metrics;
  const Log log = quietLog();
  JobServiceOptions options;
  options.dataDir = dir.path();
  {
    JobService service(options, store, engine, metrics, log);
    service.start();
    for (int i = 0; i < 1000 && service.find("long")->job.state != api::JobState::Running; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ASSERT_EQ(service.find("long")->job.state, api::JobState::Running);
    EXPECT_TRUE(service.drain(std::chrono::milliseconds(50)));
    EXPECT_TRUE(service.draining());
  }
  const auto stored = store.find("long");
  EXPECT_EQ(stored->state, api::JobState::Queued);
  EXPECT_EQ(stored->attempts, 0);
  engine.gateOpen = true;
  JobService restarted(options, store, engine, metrics, log);
  restarted.start();
  EXPECT_EQ(waitFinished(restarted, "long")->state, api::JobState::Succeeded);
}

TEST(JobService, AJobOverTheTimeLimitFailsWithAReason) {
  TempDir dir;
  SqliteJobStore store(dir.path() / "jobs.sqlite");
  leaveJob(store, dir.path(), "slow", api::JobState::Queued, 0);
  StubEngine engine;
  engine.gateOpen = false;  // never finishes by itself
  ServiceMetrics metrics;
  const Log log = quietLog();
  JobServiceOptions options;
  options.dataDir = dir.path();
  options.jobTimeLimitSeconds = 0.2;
  JobService service(options, store, engine, metrics, log);
  service.start();
  const auto job = waitFinished(service, "slow");
  ASSERT_TRUE(job);
  EXPECT_EQ(job->state, api::JobState::Failed);
  EXPECT_EQ(job->error.at("code"), "time_limit");
  EXPECT_NE(job->error.at("detail").get<std::string>().find("time limit"), std::string::npos);
}

}  // namespace
}  // namespace hexcover::server::test
