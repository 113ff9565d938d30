#pragma once
// What the job service asks of the geometry library, and nothing more: the server never sees
// geometry types, the engine never sees HTTP or jobs (OSRM's split of transport and engine).
// main.cpp binds the real engine (pipeline_engine.h: hexcover::remesh and the mesh writers);
// the server's unit tests bind a stub.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "api/job.h"
#include "core/common/run_context.h"

namespace hexcover::server {

/// One run of the engine: the uploaded mesh on disk, its options, where the results go.
struct JobInput {
  std::filesystem::path meshFile;   ///< the upload, as received
  std::string format;               ///< detected input format ("obj", "off", "ply", "stl")
  nlohmann::json options;           ///< normalized options (Engine::normalizeOptions)
  std::filesystem::path outputDir;  ///< existing, empty directory for the result files
};

/// What a successful run produced.
struct JobOutcome {
  nlohmann::json inputReport;            ///< validation/repair report of the input
  nlohmann::json metrics;                ///< quality metrics document
  std::vector<api::ResultFile> results;  ///< files written into JobInput::outputDir
};

/// A mesh refused by validation, with the report that names the defect (reported as 422).
class RefusedInput : public Error {
 public:
  RefusedInput(const Error& error, nlohmann::json report)
      : Error(error.code(), error.what()), report_(std::move(report)) {}
  const nlohmann::json& report() const { return report_; }

 private:
  nlohmann::json report_;
};

/// A remeshing engine. Implementations must be thread-safe: workers call run() concurrently.
class Engine {
 public:
  virtual ~Engine() = default;

  /// Checks the options a client asked for (a JSON object merged from the query string and the
  /// `options` part) and returns them with every default filled in. Throws
  /// hexcover::Error(InvalidOption) naming the first bad option.
  virtual nlohmann::json normalizeOptions(const nlohmann::json& requested) const = 0;

  /// Mesh format of an upload from its first bytes ("obj", "off", "ply", "stl"); throws
  /// hexcover::Error(UnknownFormat) when the bytes are none of them. `head` holds at least the
  /// first 4 KiB of the upload (less when the upload is shorter).
  virtual std::string detectFormat(std::string_view head) const = 0;

  /// Remeshes `input` and writes the result files. Reports progress and honours cancellation
  /// through `context`. Throws RefusedInput when validation refuses the mesh, hexcover::Error for
  /// other expected failures (Canceled when canceled).
  virtual JobOutcome run(const JobInput& input, const RunContext& context) const = 0;
};

}  // namespace hexcover::server
