// The job document: states round-trip, times are RFC 3339, queue position and links follow the
// state, timings measure the right intervals.

#include "api/job_json.h"

#include <gtest/gtest.h>

namespace hexcover::api {
namespace {

TEST(JobJson, StateNamesRoundTrip) {
  for (const auto state : {JobState::Queued, JobState::Running, JobState::Succeeded,
                           JobState::Failed, JobState::Canceled})
    EXPECT_EQ(parseJobState(jobStateName(state)), state);
  EXPECT_FALSE(parseJobState("done"));
  EXPECT_FALSE(isFinished(JobState::Running));
  EXPECT_TRUE(isFinished(JobState::Canceled));
}

TEST(JobJson, TimesAreRfc3339Utc) {
  EXPECT_EQ(rfc3339(0.0), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(rfc3339(1700000000.25), "2023-11-14T22:13:20.250Z");
}

TEST(JobJson, QueuedJobShowsItsPositionAndNoResults) {
  JobRecord job;
  job.id = "abc";
  job.createdAt = 100.0;
  const auto doc = jobDocument(job, 3, 104.0);
  EXPECT_EQ(doc.at("state"), "queued");
  EXPECT_EQ(doc.at("queue_position"), 3);
  EXPECT_TRUE(doc.at("started_at").is_null());
  EXPECT_DOUBLE_EQ(doc.at("timings").at("queued_seconds").get<double>(), 4.0);
  EXPECT_FALSE(doc.at("timings").contains("run_seconds"));
  EXPECT_EQ(doc.at("links").at("self"), "/v1/jobs/abc");
  EXPECT_TRUE(doc.at("links").at("results").empty());
  EXPECT_FALSE(doc.at("links").contains("metrics"));
}

TEST(JobJson, SucceededJobLinksItsMetricsAndEveryResult) {
  JobRecord job;
  job.id = "abc";
  job.state = JobState::Succeeded;
  job.createdAt = 100.0;
  job.startedAt = 101.0;
  job.finishedAt = 111.0;
  job.results = {{"triangles", "obj", "triangles.obj", 10},
                 {"hexagons", "glb", "hexagons.glb", 20}};
  const auto doc = jobDocument(job, std::nullopt, 500.0);
  EXPECT_TRUE(doc.at("queue_position").is_null());
  EXPECT_DOUBLE_EQ(doc.at("timings").at("queued_seconds").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(doc.at("timings").at("run_seconds").get<double>(), 10.0);
  EXPECT_EQ(doc.at("links").at("metrics"), "/v1/jobs/abc/metrics");
  ASSERT_EQ(doc.at("links").at("results").size(), 2u);
  EXPECT_EQ(doc.at("links").at("results")[1].at("href"),
            "/v1/jobs/abc/result?format=glb&mesh=hexagons");
  EXPECT_EQ(findResult(job, "hexagons", "glb")->bytes, 20u);
  EXPECT_EQ(findResult(job, "hexagons", "obj"), nullptr);
}

}  // namespace
}  // namespace hexcover::api
