#include "server/pipeline_engine.h"

#include <algorithm>
#include <map>
#include <mutex>

#include "api/mesh_report_json.h"
#include "api/metrics_json.h"
#include "api/options_json.h"
#include "core/common/memory.h"
#include "core/mesh/io.h"
#include "core/mesh/validate.h"
#include "core/pipeline/pipeline.h"
#include "server/glb_writer.h"

namespace hexcover::server {

namespace {

/// Share of the whole job at which each pipeline stage starts and ends (measured roughly on the
/// shared test meshes); stages not listed keep the progress where it is.
struct StageSpan {
  const char* stage;
  double begin;
  double end;
};
constexpr char kWriting[] = "writing";  // the engine's own stage, after the pipeline's
constexpr StageSpan kStageSpans[] = {
    {stage::kRepair, 0.00, 0.05},
    {stage::kField, 0.05, 0.30},
    {stage::kParameterization, 0.30, 0.62},
    {stage::kExtraction, 0.62, 0.72},
    {stage::kRerun, 0.72, 0.82},
    {stage::kMetrics, 0.82, 0.95},
    {kWriting, 0.95, 1.00},
};

/// Turns the pipeline's (stage, fraction of stage) into a monotone fraction of the whole job.
RunContext jobProgress(const RunContext& job) {
  struct State {
    std::mutex mutex;
    double done = 0.0;
  };
  auto state = std::make_shared<State>();
  RunContext context;
  context.cancelRequested = job.cancelRequested;
  context.peakMemory = job.peakMemory;
  context.progress = [state, job](std::string_view stage, double fraction) {
    double overall;
    {
      const std::lock_guard lock(state->mutex);
      for (const auto& span : kStageSpans)
        if (stage == span.stage)
          state->done = std::max(
              state->done, span.begin + (span.end - span.begin) * std::clamp(fraction, 0.0, 1.0));
      overall = state->done;
    }
    job.report(stage, overall);
  };
  return context;
}

nlohmann::json singularitiesJson(const std::vector<Singularity>& singularities, int n) {
  std::map<std::string, int> byIndex;
  for (const auto& s : singularities) {
    std::string index = s.index > 0 ? "+" : "";  // "+1/6", "-1/6"
    index += std::to_string(s.index) + "/" + std::to_string(n);
    byIndex[index] += 1;
  }
  return {{"count", singularities.size()}, {"by_index", byIndex}};
}

/// Writes `soup` as `<name>.<format>` in `dir` and records it.
void writeResult(const PolygonSoup& soup, const std::string& mesh, const std::string& format,
                 const std::filesystem::path& dir, std::vector<api::ResultFile>& results) {
  const std::string file = mesh + "." + format;
  if (format == "glb")
    writeGlb(soup, dir / file);
  else
    writeMesh(soup, dir / file);
  results.push_back({mesh, format, file, 0});
}

}  // namespace

nlohmann::json PipelineEngine::normalizeOptions(const nlohmann::json& requested) const {
  const RemeshOptions options = api::remeshOptionsFromJson(requested);
  options.validate();
  return api::toJson(options);
}

std::string PipelineEngine::detectFormat(std::string_view head) const {
  return meshFormatName(hexcover::detectFormat(head));
}

JobOutcome PipelineEngine::run(const JobInput& input, const RunContext& context) const {
  // The job's free memory goes back to the kernel when it ends, however it ends (the server
  // keeps freed memory for reuse within a job: core/common/memory.h).
  struct ReleaseFreedMemoryAtEnd {
    ~ReleaseFreedMemoryAtEnd() { releaseFreedMemory(); }
  } const releaseAtEnd;
  const RunContext progress = jobProgress(context);
  const RemeshOptions options = api::remeshOptionsFromJson(input.options);
  progress.report("reading", 0.0);
  const PolygonSoup soup = readMesh(input.meshFile);
  progress.throwIfCanceled();

  RemeshResult result;
  try {
    result = remesh(soup, options, progress);
  } catch (const Error& e) {
    // A refused mesh gets its validation report, which names the defects.
    if (e.code() == ErrorCode::InvalidMesh || e.code() == ErrorCode::LimitExceeded)
      throw RefusedInput(e, toJson(validateMesh(soup)));
    throw;
  }

  progress.report(kWriting, 0.0);
  JobOutcome outcome;
  const PolygonSoup triangles = toPolygonSoup(result.remesh.triangles);
  for (const char* format : {"obj", "ply", "off", "stl", "glb"})
    writeResult(triangles, "triangles", format, input.outputDir, outcome.results);
  progress.throwIfCanceled();
  // The Gauss lattice (rosy 4) gives quads and no hexagonal dual.
  const bool quads = result.remesh.quads.faceCount() > 0;
  for (const char* format : {"obj", "ply", "off", "stl", "glb"})
    writeResult(quads ? result.remesh.quads : result.remesh.hexDual, quads ? "quads" : "hexagons",
                format, input.outputDir, outcome.results);
  for (const char* format : {"obj", "glb"})
    writeResult(result.textured, "textured", format, input.outputDir, outcome.results);
  progress.report(kWriting, 1.0);

  outcome.inputReport = toJson(result.inputReport);
  nlohmann::json metrics = toJson(result.metrics);
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& t : result.timings) stages[t.step] = t.seconds;
  metrics["stage_timings"] = stages;
  metrics["singularities"] = singularitiesJson(result.singularities, options.rosy);
  if (!quads)
    metrics["hexagons"] = {{"vertices", result.remesh.hexDual.vertexCount()},
                           {"faces", result.remesh.hexDual.faceCount()}};
  metrics["edge_length"] = result.edgeLength;
  metrics["singularity_distance"] = result.singularityDistance;
  metrics["size_iterations"] = result.sizeIterations;
  metrics["input_edges_split"] = result.inputEdgesSplit;
  metrics["warnings"] = result.warnings;
  metrics["peak_memory_mib"] = result.peakMemoryMiB;
  outcome.metrics = std::move(metrics);
  return outcome;
}

}  // namespace hexcover::server
