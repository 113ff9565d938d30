#pragma once
// The real engine: hexcover::remesh (core/pipeline) and the mesh writers. The only file of the
// server that depends on the geometry library's implementation.

#include "server/engine.h"

namespace hexcover::server {

class PipelineEngine final : public Engine {
 public:
  /// Options: api/options_json.h names and types, then RemeshOptions::validate().
  nlohmann::json normalizeOptions(const nlohmann::json& requested) const override;
  /// hexcover::detectFormat (core/mesh/io.h).
  std::string detectFormat(std::string_view head) const override;
  /// readMesh -> remesh -> writes triangles (obj, ply, off, stl, glb), hexagons (obj, ply, off,
  /// stl and glb fan-triangulated) and textured (obj, glb) into input.outputDir.
  /// Progress: the pipeline's stages, then "writing".
  JobOutcome run(const JobInput& input, const RunContext& context) const override;
};

}  // namespace hexcover::server
