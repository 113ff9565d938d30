#pragma once
// The job service: accepts uploads as jobs, keeps them in the durable store, runs them on a
// worker pool separate from the HTTP threads, and cancels, deletes and expires them.
// HTTP handlers call it and never run geometry themselves.
//
// Files under the data directory:   jobs.sqlite            job records (SqliteJobStore)
//                                   uploads/<random>.part  uploads being received
//                                   jobs/<id>/input.<fmt>  the accepted mesh
//                                   jobs/<id>/results/     result files of a succeeded job

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "api/job.h"
#include "server/engine.h"
#include "server/job_queue.h"
#include "server/job_store.h"
#include "server/log.h"
#include "server/memory_budget.h"
#include "server/service_metrics.h"

namespace hexcover::server {

struct JobServiceOptions {
  std::filesystem::path dataDir;
  int workers = 1;
  std::size_t queueLimit = 1000;
  double jobTimeLimitSeconds = 3600.0;
  double retentionSeconds = 7 * 86400.0;
  int maxAttempts = 3;
  /// What the running jobs may use together (memory_budget.h); > 0.
  double memoryBudgetMiB = 4096.0;
};

/// A job as clients see it: the stored record with the live stage and progress of a running
/// job, and the queue position of a queued one.
struct JobView {
  api::JobRecord job;
  std::optional<std::size_t> queuePosition;
};

/// A completely received upload, ready to become a job.
struct Submission {
  std::filesystem::path uploadFile;  ///< in uploadDir(); moved into the job's directory
  std::string format;                ///< detected by Engine::detectFormat
  std::string filename;              ///< as the client named it (may be empty)
  std::uint64_t bytes = 0;
  nlohmann::json options;      ///< normalized by Engine::normalizeOptions
  std::string idempotencyKey;  ///< empty when none
  std::string requestDigest;   ///< identifies options + body for idempotent replays
};

class JobService {
 public:
  JobService(JobServiceOptions options, JobStore& store, const Engine& engine,
             ServiceMetrics& metrics, const Log& log);
  /// Stops the workers (running jobs are requeued) and joins every thread.
  ~JobService();
  JobService(const JobService&) = delete;
  JobService& operator=(const JobService&) = delete;

  /// Recovers the store (queued jobs are queued again, running ones are re-run or, after
  /// maxAttempts interrupted runs, failed), removes leftover files, starts the workers and the
  /// retention sweeper.
  void start();

  /// Accepts an upload. Returns the new job, or the existing one when idempotencyKey was used
  /// before with the same digest (`replayed`). Throws ApiError: QueueFull, Unavailable while
  /// draining, IdempotencyMismatch when the key was used for another request.
  struct Accepted {
    api::JobRecord job;
    bool replayed = false;
  };
  Accepted submit(Submission submission);

  std::optional<JobView> find(const std::string& id) const;

  struct Page {
    std::vector<api::JobRecord> jobs;
    std::optional<std::int64_t> nextCursor;  ///< pass as `beforeSequence` for the next page
  };
  Page list(std::optional<api::JobState> state, std::int64_t beforeSequence,
            std::size_t limit) const;

  /// DELETE: a queued job is canceled, a running one is asked to stop (it ends canceled at its
  /// next cancellation check), a finished one is deleted with its files.
  enum class Removal { NotFound, Canceled, CancelRequested, Deleted };
  Removal cancelOrDelete(const std::string& id);

  /// Marks an Idempotency-Key as being received; false when it already is (409).
  bool beginReceiving(const std::string& idempotencyKey);
  void endReceiving(const std::string& idempotencyKey);

  /// True while the queue is at its bound.
  bool queueFull() const { return queue_.full(); }
  bool draining() const { return draining_; }

  /// SIGTERM: stop starting jobs, wait up to `grace` for running ones, then ask them to stop and
  /// put them back in the queue (durably, for the next start). Returns false when some worker
  /// did not stop even then (its job stays "running" in the store and is re-run at next start).
  bool drain(std::chrono::duration<double> grace);

  std::filesystem::path jobDir(const std::string& id) const;
  std::filesystem::path uploadDir() const;
  ServiceMetrics::Gauges gauges() const;

 private:
  struct ActiveJob;
  void workerLoop();
  void runJob(const std::string& id, JobQueue::Slot& slot);
  void sweepLoop();
  void recover();
  void expire(double now);
  void stopThreads();

  const JobServiceOptions options_;
  JobStore& store_;
  const Engine& engine_;
  ServiceMetrics& metrics_;
  const Log& log_;
  JobQueue queue_;
  MemoryBudget memory_;

  mutable std::mutex mutex_;      ///< guards job state transitions, active_, receiving_
  std::condition_variable idle_;  ///< notified when a job leaves active_
  std::map<std::string, std::shared_ptr<ActiveJob>> active_;
  std::set<std::string> receiving_;
  std::atomic<bool> draining_{false};
  bool stopping_ = false;  ///< guarded by mutex_; ends the sweeper
  std::condition_variable sweeperWake_;
  std::vector<std::thread> workers_;
  std::thread sweeper_;
};

/// Wall-clock time in Unix seconds.
double unixNow();

}  // namespace hexcover::server
