#include "server/service_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hexcover::server {

namespace {

const std::vector<double> kRequestBuckets = {0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1,
                                             0.25,  0.5,    1.0,   2.5,  5.0,   10.0};
const std::vector<double> kJobBuckets = {0.1,  0.25, 0.5,   1.0,   2.5,   5.0,    10.0,
                                         30.0, 60.0, 120.0, 300.0, 600.0, 1800.0, 3600.0};

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

void header(std::string& out, const char* name, const char* type, const char* help) {
  out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
}

}  // namespace

Histogram::Histogram(std::vector<double> upperBounds)
    : upperBounds_(std::move(upperBounds)), counts_(upperBounds_.size() + 1, 0) {}

void Histogram::observe(double value) {
  const auto bucket =
      std::lower_bound(upperBounds_.begin(), upperBounds_.end(), value) - upperBounds_.begin();
  ++counts_[std::size_t(bucket)];
  sum_ += value;
  ++count_;
}

void Histogram::render(std::string& out, const std::string& name, const std::string& labels) const {
  const std::string prefix = labels.empty() ? "" : labels + ",";
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i <= upperBounds_.size(); ++i) {
    cumulative += counts_[i];
    const std::string le = i < upperBounds_.size() ? number(upperBounds_[i]) : "+Inf";
    out += name + "_bucket{" + prefix + "le=\"" + le + "\"} " + std::to_string(cumulative) + "\n";
  }
  const std::string braces = labels.empty() ? "" : "{" + labels + "}";
  out += name + "_sum" + braces + " " + number(sum_) + "\n";
  out += name + "_count" + braces + " " + std::to_string(count_) + "\n";
}

void ServiceMetrics::recordRequest(std::string_view route, std::string_view method, int status,
                                   double seconds) {
  const std::lock_guard lock(mutex_);
  ++requests_[{std::string(route), std::string(method), status}];
  requestDurations_.try_emplace(std::string(route), kRequestBuckets).first->second.observe(seconds);
}

void ServiceMetrics::recordJobFinished(api::JobState state, double runSeconds) {
  const std::lock_guard lock(mutex_);
  ++jobsFinished_[state];
  jobDurations_.try_emplace(state, kJobBuckets).first->second.observe(runSeconds);
}

void ServiceMetrics::addUploadedBytes(std::uint64_t bytes) {
  const std::lock_guard lock(mutex_);
  uploadedBytes_ += bytes;
}

std::string ServiceMetrics::exposition(const Gauges& gauges) const {
  const std::lock_guard lock(mutex_);
  std::string out;
  header(out, "hexcover_http_requests_total", "counter",
         "HTTP requests answered, by route, method and status.");
  for (const auto& [key, count] : requests_) {
    const auto& [route, method, status] = key;
    out += "hexcover_http_requests_total{route=\"" + route + "\",method=\"" + method +
           "\",status=\"" + std::to_string(status) + "\"} " + std::to_string(count) + "\n";
  }
  header(out, "hexcover_http_request_duration_seconds", "histogram",
         "Time to answer an HTTP request (until the handler returns), by route.");
  for (const auto& [route, histogram] : requestDurations_)
    histogram.render(out, "hexcover_http_request_duration_seconds", "route=\"" + route + "\"");

  header(out, "hexcover_queue_jobs", "gauge", "Jobs waiting in the queue.");
  out += "hexcover_queue_jobs " + std::to_string(gauges.queueDepth) + "\n";
  header(out, "hexcover_jobs", "gauge", "Stored jobs by state.");
  for (const auto state : {api::JobState::Queued, api::JobState::Running, api::JobState::Succeeded,
                           api::JobState::Failed, api::JobState::Canceled}) {
    const auto it = gauges.jobsByState.find(state);
    out += std::string("hexcover_jobs{state=\"") + api::jobStateName(state) + "\"} " +
           std::to_string(it == gauges.jobsByState.end() ? 0 : it->second) + "\n";
  }
  header(out, "hexcover_jobs_finished_total", "counter",
         "Jobs that reached a final state since start.");
  for (const auto& [state, count] : jobsFinished_)
    out += std::string("hexcover_jobs_finished_total{state=\"") + api::jobStateName(state) +
           "\"} " + std::to_string(count) + "\n";
  header(out, "hexcover_job_duration_seconds", "histogram",
         "Run time of finished jobs, by final state.");
  for (const auto& [state, histogram] : jobDurations_)
    histogram.render(out, "hexcover_job_duration_seconds",
                     std::string("state=\"") + api::jobStateName(state) + "\"");

  header(out, "hexcover_workers_busy", "gauge", "Workers running a job.");
  out += "hexcover_workers_busy " + std::to_string(gauges.busyWorkers) + "\n";
  header(out, "hexcover_workers", "gauge", "Size of the worker pool.");
  out += "hexcover_workers " + std::to_string(gauges.workers) + "\n";
  constexpr double kBytesPerMiB = 1024.0 * 1024.0;
  header(out, "hexcover_memory_budget_bytes", "gauge",
         "Memory the running jobs may use together (--memory-budget).");
  out += "hexcover_memory_budget_bytes " +
         std::to_string(std::llround(gauges.memoryBudgetMiB * kBytesPerMiB)) + "\n";
  header(out, "hexcover_memory_reserved_bytes", "gauge",
         "Estimated peak memory of the running jobs, reserved from the budget.");
  out += "hexcover_memory_reserved_bytes " +
         std::to_string(std::llround(gauges.memoryReservedMiB * kBytesPerMiB)) + "\n";
  header(out, "hexcover_upload_bytes_total", "counter", "Bytes of accepted mesh uploads.");
  out += "hexcover_upload_bytes_total " + std::to_string(uploadedBytes_) + "\n";
  header(out, "hexcover_ready", "gauge",
         "1 when the server accepts new jobs, 0 while starting or draining.");
  out += std::string("hexcover_ready ") + (gauges.ready ? "1" : "0") + "\n";
  return out;
}

}  // namespace hexcover::server
