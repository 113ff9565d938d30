// `hexcover param MESH -o TEXTURED.obj [--edge-length h | --vertices K] [--rosy 6|4]
//  [--sizing uniform|curvature] [--texture HEX.png] [--rounding direct|greedy] [--d-sing X]
//  [--feature-angle DEG]`:
// the seamless HexCover parameterization (paper section 4) of a mesh along its geometry-aware
// field. Writes the mesh with per-corner texture coordinates vt = (u, v/√3) (one 1:√3 pattern
// period per unit square), optionally the matching hexagonal pattern tile, and prints one JSON
// object on stdout.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "api/param_json.h"
#include "clients/cli/arguments.h"
#include "clients/cli/commands.h"
#include "core/field/rosy_field.h"
#include "core/geometry/curvature.h"
#include "core/mesh/io.h"
#include "core/mesh/load.h"
#include "core/mesh/refine.h"
#include "core/param/hexcover.h"
#include "core/param/sizing.h"
#include "core/param/texture.h"
#include "core/pipeline/pipeline.h"

namespace hexcover::cli {

int runParam(int argc, char** argv) {
  const Arguments args(argc, argv, 2,
                       {"-o", "--edge-length", "--vertices", "--rosy", "--sizing", "--texture",
                        "--rounding", "--d-sing", "--feature-angle"},
                       {});
  const std::string& path = args.positional(0, "MESH");
  args.expectPositionalCount(1);
  const auto output = args.value("-o");
  if (!output) throw UsageError("missing -o TEXTURED.obj");
  if (args.has("--edge-length") && args.has("--vertices"))
    throw UsageError("give --edge-length or --vertices, not both");
  int n = 6;
  if (const auto rosy = args.integer("--rosy")) {
    if (*rosy != 6 && *rosy != 4) throw UsageError("--rosy must be 6 or 4");
    n = static_cast<int>(*rosy);
  }
  ParamOptions options;
  if (const auto h = args.number("--edge-length")) {
    if (!(*h > 0.0)) throw UsageError("--edge-length must be positive");
    options.edgeLength = *h;
  }
  if (const auto k = args.integer("--vertices")) {
    if (*k < 1 || *k > 100'000'000) throw UsageError("--vertices must be between 1 and 10^8");
    options.targetVertices = static_cast<int>(*k);
  }
  if (const auto rounding = args.value("--rounding")) {
    if (*rounding != "direct" && *rounding != "greedy")
      throw UsageError("--rounding must be direct or greedy, got '" + *rounding + "'");
    options.rounding = parseRoundingMethod(*rounding);
  }
  const double featureAngle = args.number("--feature-angle").value_or(kDefaultFeatureAngle);
  if (!(featureAngle >= 0.0 && featureAngle <= 180.0))
    throw UsageError("--feature-angle must be between 0 and 180 degrees (0: creases not followed)");
  const auto dSing = args.number("--d-sing");
  if (dSing && !(*dSing > 0.0))
    throw UsageError("--d-sing must be a positive distance in mesh units");
  const std::string sizing = args.value("--sizing").value_or("uniform");
  if (sizing != "uniform" && sizing != "curvature")
    throw UsageError("--sizing must be uniform or curvature, got '" + sizing + "'");

  const auto start = std::chrono::steady_clock::now();
  TriMesh mesh = loadMesh(path);
  // The uniform lattice unit requested (before the conformal correction of the parameterization).
  const double uniform =
      options.edgeLength > 0.0
          ? options.edgeLength
          : edgeLengthForVertexCount(mesh,
                                     options.targetVertices > 0
                                         ? options.targetVertices
                                         : std::max(4, static_cast<int>(mesh.n_vertices()) / 4),
                                     n);
  // d_sing follows the edge length as in the remesh pipeline (paper 3.3: for remeshing it "can be
  // selected based on the edge length of the output mesh"): singularities closer than a few
  // lattice units would be rounded onto one lattice point (its Fig. 15). --d-sing 0.1·B gives the
  // paper's figures. Creases, and the refinement of an input coarser than the lattice, as in the
  // remesh pipeline.
  const FieldOptions fieldOptions = parameterizationFieldOptions(
      n, uniform, dSing.value_or(kSingularityDistanceInEdges * uniform), featureAngle);
  const double latticeVertices = latticeVertexCount(mesh, uniform);
  const std::size_t maxFaces = RepairOptions{}.maxFaces;  // the limit loadMesh applied
  long long edgesSplit = refineLongEdges(mesh, kInputEdgeInEdgeLengths * uniform, maxFaces);
  RosyField field = computeRosyField(mesh, fieldOptions);
  if (needsFinerInputForLattice(field, latticeVertices)) {
    const long long finer =
        refineLongEdges(mesh, kCoarseInputEdgeInEdgeLengths * uniform, maxFaces);
    edgesSplit += finer;
    if (finer > 0) field = computeRosyField(mesh, fieldOptions);
  }
  if (sizing == "curvature") {
    // Scale with the largest absolute principal curvature (paper Fig. 13).
    // Smoothed over kSizingSmoothingInEdges uniform lattice units, as the pipeline does.
    options.vertexSizing =
        smoothSizing(mesh, curvatureSizing(computeCurvature(mesh).largestAbsolute()),
                     kSizingSmoothingInEdges * uniform);
  }
  Parameterization parameterization = computeParameterization(mesh, field, options);
  double fieldSeconds = field.seconds;
  // Crease lines meeting at angles other than multiples of 60° (a box's 90° corners) cannot all
  // be lattice lines, and a field that follows them all twists between them. As in the remesh
  // pipeline, the field that follows only a compatible subset is tried too; its parameterization
  // is kept when it has no more fold-overs and a lower mean angle distortion (an L-bracket at
  // K = 2000: 4.1° -> 1.9°, a plate with a hole 8.2° -> 4.3°; fandisk keeps all of its creases,
  // 3.2° against 3.3°).
  std::string creases = field.sharpEdges.empty() ? "none" : "all";
  if (const std::optional<RosyField> compatibleField =
          computeCompatibleCreaseField(mesh, field, fieldOptions)) {
    fieldSeconds += compatibleField->seconds;
    Parameterization compatible = computeParameterization(mesh, *compatibleField, options);
    const auto faults = [](const Parameterization& p) {
      return std::make_tuple(p.flippedTriangles, p.distortion.angleMean);
    };
    if (faults(compatible) < faults(parameterization)) {
      parameterization = std::move(compatible);
      creases = "compatible";
    }
  }
  writeMesh(texturedSoup(mesh, parameterization), *output);
  if (const auto texture = args.value("--texture"))
    writeLatticePatternPng(*texture, parameterization.n);

  nlohmann::json json = toJson(parameterization);
  json["input"] = path;
  json["output"] = *output;
  json["rounding"] = roundingMethodName(options.rounding);
  json["sizing"] = sizing;
  json["singularity_distance"] = fieldOptions.singularityDistance;
  json["input_edges_split"] = edgesSplit;
  json["creases"] = creases;
  json["field_seconds"] = fieldSeconds;
  json["total_seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << json.dump(2) << "\n";
  return 0;
}

}  // namespace hexcover::cli
