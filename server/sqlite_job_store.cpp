#include "server/sqlite_job_store.h"

#include <sqlite3.h>

#include <nlohmann/json.hpp>

namespace hexcover::server {

using api::JobRecord;
using api::JobState;

namespace {

nlohmann::json toStored(const JobRecord& job) {
  nlohmann::json results = nlohmann::json::array();
  for (const auto& r : job.results)
    results.push_back(
        {{"mesh", r.mesh}, {"format", r.format}, {"file", r.file}, {"bytes", r.bytes}});
  return {{"id", job.id},
          {"state", api::jobStateName(job.state)},
          {"stage", job.stage},
          {"progress", job.progress},
          {"options", job.options},
          {"input_format", job.inputFormat},
          {"input_filename", job.inputFilename},
          {"input_bytes", job.inputBytes},
          {"idempotency_key", job.idempotencyKey},
          {"request_digest", job.requestDigest},
          {"attempts", job.attempts},
          {"created_at", job.createdAt},
          {"started_at", job.startedAt},
          {"finished_at", job.finishedAt},
          {"input_report", job.inputReport},
          {"metrics", job.metrics},
          {"error", job.error},
          {"results", results}};
}

JobRecord fromStored(const nlohmann::json& doc, std::int64_t sequence) {
  JobRecord job;
  job.id = doc.at("id").get<std::string>();
  job.sequence = sequence;
  job.state = api::parseJobState(doc.at("state").get<std::string>()).value_or(JobState::Failed);
  job.stage = doc.value("stage", "");
  job.progress = doc.value("progress", 0.0);
  job.options = doc.value("options", nlohmann::json::object());
  job.inputFormat = doc.value("input_format", "");
  job.inputFilename = doc.value("input_filename", "");
  job.inputBytes = doc.value("input_bytes", std::uint64_t{0});
  job.idempotencyKey = doc.value("idempotency_key", "");
  job.requestDigest = doc.value("request_digest", "");
  job.attempts = doc.value("attempts", 0);
  job.createdAt = doc.value("created_at", 0.0);
  job.startedAt = doc.value("started_at", 0.0);
  job.finishedAt = doc.value("finished_at", 0.0);
  job.inputReport = doc.value("input_report", nlohmann::json());
  job.metrics = doc.value("metrics", nlohmann::json());
  job.error = doc.value("error", nlohmann::json());
  for (const auto& r : doc.value("results", nlohmann::json::array()))
    job.results.push_back({r.at("mesh").get<std::string>(), r.at("format").get<std::string>(),
                           r.at("file").get<std::string>(), r.value("bytes", std::uint64_t{0})});
  return job;
}

}  // namespace

/// A prepared statement that finalizes itself; errors name the SQLite message.
class SqliteJobStore::Statement {
 public:
  Statement(sqlite3* db, const std::string& sql) : db_(db) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK)
      throw StoreError(std::string("job store: cannot prepare statement: ") + sqlite3_errmsg(db));
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void bind(int index, const std::string& text) {
    check(sqlite3_bind_text(stmt_, index, text.c_str(), int(text.size()), SQLITE_TRANSIENT));
  }
  void bindNullable(int index, const std::string& text) {
    if (text.empty())
      check(sqlite3_bind_null(stmt_, index));
    else
      bind(index, text);
  }
  void bind(int index, std::int64_t value) { check(sqlite3_bind_int64(stmt_, index, value)); }
  void bind(int index, double value) { check(sqlite3_bind_double(stmt_, index, value)); }

  /// Steps once: true when a row is available, false when done. Throws on errors; a UNIQUE
  /// violation is reported through `constraintViolated` when given.
  bool step(bool* constraintViolated = nullptr) {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    if (constraintViolated && rc == SQLITE_CONSTRAINT) {
      *constraintViolated = true;
      return false;
    }
    throw StoreError(std::string("job store: ") + sqlite3_errmsg(db_));
  }
  std::int64_t integer(int column) const { return sqlite3_column_int64(stmt_, column); }
  std::string text(int column) const {
    const auto* p = sqlite3_column_text(stmt_, column);
    return p ? std::string(reinterpret_cast<const char*>(p), sqlite3_column_bytes(stmt_, column))
             : std::string();
  }

 private:
  void check(int rc) const {
    if (rc != SQLITE_OK) throw StoreError(std::string("job store: ") + sqlite3_errmsg(db_));
  }
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

SqliteJobStore::SqliteJobStore(const std::filesystem::path& databaseFile) {
  if (sqlite3_open_v2(databaseFile.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE,
                      nullptr) != SQLITE_OK) {
    const std::string message = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    throw StoreError("cannot open job store " + databaseFile.string() + ": " + message);
  }
  sqlite3_busy_timeout(db_, 5000);
  try {
    execute("PRAGMA journal_mode=WAL");
    execute("PRAGMA synchronous=FULL");
    execute(
        "CREATE TABLE IF NOT EXISTS jobs ("
        " sequence INTEGER PRIMARY KEY AUTOINCREMENT,"
        " id TEXT NOT NULL UNIQUE,"
        " state TEXT NOT NULL,"
        " idempotency_key TEXT UNIQUE,"
        " finished_at REAL NOT NULL DEFAULT 0,"
        " record TEXT NOT NULL)");
    execute("CREATE INDEX IF NOT EXISTS jobs_state ON jobs(state, sequence)");
  } catch (...) {
    sqlite3_close(db_);
    throw;
  }
}

SqliteJobStore::~SqliteJobStore() { sqlite3_close(db_); }

void SqliteJobStore::execute(const char* sql) const {
  char* message = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string text = message ? message : "unknown error";
    sqlite3_free(message);
    throw StoreError("job store: " + text);
  }
}

bool SqliteJobStore::insert(JobRecord& job) {
  const std::lock_guard lock(mutex_);
  Statement stmt(db_,
                 "INSERT INTO jobs (id, state, idempotency_key, finished_at, record) "
                 "VALUES (?, ?, ?, ?, ?)");
  stmt.bind(1, job.id);
  stmt.bind(2, std::string(api::jobStateName(job.state)));
  stmt.bindNullable(3, job.idempotencyKey);
  stmt.bind(4, job.finishedAt);
  stmt.bind(5, toStored(job).dump());
  bool duplicate = false;
  stmt.step(&duplicate);
  if (duplicate) return false;
  job.sequence = sqlite3_last_insert_rowid(db_);
  return true;
}

void SqliteJobStore::update(const JobRecord& job) {
  const std::lock_guard lock(mutex_);
  Statement stmt(db_, "UPDATE jobs SET state = ?, finished_at = ?, record = ? WHERE id = ?");
  stmt.bind(1, std::string(api::jobStateName(job.state)));
  stmt.bind(2, job.finishedAt);
  stmt.bind(3, toStored(job).dump());
  stmt.bind(4, job.id);
  stmt.step();
}

void SqliteJobStore::remove(const std::string& id) {
  const std::lock_guard lock(mutex_);
  Statement stmt(db_, "DELETE FROM jobs WHERE id = ?");
  stmt.bind(1, id);
  stmt.step();
}

std::vector<JobRecord> SqliteJobStore::query(const std::string& sql,
                                             const std::function<void(Statement&)>& bind) const {
  const std::lock_guard lock(mutex_);
  Statement stmt(db_, sql);
  bind(stmt);
  std::vector<JobRecord> jobs;
  while (stmt.step()) {
    try {
      jobs.push_back(fromStored(nlohmann::json::parse(stmt.text(1)), stmt.integer(0)));
    } catch (const nlohmann::json::exception& e) {
      throw StoreError(std::string("job store: corrupt record: ") + e.what());
    }
  }
  return jobs;
}

std::optional<JobRecord> SqliteJobStore::find(const std::string& id) const {
  auto jobs =
      query("SELECT sequence, record FROM jobs WHERE id = ?", [&](Statement& s) { s.bind(1, id); });
  if (jobs.empty()) return std::nullopt;
  return std::move(jobs.front());
}

std::optional<JobRecord> SqliteJobStore::findByIdempotencyKey(const std::string& key) const {
  auto jobs = query("SELECT sequence, record FROM jobs WHERE idempotency_key = ?",
                    [&](Statement& s) { s.bind(1, key); });
  if (jobs.empty()) return std::nullopt;
  return std::move(jobs.front());
}

std::vector<JobRecord> SqliteJobStore::list(std::optional<JobState> state,
                                            std::int64_t beforeSequence, std::size_t limit) const {
  if (state)
    return query(
        "SELECT sequence, record FROM jobs WHERE state = ? AND sequence < ? "
        "ORDER BY sequence DESC LIMIT ?",
        [&](Statement& s) {
          s.bind(1, std::string(api::jobStateName(*state)));
          s.bind(2, beforeSequence);
          s.bind(3, std::int64_t(limit));
        });
  return query(
      "SELECT sequence, record FROM jobs WHERE sequence < ? ORDER BY sequence DESC LIMIT ?",
      [&](Statement& s) {
        s.bind(1, beforeSequence);
        s.bind(2, std::int64_t(limit));
      });
}

std::vector<JobRecord> SqliteJobStore::unfinished() const {
  return query(
      "SELECT sequence, record FROM jobs WHERE state IN ('queued', 'running') ORDER BY sequence",
      [](Statement&) {});
}

std::vector<std::string> SqliteJobStore::finishedBefore(double unixSeconds) const {
  const auto jobs = query(
      "SELECT sequence, record FROM jobs WHERE state IN ('succeeded', 'failed', 'canceled') "
      "AND finished_at < ?",
      [&](Statement& s) { s.bind(1, unixSeconds); });
  std::vector<std::string> ids;
  for (const auto& job : jobs) ids.push_back(job.id);
  return ids;
}

std::map<JobState, std::size_t> SqliteJobStore::countByState() const {
  const std::lock_guard lock(mutex_);
  Statement stmt(db_, "SELECT state, COUNT(*) FROM jobs GROUP BY state");
  std::map<JobState, std::size_t> counts;
  while (stmt.step())
    if (const auto state = api::parseJobState(stmt.text(0)))
      counts[*state] = std::size_t(stmt.integer(1));
  return counts;
}

}  // namespace hexcover::server
