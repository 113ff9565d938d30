#pragma once
// The job resource of the HTTP API: what the server stores about one remeshing job and what
// GET /v1/jobs/{id} shows. Plain data; the store persists it, job_json.h renders it.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hexcover::api {

/// Life cycle: queued -> running -> succeeded | failed | canceled. A running job that the server
/// could not finish (crash, shutdown) goes back to queued.
enum class JobState { Queued, Running, Succeeded, Failed, Canceled };

/// "queued", "running", "succeeded", "failed", "canceled".
const char* jobStateName(JobState state);
/// Inverse of jobStateName; nullopt for any other text.
std::optional<JobState> parseJobState(std::string_view name);
/// True for succeeded, failed and canceled.
inline bool isFinished(JobState state) {
  return state == JobState::Succeeded || state == JobState::Failed || state == JobState::Canceled;
}

/// One downloadable result file of a job, written by the worker when the job succeeds.
struct ResultFile {
  std::string mesh;    ///< "triangles", "hexagons" or "textured"
  std::string format;  ///< "obj", "ply", "off", "stl" or "glb"
  std::string file;    ///< file name inside the job's directory
  std::uint64_t bytes = 0;
};

/// Everything the server knows about a job. Times are Unix seconds (0 = not yet).
struct JobRecord {
  std::string id;             ///< 32 lowercase hex digits, random
  std::int64_t sequence = 0;  ///< acceptance order (FIFO key of the queue)
  JobState state = JobState::Queued;
  std::string stage;      ///< pipeline stage now running (empty when not running)
  double progress = 0.0;  ///< fraction of the whole job done, in [0, 1]
  nlohmann::json options = nlohmann::json::object();  ///< the normalized remesh options
  std::string inputFormat;    ///< "obj", "off", "ply" or "stl", detected from the bytes
  std::string inputFilename;  ///< file name given by the client (may be empty)
  std::uint64_t inputBytes = 0;
  std::string idempotencyKey;  ///< empty when the client sent none
  std::string requestDigest;   ///< SHA-256 of options and body (idempotency replay check)
  int attempts = 0;            ///< runs started (a crash or restart re-runs the job)
  double createdAt = 0.0;
  double startedAt = 0.0;
  double finishedAt = 0.0;
  nlohmann::json inputReport;  ///< the input's validation/repair report (null until known)
  nlohmann::json metrics;      ///< the quality metrics document (null until succeeded)
  nlohmann::json error;        ///< problem document when failed (null otherwise)
  std::vector<ResultFile> results;
};

/// The result file for (mesh, format), or nullptr.
const ResultFile* findResult(const JobRecord& job, std::string_view mesh, std::string_view format);

}  // namespace hexcover::api
