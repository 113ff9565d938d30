#pragma once
// Durable job records. The embedded default is SqliteJobStore; a store shared by several
// machines (Redis, say) implements the same interface. Mesh files live beside it (JobFiles).

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "api/job.h"

namespace hexcover::server {

/// The store could not read or write (disk full, corrupt database). Reported as 500.
class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class JobStore {
 public:
  virtual ~JobStore() = default;

  /// Persists a new job and assigns job.sequence (increasing in acceptance order). Once this
  /// returns, the job survives a crash. Returns false, storing nothing, when another job already
  /// holds job.idempotencyKey.
  virtual bool insert(api::JobRecord& job) = 0;
  /// Replaces the stored record of job.id (durably).
  virtual void update(const api::JobRecord& job) = 0;
  /// Deletes the record of `id` (no-op when absent).
  virtual void remove(const std::string& id) = 0;

  virtual std::optional<api::JobRecord> find(const std::string& id) const = 0;
  virtual std::optional<api::JobRecord> findByIdempotencyKey(const std::string& key) const = 0;
  /// Up to `limit` jobs, newest first, with sequence < `beforeSequence` (a page cursor; use
  /// INT64_MAX for the first page), in `state` when given.
  virtual std::vector<api::JobRecord> list(std::optional<api::JobState> state,
                                           std::int64_t beforeSequence,
                                           std::size_t limit) const = 0;
  /// Queued and running jobs, oldest first (what a restart must run).
  virtual std::vector<api::JobRecord> unfinished() const = 0;
  /// Ids of finished jobs that finished before `unixSeconds`.
  virtual std::vector<std::string> finishedBefore(double unixSeconds) const = 0;
  /// Number of stored jobs in each state.
  virtual std::map<api::JobState, std::size_t> countByState() const = 0;
};

}  // namespace hexcover::server
