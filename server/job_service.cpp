#include "server/job_service.h"

#include <algorithm>
#include <random>

#include "api/problem.h"

namespace hexcover::server {

namespace fs = std::filesystem;
using api::JobRecord;
using api::JobState;

namespace {

std::string newJobId() {
  std::random_device device;
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id;
  for (int i = 0; i < 4; ++i) {
    auto word = device();
    for (int k = 0; k < 8; ++k, word >>= 4) id += kHex[word & 15u];
  }
  return id;
}

/// Removes a directory tree, ignoring errors (a leftover is removed at the next start).
void removeTree(const fs::path& dir) {
  std::error_code ignored;
  fs::remove_all(dir, ignored);
}

}  // namespace

double unixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

/// What a worker and the HTTP threads share about a running job.
struct JobService::ActiveJob {
  std::atomic<bool> cancel{false};    ///< DELETE asked to stop
  std::atomic<bool> requeue{false};   ///< drain asked to stop and requeue
  std::atomic<bool> timedOut{false};  ///< the time limit passed
  mutable std::mutex mutex;
  std::string stage;
  double progress = 0.0;
};

JobService::JobService(JobServiceOptions options, JobStore& store, const Engine& engine,
                       ServiceMetrics& metrics, const Log& log)
    : options_(std::move(options)),
      store_(store),
      engine_(engine),
      metrics_(metrics),
      log_(log),
      queue_(options_.queueLimit, options_.workers),
      memory_(options_.memoryBudgetMiB) {}

JobService::~JobService() {
  if (!workers_.empty() && !draining_) drain(std::chrono::seconds(0));
  stopThreads();
}

fs::path JobService::jobDir(const std::string& id) const { return options_.dataDir / "jobs" / id; }
fs::path JobService::uploadDir() const { return options_.dataDir / "uploads"; }

void JobService::start() {
  fs::create_directories(options_.dataDir / "jobs");
  removeTree(uploadDir());  // partial uploads of a previous run
  fs::create_directories(uploadDir());
  recover();
  // Two threads per slot: the second takes a queued job while the first one's waits for memory.
  for (int i = 0; i < 2 * queue_.slots(); ++i) workers_.emplace_back([this] { workerLoop(); });
  sweeper_ = std::thread([this] { sweepLoop(); });
  log_.info("job_service_started", {{"workers", queue_.slots()}, {"queued", queue_.size()}});
}

void JobService::recover() {
  for (auto& job : store_.unfinished()) {
    if (job.state == JobState::Running && job.attempts >= options_.maxAttempts) {
      job.state = JobState::Failed;
      job.finishedAt = unixNow();
      job.stage.clear();
      job.error = api::problemDocument(api::ProblemKind::UnprocessableMesh,
                                       "the server stopped " + std::to_string(job.attempts) +
                                           " times while this job ran; it is not run again",
                                       {{"code", "interrupted"}});
      store_.update(job);
      log_.warn("job_failed",
                {{"job", job.id}, {"reason", "interrupted"}, {"attempts", job.attempts}});
      continue;
    }
    if (job.state == JobState::Running) {
      log_.info("job_requeued", {{"job", job.id}, {"attempts", job.attempts}});
      job.state = JobState::Queued;
      job.stage.clear();
      job.progress = 0.0;
      job.startedAt = 0.0;
      store_.update(job);
    }
    queue_.restore(job.id);
  }
  // Directories without a record: a crash between receiving and storing, or during a delete.
  for (const auto& entry : fs::directory_iterator(options_.dataDir / "jobs"))
    if (entry.is_directory() && !store_.find(entry.path().filename().string()))
      removeTree(entry.path());
}

JobService::Accepted JobService::submit(Submission submission) {
  if (draining_)
    throw api::ApiError(api::ProblemKind::Unavailable, "the server is shutting down; retry later");
  JobRecord job;
  job.id = newJobId();
  job.state = JobState::Queued;
  job.options = std::move(submission.options);
  job.inputFormat = submission.format;
  job.inputFilename = submission.filename;
  job.inputBytes = submission.bytes;
  job.idempotencyKey = submission.idempotencyKey;
  job.requestDigest = submission.requestDigest;
  job.createdAt = unixNow();

  const fs::path dir = jobDir(job.id);
  fs::create_directories(dir);
  fs::rename(submission.uploadFile, dir / ("input." + job.inputFormat));

  const std::lock_guard lock(mutex_);
  if (queue_.full()) {
    removeTree(dir);
    throw api::ApiError(api::ProblemKind::QueueFull, "the queue holds its limit of " +
                                                         std::to_string(options_.queueLimit) +
                                                         " jobs; retry later");
  }
  if (!store_.insert(job)) {  // the Idempotency-Key is taken
    removeTree(dir);
    auto existing = store_.findByIdempotencyKey(job.idempotencyKey);
    if (!existing)
      throw api::ApiError(api::ProblemKind::Conflict,
                          "the Idempotency-Key was just released; retry");
    if (existing->requestDigest != job.requestDigest)
      throw api::ApiError(api::ProblemKind::IdempotencyMismatch,
                          "Idempotency-Key '" + job.idempotencyKey +
                              "' was used for a request with another body or other options",
                          {{"job", existing->id}});
    return {std::move(*existing), true};
  }
  queue_.push(job.id);
  metrics_.addUploadedBytes(job.inputBytes);
  log_.info("job_accepted", {{"job", job.id},
                             {"format", job.inputFormat},
                             {"bytes", job.inputBytes},
                             {"options", job.options}});
  return {std::move(job), false};
}

std::optional<JobView> JobService::find(const std::string& id) const {
  auto job = store_.find(id);
  if (!job) return std::nullopt;
  JobView view{std::move(*job), std::nullopt};
  if (view.job.state == JobState::Queued) view.queuePosition = queue_.position(id);
  if (view.job.state == JobState::Running) {
    const std::lock_guard lock(mutex_);
    if (const auto it = active_.find(id); it != active_.end()) {
      const std::lock_guard progressLock(it->second->mutex);
      view.job.stage = it->second->stage;
      view.job.progress = it->second->progress;
    }
  }
  return view;
}

JobService::Page JobService::list(std::optional<JobState> state, std::int64_t beforeSequence,
                                  std::size_t limit) const {
  Page page;
  page.jobs = store_.list(state, beforeSequence, limit + 1);
  if (page.jobs.size() > limit) {
    page.jobs.resize(limit);
    page.nextCursor = page.jobs.back().sequence;
  }
  return page;
}

JobService::Removal JobService::cancelOrDelete(const std::string& id) {
  const std::lock_guard lock(mutex_);
  auto job = store_.find(id);
  if (!job) return Removal::NotFound;
  switch (job->state) {
    case JobState::Queued:
      queue_.remove(id);
      job->state = JobState::Canceled;
      job->finishedAt = unixNow();
      store_.update(*job);
      metrics_.recordJobFinished(JobState::Canceled, 0.0);
      log_.info("job_canceled", {{"job", id}, {"while", "queued"}});
      return Removal::Canceled;
    case JobState::Running:
      if (const auto it = active_.find(id); it != active_.end()) it->second->cancel = true;
      log_.info("job_cancel_requested", {{"job", id}});
      return Removal::CancelRequested;
    default:
      store_.remove(id);
      removeTree(jobDir(id));
      log_.info("job_deleted", {{"job", id}});
      return Removal::Deleted;
  }
}

bool JobService::beginReceiving(const std::string& idempotencyKey) {
  const std::lock_guard lock(mutex_);
  return receiving_.insert(idempotencyKey).second;
}

void JobService::endReceiving(const std::string& idempotencyKey) {
  const std::lock_guard lock(mutex_);
  receiving_.erase(idempotencyKey);
}

void JobService::workerLoop() {
  while (auto taken = queue_.pop()) {
    try {
      runJob(taken->id, taken->slot);
    } catch (const std::exception& e) {  // the store failed: log, keep the worker alive
      log_.error("worker_error", {{"job", taken->id}, {"error", e.what()}});
    }
  }
}

void JobService::runJob(const std::string& id, JobQueue::Slot& slot) {
  JobRecord job;
  const auto active = std::make_shared<ActiveJob>();
  {
    const std::lock_guard lock(mutex_);
    auto stored = store_.find(id);
    if (!stored || stored->state != JobState::Queued) return;  // canceled or deleted meanwhile
    job = std::move(*stored);
    job.state = JobState::Running;
    job.startedAt = unixNow();
    job.finishedAt = 0.0;
    job.attempts += 1;
    job.stage = "starting";
    job.progress = 0.0;
    job.error = nullptr;
    store_.update(job);
    active->stage = job.stage;
    active_[id] = active;
  }
  log_.info("job_started", {{"job", id}, {"attempt", job.attempts}});

  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration<double>(options_.jobTimeLimitSeconds);
  // Returned when the job ends, whatever way.
  MemoryBudget::Share memory(memory_);
  RunContext context;
  context.progress = [active](std::string_view stage, double fraction) {
    const std::lock_guard lock(active->mutex);
    active->stage = stage;
    active->progress = std::clamp(fraction, 0.0, 1.0);
  };
  context.cancelRequested = [active, deadline] {
    if (std::chrono::steady_clock::now() > deadline) active->timedOut = true;
    return active->cancel || active->requeue || active->timedOut;
  };
  // While it waits for its memory (the budget polls), the job's stage says so, and its slot
  // runs a queued job.
  context.peakMemory = [&memory, &context, &slot, active](double mib) {
    bool waited = false;
    memory.raise(mib, [&] {
      if (!waited) {
        waited = true;
        slot.suspend();
        const std::lock_guard lock(active->mutex);
        active->stage = "memory";
      }
      context.throwIfCanceled();
    });
    if (waited) slot.resume();
  };

  const fs::path dir = jobDir(id);
  const fs::path resultDir = dir / "results";
  removeTree(resultDir);  // a previous, interrupted attempt
  fs::create_directories(resultDir);
  const JobInput input{dir / ("input." + job.inputFormat), job.inputFormat, job.options, resultDir};

  bool requeue = false;
  try {
    JobOutcome outcome = engine_.run(input, context);
    job.state = JobState::Succeeded;
    job.progress = 1.0;
    job.inputReport = std::move(outcome.inputReport);
    job.metrics = std::move(outcome.metrics);
    job.results = std::move(outcome.results);
    for (auto& result : job.results) result.bytes = fs::file_size(resultDir / result.file);
  } catch (const RefusedInput& e) {
    job.state = JobState::Failed;
    job.inputReport = e.report();
    job.error = api::problemDocument(api::problemKindFor(e.code()), e.what(),
                                     {{"code", errorCodeName(e.code())}, {"report", e.report()}});
  } catch (const Error& e) {
    if (e.code() == ErrorCode::Canceled && active->timedOut && !active->cancel) {
      job.state = JobState::Failed;
      job.error = api::problemDocument(api::ProblemKind::UnprocessableMesh,
                                       "the job did not finish within the time limit of " +
                                           std::to_string(int(options_.jobTimeLimitSeconds)) + " s",
                                       {{"code", "time_limit"}});
    } else if (e.code() == ErrorCode::Canceled && active->requeue && !active->cancel) {
      requeue = true;
    } else if (e.code() == ErrorCode::Canceled) {
      job.state = JobState::Canceled;
    } else {
      job.state = JobState::Failed;
      job.error = api::problemDocument(e);
    }
  } catch (const std::exception& e) {
    job.state = JobState::Failed;
    job.error = api::problemDocument(api::ProblemKind::Internal, e.what());
    log_.error("job_exception", {{"job", id}, {"error", e.what()}});
  }

  const double runSeconds = unixNow() - job.startedAt;
  // Counted before the final state is stored, so that a client that sees the job finished also
  // sees it in /metrics (outside mutex_: the metrics' gauges take it).
  if (!requeue) metrics_.recordJobFinished(job.state, runSeconds);
  {
    const std::lock_guard lock(mutex_);
    active_.erase(id);
    job.stage.clear();
    if (requeue) {  // back to the queue of the next start; this run does not count
      job.state = JobState::Queued;
      job.progress = 0.0;
      job.startedAt = 0.0;
      job.attempts -= 1;
    } else {
      job.finishedAt = unixNow();
    }
    store_.update(job);
  }
  idle_.notify_all();
  if (job.state != JobState::Succeeded) removeTree(resultDir);
  if (requeue) {
    log_.info("job_requeued", {{"job", id}, {"reason", "shutdown"}});
    return;
  }
  nlohmann::json fields = {
      {"job", id}, {"state", api::jobStateName(job.state)}, {"seconds", runSeconds}};
  if (!job.error.is_null()) fields["error"] = job.error.value("detail", "");
  log_.info("job_finished", fields);
}

void JobService::sweepLoop() {
  const auto interval =
      std::chrono::duration<double>(std::clamp(options_.retentionSeconds / 4.0, 0.25, 60.0));
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    sweeperWake_.wait_for(lock, interval);
    if (stopping_) break;
    lock.unlock();
    try {
      expire(unixNow());
    } catch (const std::exception& e) {
      log_.error("retention_error", {{"error", e.what()}});
    }
    lock.lock();
  }
}

void JobService::expire(double now) {
  for (const auto& id : store_.finishedBefore(now - options_.retentionSeconds)) {
    const std::lock_guard lock(mutex_);
    store_.remove(id);
    removeTree(jobDir(id));
    log_.info("job_expired", {{"job", id}});
  }
}

bool JobService::drain(std::chrono::duration<double> grace) {
  draining_ = true;
  queue_.close();
  std::unique_lock lock(mutex_);
  log_.info("drain_started", {{"running", active_.size()}, {"grace_seconds", grace.count()}});
  idle_.wait_for(lock, grace, [&] { return active_.empty(); });
  for (auto& [id, job] : active_) job->requeue = true;
  const bool stopped =
      idle_.wait_for(lock, std::chrono::seconds(10), [&] { return active_.empty(); });
  if (!stopped) log_.warn("drain_incomplete", {{"running", active_.size()}});
  return stopped;
}

void JobService::stopThreads() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  sweeperWake_.notify_all();
  queue_.close();
  for (auto& worker : workers_)
    if (worker.joinable()) worker.join();
  workers_.clear();
  if (sweeper_.joinable()) sweeper_.join();
}

ServiceMetrics::Gauges JobService::gauges() const {
  ServiceMetrics::Gauges g;
  g.queueDepth = queue_.size();
  g.workers = queue_.slots();
  g.memoryBudgetMiB = memory_.totalMiB();
  g.memoryReservedMiB = memory_.reservedMiB();
  g.busyWorkers = queue_.busySlots();
  g.jobsByState = store_.countByState();
  g.ready = !draining_;
  return g;
}

}  // namespace hexcover::server
