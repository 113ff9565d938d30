#pragma once
// The embedded job store: one SQLite database (WAL, synchronous=FULL) in the data directory.
// Each record is a JSON document plus the indexed columns the queries need.

#include <filesystem>
#include <functional>
#include <mutex>

#include "server/job_store.h"

struct sqlite3;

namespace hexcover::server {

class SqliteJobStore final : public JobStore {
 public:
  /// Opens or creates the database file. Throws StoreError when it cannot.
  explicit SqliteJobStore(const std::filesystem::path& databaseFile);
  ~SqliteJobStore() override;
  SqliteJobStore(const SqliteJobStore&) = delete;
  SqliteJobStore& operator=(const SqliteJobStore&) = delete;

  bool insert(api::JobRecord& job) override;
  void update(const api::JobRecord& job) override;
  void remove(const std::string& id) override;
  std::optional<api::JobRecord> find(const std::string& id) const override;
  std::optional<api::JobRecord> findByIdempotencyKey(const std::string& key) const override;
  std::vector<api::JobRecord> list(std::optional<api::JobState> state, std::int64_t beforeSequence,
                                   std::size_t limit) const override;
  std::vector<api::JobRecord> unfinished() const override;
  std::vector<std::string> finishedBefore(double unixSeconds) const override;
  std::map<api::JobState, std::size_t> countByState() const override;

 private:
  class Statement;
  std::vector<api::JobRecord> query(const std::string& sql,
                                    const std::function<void(Statement&)>& bind) const;
  void execute(const char* sql) const;

  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;  ///< one connection, one statement at a time
};

}  // namespace hexcover::server
