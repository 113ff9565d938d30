#pragma once
// JSON documents of the job resource (GET /v1/jobs/{id}, the job list).

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "api/job.h"

namespace hexcover::api {

/// The job document: {id, state, stage, progress, queue_position (queued jobs only), created_at,
/// started_at, finished_at (RFC 3339, null when not yet), timings {queued_seconds, run_seconds},
/// options, input {filename, format, bytes, report}, attempts, error (problem document or null),
/// links {self, metrics, results[{mesh, format, href}]}}.
/// `queuePosition` is 0 for the next job to run. `now` (Unix seconds) measures unfinished
/// intervals.
nlohmann::json jobDocument(const JobRecord& job, std::optional<std::size_t> queuePosition,
                           double now);

/// A short entry of the job list: {id, state, progress, created_at, href}.
nlohmann::json jobSummary(const JobRecord& job);

/// RFC 3339 UTC text of Unix seconds with millisecond precision ("2026-11-22T01:02:03.456Z").
std::string rfc3339(double unixSeconds);

/// Path of a job resource ("/v1/jobs/<id>").
std::string jobPath(const std::string& id);

}  // namespace hexcover::api
