// `hexcover remesh IN -o OUT [--edge-length h | --vertices K] [--rosy 6|4]
//  [--sizing uniform|curvature] [--placement balanced|on_surface] [--feature-angle DEG]
//  [--d-sing X] [--hex OUT_HEX] [--textured OUT_OBJ] [--metrics METRICS.json] [--quiet]`: the
//  whole pipeline (core/pipeline) on one file. With --rosy 4, OUT is the quad-dominant remesh.

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "api/metrics_json.h"
#include "api/options_json.h"
#include "clients/cli/arguments.h"
#include "clients/cli/commands.h"
#include "core/mesh/io.h"
#include "core/pipeline/pipeline.h"

namespace hexcover::cli {
namespace {

RemeshOptions parseOptions(const Arguments& args) {
  RemeshOptions options;
  if (args.has("--edge-length") && args.has("--vertices"))
    throw UsageError("give --edge-length or --vertices, not both");
  options.edgeLength = args.number("--edge-length");
  options.targetVertices = args.integer("--vertices");
  if (const auto rosy = args.integer("--rosy")) {
    if (*rosy != 6 && *rosy != 4) throw UsageError("--rosy must be 6 or 4");
    options.rosy = static_cast<int>(*rosy);
  }
  if (options.rosy == 4 && args.has("--hex"))
    throw UsageError("--hex writes the hexagonal dual of a triangle remesh; --rosy 4 gives quads");
  // Enumerated options take the words of the API (api/options_json.h).
  const auto enumerated = [&](const std::string& flag, const auto& words, auto& target) {
    const auto word = args.value(flag);
    if (!word) return;
    const auto value = api::valueOfWord(words, *word);
    if (!value)
      throw UsageError(flag + " must be " + api::wordList(words) + ", got '" + *word + "'");
    target = *value;
  };
  enumerated("--sizing", api::kSizingWords, options.sizing);
  enumerated("--placement", api::kPlacementWords, options.placement);
  if (const auto angle = args.number("--feature-angle")) {
    if (!(*angle >= 0.0 && *angle <= 180.0))
      throw UsageError("--feature-angle must be between 0 and 180 degrees (0: creases not followed)");
    options.featureAngle = *angle;
  }
  if (const auto dSing = args.number("--d-sing")) {
    if (!(*dSing >= 0.0))
      throw UsageError("--d-sing must be a distance in mesh units, ≥ 0 (0: no clustering)");
    options.dSing = *dSing;
  }
  return options;
}

/// A one-line progress bar on stderr, redrawn in place: "field        [#####     ] 50%".
void drawProgress(std::string_view stage, double fraction) {
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * kWidth + 0.5);
  std::fprintf(stderr, "\r%-16.*s [%s%s] %3d%%", static_cast<int>(stage.size()), stage.data(),
               std::string(filled, '#').c_str(), std::string(kWidth - filled, ' ').c_str(),
               static_cast<int>(fraction * 100.0 + 0.5));
  std::fflush(stderr);
}

nlohmann::json metricsDocument(const RemeshResult& result) {
  nlohmann::json json = toJson(result.metrics);
  nlohmann::json singularities = nlohmann::json::array();
  for (const auto& s : result.singularities)
    singularities.push_back({{"vertex", s.vertex},
                             {"index", s.index},
                             {"position", {s.position.x(), s.position.y(), s.position.z()}}});
  json["singularities"] = std::move(singularities);
  nlohmann::json timings = nlohmann::json::object();
  for (const auto& t : result.timings) timings[t.step] = t.seconds;
  timings["total"] = totalSeconds(result.timings);
  json["timings"] = std::move(timings);
  json["peak_memory_mb"] = result.peakMemoryMiB;
  json["edge_length"] = result.edgeLength;
  json["singularity_distance"] = result.singularityDistance;
  json["input_edges_split"] = result.inputEdgesSplit;
  json["warnings"] = result.warnings;
  const ExtractionReport& r = result.remesh.report;
  json["extraction"] = {{"lattice_points", r.latticePoints},
                        {"lattice_triangles", r.latticeTriangles},
                        {"boundary_samples", r.boundarySamples},
                        {"strip_triangles", r.stripTriangles},
                        {"strip_flips", r.stripFlips},
                        {"strip_splits", r.stripSplits},
                        {"boundary_slides", r.boundarySlides},
                        {"flipped_param_triangles", r.flippedParamTriangles},
                        {"uncovered_triangles", r.uncoveredTriangles},
                        {"overlapping_triangles", r.overlappingTriangles},
                        {"holes_filled", r.holesFilled},
                        {"lattice_point_copies_merged", r.latticePointCopiesMerged},
                        {"unmatched_boundary_loops", r.unmatchedBoundaryLoops},
                        {"pinched_fan_triangles", r.pinchedFanTriangles},
                        {"farthest_centroid", r.farthestCentroid},
                        {"components_kept", r.componentsKept},
                        {"components_kept_for_topology", r.componentsKeptForTopology},
                        {"kept_vertices", r.keptVertices},
                        {"components", r.components},
                        {"feature_snaps", r.featureSnaps},
                        {"smoothed_vertices", r.smoothedVertices},
                        {"relaxed_vertices", r.relaxedVertices},
                        {"balanced_vertices", r.balancedVertices},
                        {"outlier_angle_moves", r.outlierAngleMoves},
                        {"boundary_sliver_collapses", r.boundarySliverCollapses},
                        {"boundary_sliver_flips", r.boundarySliverFlips},
                        {"non_manifold_faces_dropped", r.nonManifoldFacesDropped},
                        {"lattice_squares", r.latticeSquares},
                        {"quad_corners_restored", r.restoredVertices},
                        {"quad_cones_centred", r.centredVertices},
                        {"triangle_pairs_merged", r.mergedTrianglePairs}};
  return json;
}

}  // namespace

int runRemesh(int argc, char** argv) {
  const Arguments args(argc, argv, 2,
                       {"-o", "--edge-length", "--vertices", "--rosy", "--sizing", "--placement",
                        "--feature-angle", "--d-sing", "--hex", "--textured", "--metrics"},
                       {"--quiet"});
  const std::string& inputPath = args.positional(0, "IN");
  args.expectPositionalCount(1);
  const auto outputPath = args.value("-o");
  if (!outputPath) throw UsageError("missing -o OUT");
  const RemeshOptions options = parseOptions(args);
  const bool quiet = args.has("--quiet");
  // Output formats are checked before the work starts.
  formatFromExtension(*outputPath);
  if (const auto hex = args.value("--hex")) formatFromExtension(*hex);
  if (const auto textured = args.value("--textured")) {
    if (formatFromExtension(*textured) != MeshFormat::Obj)
      throw UsageError("--textured needs an .obj file (the only format with texture coordinates)");
  }

  RunContext context;
  const bool showProgress = !quiet && isatty(STDERR_FILENO);
  if (showProgress) context.progress = drawProgress;
  const RemeshResult result = remesh(readMesh(inputPath), options, context);
  if (showProgress) std::fprintf(stderr, "\r%60s\r", "");

  writeMesh(options.rosy == 4 ? result.remesh.quads : toPolygonSoup(result.remesh.triangles),
            *outputPath);
  if (const auto hex = args.value("--hex")) writeMesh(result.remesh.hexDual, *hex);
  if (const auto textured = args.value("--textured")) writeMesh(result.textured, *textured);
  if (const auto metricsPath = args.value("--metrics")) {
    std::ofstream out(*metricsPath);
    out << metricsDocument(result).dump(2) << "\n";
    if (!out) throw Error(ErrorCode::Io, "cannot write " + *metricsPath);
  }
  if (!quiet) {
    const QualityReport& m = result.metrics;
    std::cerr << "remeshed " << inputPath << " -> " << *outputPath << ": " << m.vertices
              << " vertices, " << m.faces << " faces, " << result.singularities.size()
              << " singularities, angles " << m.angleMin << "-" << m.angleMax << " (sd "
              << m.angleSd << "), irregular interior " << m.irregularInterior << ", Hausdorff "
              << (m.distance ? m.distance->hausdorffPct : 0.0) << "%, "
              << totalSeconds(result.timings) << " s\n";
    for (const auto& warning : result.warnings) std::cerr << "warning: " << warning << "\n";
  }
  return 0;
}

}  // namespace hexcover::cli
