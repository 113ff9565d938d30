// The SQLite job store: records survive reopening, idempotency keys are unique, pages are
// ordered and complete, recovery and retention queries select the right jobs.

#include <gtest/gtest.h>

#include <set>

#include "server/sqlite_job_store.h"
#include "tests/server/in_process_server.h"

namespace hexcover::server::test {
namespace {

api::JobRecord makeJob(const std::string& id, api::JobState state = api::JobState::Queued) {
  api::JobRecord job;
  job.id = id;
  job.state = state;
  job.inputFormat = "obj";
  job.inputBytes = 42;
  job.options = {{"rosy", 6}};
  job.createdAt = 1000.0;
  return job;
}

TEST(SqliteJobStore, RecordsSurviveReopeningTheDatabase) {
  TempDir dir;
  const auto file = dir.path() / "jobs.sqlite";
  std::string id = "a";
  {
    SqliteJobStore store(file);
    auto job = makeJob(id);
    ASSERT_TRUE(store.insert(job));
    EXPECT_GT(job.sequence, 0);
    job.state = api::JobState::Succeeded;
    job.metrics = {{"faces", 12}};
    job.results.push_back({"triangles", "obj", "triangles.obj", 99});
    job.finishedAt = 2000.0;
    store.update(job);
  }
  SqliteJobStore reopened(file);
  const auto job = reopened.find(id);
  ASSERT_TRUE(job);
  EXPECT_EQ(job->state, api::JobState::Succeeded);
  EXPECT_EQ(job->metrics.at("faces"), 12);
  ASSERT_EQ(job->results.size(), 1u);
  EXPECT_EQ(job->results[0].file, "triangles.obj");
  EXPECT_EQ(job->results[0].bytes, 99u);
  EXPECT_EQ(job->options.at("rosy"), 6);
  EXPECT_FALSE(reopened.find("b"));
}

TEST(SqliteJobStore, AnIdempotencyKeyBelongsToOneJob) {
  TempDir dir;
  SqliteJobStore store(dir.path() / "jobs.sqlite");
  auto first = makeJob("a");
  first.idempotencyKey = "k";
  auto second = makeJob("b");
  second.idempotencyKey = "k";
  auto third = makeJob("c");  // no key: any number of jobs may have none
  auto fourth = makeJob("d");
  EXPECT_TRUE(store.insert(first));
  EXPECT_FALSE(store.insert(second));
  EXPECT_TRUE(store.insert(third));
  EXPECT_TRUE(store.insert(fourth));
  EXPECT_FALSE(store.find("b"));
  EXPECT_EQ(store.findByIdempotencyKey("k")->id, "a");
}

TEST(SqliteJobStore, PagesAreNewestFirstAndCoverEveryJobOnce) {
  TempDir dir;
  SqliteJobStore store(dir.path() / "jobs.sqlite");
  for (int i = 0; i < 7; ++i) {
    auto job =
        makeJob("job" + std::to_string(i), i % 2 ? api::JobState::Failed : api::JobState::Queued);
    store.insert(job);
  }
  std::vector<std::string> seen;
  std::int64_t cursor = INT64_MAX;
  for (;;) {
    const auto page = store.list(std::nullopt, cursor, 3);
    for (const auto& job : page) seen.push_back(job.id);
    if (page.size() < 3) break;
    cursor = page.back().sequence;
  }
  EXPECT_EQ(seen,
            (std::vector<std::string>{"job6", "job5", "job4", "job3", "job2", "job1", "job0"}));
  EXPECT_EQ(store.list(api::JobState::Failed, INT64_MAX, 10).size(), 3u);
  const auto counts = store.countByState();
  EXPECT_EQ(counts.at(api::JobState::Queued), 4u);
  EXPECT_EQ(counts.at(api::JobState::Failed), 3u);
}

TEST(SqliteJobStore, UnfinishedAndExpiredQueriesSelectByStateAndTime) {
  TempDir dir;
  SqliteJobStore store(dir.path() / "jobs.sqlite");
  auto queued = makeJob("q");
  auto running = makeJob("r", api::JobState::Running);
  auto oldDone = makeJob("old", api::JobState::Succeeded);
  oldDone.finishedAt = 100.0;
  auto newDone = makeJob("new", api::JobState::Canceled);
  newDone.finishedAt = 900.0;
  for (auto* job : {&queued, &running, &oldDone, &newDone}) store.insert(*job);
  const auto unfinished = store.unfinished();
  ASSERT_EQ(unfinished.size(), 2u);
  EXPECT_EQ(unfinished[0].id, "q");  // acceptance order
  EXPECT_EQ(unfinished[1].id, "r");
  EXPECT_EQ(store.finishedBefore(500.0), std::vector<std::string>{"old"});
  store.remove("old");
  EXPECT_TRUE(store.finishedBefore(500.0).empty());
}

}  // namespace
}  // namespace hexcover::server::test
