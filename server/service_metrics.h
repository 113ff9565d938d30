#pragma once
// The service's own Prometheus metrics (text exposition format 0.0.4), in base units with
// _total/_seconds/_bytes suffixes. Labels are bounded sets (route templates, methods, statuses,
// job states); never a job id.

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "api/job.h"

namespace hexcover::server {

/// Cumulative histogram with fixed upper bounds (seconds).
class Histogram {
 public:
  explicit Histogram(std::vector<double> upperBounds);
  void observe(double value);
  /// Appends the _bucket, _sum and _count lines of `name` with `labels` ("" or `a="b",...`).
  void render(std::string& out, const std::string& name, const std::string& labels) const;

 private:
  std::vector<double> upperBounds_;
  std::vector<std::uint64_t> counts_;  ///< per bucket, not cumulative; last = +Inf
  double sum_ = 0.0;
  std::uint64_t count_ = 0;
};

class ServiceMetrics {
 public:
  /// Values read at scrape time from the queue, the workers and the store.
  struct Gauges {
    std::size_t queueDepth = 0;
    std::size_t busyWorkers = 0;
    std::size_t workers = 0;
    double memoryBudgetMiB = 0.0;    ///< what the running jobs may use together
    double memoryReservedMiB = 0.0;  ///< their estimated peaks, reserved (memory_budget.h)
    std::map<api::JobState, std::size_t> jobsByState;
    bool ready = false;
  };

  /// One answered HTTP request. `route` is the route template ("/v1/jobs/{id}"), or "unmatched".
  void recordRequest(std::string_view route, std::string_view method, int status, double seconds);
  /// One job that reached a final state after running for `runSeconds`.
  void recordJobFinished(api::JobState state, double runSeconds);
  /// Bytes of accepted uploads.
  void addUploadedBytes(std::uint64_t bytes);

  /// The whole exposition (Content-Type: text/plain; version=0.0.4).
  std::string exposition(const Gauges& gauges) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::tuple<std::string, std::string, int>, std::uint64_t> requests_;
  std::map<std::string, Histogram> requestDurations_;
  std::map<api::JobState, std::uint64_t> jobsFinished_;
  std::map<api::JobState, Histogram> jobDurations_;
  std::uint64_t uploadedBytes_ = 0;
};

}  // namespace hexcover::server
