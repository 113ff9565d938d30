#include "api/job_json.h"

#include <algorithm>
#include <cmath>
#include <ctime>

namespace hexcover::api {

namespace {

constexpr const char* kStateNames[] = {"queued", "running", "succeeded", "failed", "canceled"};

nlohmann::json timeOrNull(double unixSeconds) {
  return unixSeconds > 0.0 ? nlohmann::json(rfc3339(unixSeconds)) : nlohmann::json(nullptr);
}

}  // namespace

const char* jobStateName(JobState state) { return kStateNames[static_cast<int>(state)]; }

std::optional<JobState> parseJobState(std::string_view name) {
  for (int i = 0; i < 5; ++i)
    if (name == kStateNames[i]) return static_cast<JobState>(i);
  return std::nullopt;
}

const ResultFile* findResult(const JobRecord& job, std::string_view mesh, std::string_view format) {
  const auto it = std::find_if(job.results.begin(), job.results.end(), [&](const ResultFile& r) {
    return r.mesh == mesh && r.format == format;
  });
  return it == job.results.end() ? nullptr : &*it;
}

std::string rfc3339(double unixSeconds) {
  const auto whole = static_cast<std::time_t>(std::floor(unixSeconds));
  const int millis = std::clamp(static_cast<int>((unixSeconds - whole) * 1000.0), 0, 999);
  std::tm utc{};
  gmtime_r(&whole, &utc);
  char text[40];
  std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", utc.tm_year + 1900,
                utc.tm_mon + 1, utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, millis);
  return text;
}

std::string jobPath(const std::string& id) { return "/v1/jobs/" + id; }

nlohmann::json jobDocument(const JobRecord& job, std::optional<std::size_t> queuePosition,
                           double now) {
  const std::string self = jobPath(job.id);
  nlohmann::json results = nlohmann::json::array();
  for (const auto& r : job.results)
    results.push_back({{"mesh", r.mesh},
                       {"format", r.format},
                       {"bytes", r.bytes},
                       {"href", self + "/result?format=" + r.format + "&mesh=" + r.mesh}});
  nlohmann::json links = {{"self", self}, {"results", results}};
  if (job.state == JobState::Succeeded) links["metrics"] = self + "/metrics";

  // A job leaves the queue when it starts, or when it is canceled before starting.
  const double leftQueue =
      job.startedAt > 0.0 ? job.startedAt : (job.finishedAt > 0.0 ? job.finishedAt : now);
  const double queuedSeconds = std::max(0.0, leftQueue - job.createdAt);
  nlohmann::json timings = {{"queued_seconds", queuedSeconds}};
  if (job.startedAt > 0.0)
    timings["run_seconds"] =
        std::max(0.0, (job.finishedAt > 0.0 ? job.finishedAt : now) - job.startedAt);

  nlohmann::json doc = {
      {"id", job.id},
      {"state", jobStateName(job.state)},
      {"stage", job.stage.empty() ? nlohmann::json(nullptr) : nlohmann::json(job.stage)},
      {"progress", job.progress},
      {"queue_position", queuePosition ? nlohmann::json(*queuePosition) : nlohmann::json(nullptr)},
      {"created_at", timeOrNull(job.createdAt)},
      {"started_at", timeOrNull(job.startedAt)},
      {"finished_at", timeOrNull(job.finishedAt)},
      {"timings", timings},
      {"attempts", job.attempts},
      {"options", job.options},
      {"input",
       {{"filename", job.inputFilename},
        {"format", job.inputFormat},
        {"bytes", job.inputBytes},
        {"report", job.inputReport}}},
      {"error", job.error},
      {"links", links},
  };
  return doc;
}

nlohmann::json jobSummary(const JobRecord& job) {
  return {{"id", job.id},
          {"state", jobStateName(job.state)},
          {"progress", job.progress},
          {"created_at", timeOrNull(job.createdAt)},
          {"href", jobPath(job.id)}};
}

}  // namespace hexcover::api
