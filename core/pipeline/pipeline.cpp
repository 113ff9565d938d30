#include "core/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "core/common/memory.h"
#include "core/geometry/curvature.h"
#include "core/mesh/refine.h"
#include "core/mesh/repair.h"
#include "core/mesh/topology.h"
#include "core/param/hexcover.h"
#include "core/param/sizing.h"
#include "core/param/texture.h"
#include "core/pipeline/lattice_runs.h"

namespace hexcover {

using pipeline_detail::addTiming;
using pipeline_detail::countedVertices;
using pipeline_detail::kCountPromise;
using pipeline_detail::kCountTolerance;
using pipeline_detail::kRunsAlongField;
using pipeline_detail::LatticeRun;
using pipeline_detail::LatticeRunProgress;
using pipeline_detail::LatticeRuns;
using pipeline_detail::RunsAlongField;
using pipeline_detail::sameForLattice;
using pipeline_detail::secondsSince;
using pipeline_detail::SolvedField;

void RemeshOptions::validate() const {
  const auto fail = [](const std::string& message) { throw Error(ErrorCode::InvalidOption, message); };
  if (edgeLength && targetVertices)
    fail("give either an edge length or a target vertex count, not both");
  if (edgeLength && !(std::isfinite(*edgeLength) && *edgeLength > 0.0))
    fail("edge length must be a positive finite number, got " + std::to_string(*edgeLength));
  if (targetVertices && *targetVertices < 4)
    fail("target vertex count must be at least 4, got " + std::to_string(*targetVertices));
  if (targetVertices && *targetVertices > kMaxTargetVertices)
    fail("target vertex count must be at most " + std::to_string(kMaxTargetVertices) + ", got " +
         std::to_string(*targetVertices));
  if (rosy != 6 && rosy != 4)
    fail("rosy must be 6 (triangles) or 4 (quads), got " + std::to_string(rosy));
  if (dSing && !(std::isfinite(*dSing) && *dSing >= 0.0))
    fail("singularity distance d_sing must be a finite number ≥ 0, got " + std::to_string(*dSing));
  if (!(featureAngle >= 0.0 && featureAngle <= 180.0))
    fail("feature angle must be between 0 and 180 degrees (0: creases not followed), got " +
         std::to_string(featureAngle));
  if (maxFaces == 0) fail("the face limit must be positive");
}

namespace {

/// Vertices that belong to a face.
long long usedVertexCount(const TriMesh& mesh) {
  long long count = 0;
  for (const auto v : mesh.vertices()) count += mesh.is_isolated(v) ? 0 : 1;
  return count;
}

/// The remesh measured against `reference`: its quads and their triangles for N = 4, its
/// triangles for N = 6.
QualityReport measureRemesh(const Remesh& remesh, const TriMesh& reference) {
  return remesh.quads.faceCount() > 0
             ? measurePolygonQuality(remesh.quads, remesh.triangles, &reference)
             : measureQuality(remesh.triangles, &reference);
}

/// The result's warnings (RemeshResult::warnings) about the remesh `chosen`.
std::vector<std::string> remeshWarnings(const LatticeRun& run, int misses,
                                        const RemeshOptions& options) {
  const double h = run.param.edgeLength;
  std::vector<std::string> warnings;
  const long long copied = run.remesh.report.componentsKept;
  const auto all = static_cast<long long>(run.remesh.triangles.n_vertices());
  const long long counted = countedVertices(run.remesh);
  if (copied > 0) {
    std::ostringstream text;
    text << copied << (copied == 1 ? " input component was" : " input components were")
         << " copied unchanged: the lattice at edge length " << std::setprecision(3) << h
         << " does not fit " << (copied == 1 ? "it" : "them")
         << " (too small, or too thin for this vertex count); more vertices or a smaller edge "
            "length remesh "
         << (copied == 1 ? "it" : "them");
    if (options.targetVertices && counted < all)
      text << " (their " << all - counted << " vertices come on top of the "
           << *options.targetVertices << " asked for)";
    warnings.push_back(text.str());
  }
  // Folds matter where the lattice was taken: not in an input copied whole.
  if (run.param.flippedTriangles > 0 && copied < run.remesh.report.components)
    warnings.push_back(std::to_string(run.param.flippedTriangles) +
                       " parameter triangles stayed folded; the extraction filled the gaps, which "
                       "puts irregular vertices away from the singularities there (another "
                       "vertex count may avoid it)");
  if (!run.shapeKept) {
    std::ostringstream text;
    text << "a part of the input was lost: an input vertex is " << std::setprecision(3)
         << run.farthestInput / h
         << " edge lengths from the remesh (a part too thin for the lattice at edge length " << h
         << "); more vertices or a smaller edge length keep it";
    warnings.push_back(text.str());
  }
  // Flaws the runs could not avoid: LatticeRun::betterThan puts the topology, the shape and the
  // vertex count first.
  if (run.slivered) {
    std::ostringstream text;
    text << "the remesh has angles of " << std::setprecision(3) << run.smallestAngle << "° to "
         << run.largestAngle
         << "°: a sliver where the lattice meets a boundary, a crease or a fold, which the "
            "runs could not avoid at this vertex count; a slightly different vertex count or "
            "edge length may avoid it";
    warnings.push_back(text.str());
  }
  if (run.strayed) {
    std::ostringstream text;
    text << "a triangle of the remesh lies off the input (its centroid " << std::setprecision(2)
         << run.remesh.report.farthestCentroid / h
         << " edge lengths away: a strip across a hole or a gap narrower than an edge); a "
            "slightly different vertex count or edge length may avoid it";
    warnings.push_back(text.str());
  }
  if (options.targetVertices && run.countError > kCountPromise) {
    const bool moreForShape = misses > 0 && copied == 0 && counted > *options.targetVertices;
    warnings.push_back("the remesh has " + std::to_string(counted) + " vertices" +
                       (counted < all ? " besides those of the components copied unchanged" : "") +
                       ", more than 10% away from the " + std::to_string(*options.targetVertices) +
                       " asked for" +
                       (moreForShape ? ": remeshes with fewer vertices did not keep the input's "
                                       "topology or shape (a part too thin for them)"
                                     : ""));
  }
  return warnings;
}

}  // namespace

double estimatedPeakMemoryMiB(std::size_t faces, double remeshVertices) {
  constexpr double kMiBPerFace = 3.5 / 1024.0, kMiBPerVertex = 1.0 / 1024.0, kBaseMiB = 50.0;
  return kBaseMiB + kMiBPerFace * static_cast<double>(faces) + kMiBPerVertex * remeshVertices;
}

double latticeVertexCount(const TriMesh& mesh, double h) {
  // (h₁ / h)², h₁ the edge length of a lattice of one vertex.
  return std::pow(edgeLengthForVertexCount(mesh, 1, 6) / h, 2);
}

bool needsFinerInputForLattice(const RosyField& field, double latticeVertices) {
  int unsplit = 0;
  for (const auto& s : field.singularities)
    if (!s.onBoundary && std::abs(s.index) > kMergedIndexForLattice) unsplit += std::abs(s.index);
  return unsplit > 0 && latticeVertices >= kLatticeVerticesPerSplitSingularity * unsplit;
}

RemeshResult remesh(const PolygonSoup& input, const RemeshOptions& options,
                    const RunContext& context) {
  options.validate();
  RemeshResult result;
  using Clock = std::chrono::steady_clock;

  // 1. Repair, once the input's triangles have their memory (estimatedPeakMemoryMiB; the remesh's
  // part is reserved below, when its size is known).
  context.reservePeakMemory(estimatedPeakMemoryMiB(input.triangleCount(), 0.0));
  context.report(stage::kRepair, 0.0);
  RepairedMesh repaired;
  {
    ScopedTimer timer(result.timings, stage::kRepair);
    RepairOptions repairOptions;
    repairOptions.maxFaces = options.maxFaces;
    repaired = repairMesh(input, repairOptions);
  }
  result.inputReport = repaired.report;
  context.report(stage::kRepair, 1.0);
  context.throwIfCanceled();

  // A target of a quarter of the input's vertices by default, and h of a uniform lattice for it.
  const long long inputVertices = usedVertexCount(repaired.mesh);
  const long long target =
      options.targetVertices.value_or(std::max<long long>(4, inputVertices / 4));
  const double uniform = options.edgeLength
                             ? *options.edgeLength
                             : edgeLengthForVertexCount(repaired.mesh, static_cast<int>(target), 6);
  const double latticeVertices = latticeVertexCount(repaired.mesh, uniform);
  if (!(latticeVertices <= static_cast<double>(kMaxTargetVertices))) {
    std::ostringstream message;
    message << "edge length " << uniform << " would give about " << std::setprecision(3)
            << latticeVertices << " vertices on this mesh, more than the " << kMaxTargetVertices
            << " supported: give a larger edge length";
    throw Error(ErrorCode::InvalidOption, message.str());
  }
  const TriMesh& mesh = repaired.mesh;
  // Splits the input's edges longer than `longest` uniform edge lengths: the same surface,
  // sampled finely enough for the field's singularities and the lattice's detail (within the
  // input's face limit). The input as repaired is kept for the metrics (the same surface, with
  // far fewer faces to sample and query when the refinement split many). The surface fit works
  // on the refinement: its vertices and face centroids sample the input densely, and fitting to
  // the unrefined input instead raised Hausdorff distances (a plate with a hole 0.82 -> 1.31%).
  std::optional<TriMesh> unrefined;
  const auto refine = [&](double longest) {
    const auto start = Clock::now();
    const bool longer = std::any_of(mesh.edges_begin(), mesh.edges_end(), [&](const auto e) {
      return mesh.calc_edge_length(e) > longest * uniform;
    });
    if (longer && !unrefined) unrefined = repaired.mesh;
    const long long splits = refineLongEdges(repaired.mesh, longest * uniform, options.maxFaces);
    addTiming(result.timings, "refinement", secondsSince(start));
    result.inputEdgesSplit += splits;
    return splits > 0;
  };

  // 2. Sizing (curvature sizing is smoothed over kSizingSmoothingInEdges uniform edge lengths),
  // h and the field, on the input as refined.
  std::vector<double> sizing;
  const auto computeSizing = [&] {
    if (options.sizing != Sizing::Curvature) return;
    const auto start = Clock::now();
    sizing = smoothSizing(mesh, curvatureSizing(computeCurvature(mesh).largestAbsolute()),
                          kSizingSmoothingInEdges * uniform);
    addTiming(result.timings, "sizing", secondsSince(start));
  };
  // The field with d_sing = dSingScale × its default (unless d_sing is given).
  const auto computeField = [&](double dSingScale) {
    const auto start = Clock::now();
    const double h = options.edgeLength
                         ? *options.edgeLength
                         : edgeLengthForVertexCount(mesh, static_cast<int>(target), 6, sizing);
    const double singularityDistance =
        options.dSing.value_or(dSingScale * kSingularityDistanceInEdges * h);
    FieldOptions fieldOptions =
        parameterizationFieldOptions(options.rosy, h, singularityDistance, options.featureAngle);
    if (const std::string problem = fieldOptions.validate(); !problem.empty())
      throw Error(ErrorCode::InvalidOption, problem);
    // d_sing = 0 means "no clustering" to the caller; the field reads 0 as "use the default".
    fieldOptions.clusterSingularities = singularityDistance > 0.0;
    RosyField field = computeRosyField(mesh, fieldOptions, context);
    addTiming(result.timings, stage::kField, secondsSince(start));
    return SolvedField{std::move(field), fieldOptions};
  };
  // Edges beyond kInputEdgeInEdgeLengths are split first. Interior singularities of a higher
  // index than the lattice takes, which the field could not split for want of vertices around
  // them, get the input refined to kCoarseInputEdgeInEdgeLengths and the field again, when the
  // lattice has the room: kLatticeVerticesPerSplitSingularity vertices for each first-order
  // singularity they would become (a cube of 8 vertices at K = 2 stays as it is).
  // The run's memory is reserved before the stages that take it (a service may wait there until
  // it is free): for the input refined to kInputEdgeInEdgeLengths (about a face per eight lattice
  // vertices where the input is coarser), then for the faces that each refinement made.
  const auto reserveMemory = [&](std::size_t faces) {
    context.reservePeakMemory(estimatedPeakMemoryMiB(faces, latticeVertices));
  };
  reserveMemory(std::max(mesh.n_faces(), static_cast<std::size_t>(latticeVertices / 8.0)));
  refine(kInputEdgeInEdgeLengths);
  reserveMemory(mesh.n_faces());
  computeSizing();
  SolvedField solved = computeField(1.0);
  if (needsFinerInputForLattice(solved.field, latticeVertices) &&
      refine(kCoarseInputEdgeInEdgeLengths)) {
    reserveMemory(mesh.n_faces());
    computeSizing();
    solved = computeField(1.0);
  }
  context.throwIfCanceled();

  // 3 and 4. Parameterization and extraction (see RunsAlongField).
  const MeshTopology inputTopology = computeTopology(mesh);
  ExtractOptions extractOptions;
  extractOptions.balanceDeviation = options.placement == VertexPlacement::Balanced;
  extractOptions.creaseAngle = options.featureAngle;
  // A run whose lattice misses a component's topology is redone: its remesh is finished only
  // when it is kept after all (RunsAlongField::finishBest).
  extractOptions.finishOtherTopology = false;
  const LatticeRuns runs{mesh,
                         unrefined ? &*unrefined : nullptr,
                         inputTopology,
                         sizing,
                         extractOptions,
                         target,
                         options.targetVertices.has_value(),
                         options.edgeLength,
                         !options.edgeLength && 2 * target < inputVertices};
  LatticeRunProgress runProgress(context);
  // Every field remeshed, with its runs; `chosen` is the one whose best run is kept.
  std::vector<std::unique_ptr<RunsAlongField>> fields;
  const auto addField = [&](SolvedField field) -> RunsAlongField& {
    fields.push_back(
        std::make_unique<RunsAlongField>(std::move(field), runs, result.timings, runProgress));
    return *fields.back();
  };
  RunsAlongField* chosen = &addField(std::move(solved));
  chosen->runUpTo(kRunsAlongField);
  // When no lattice along the field kept the input's topology, the field's singularities are
  // likely merged too far for the shape: clustered within d_sing, like-signed ones become nodes
  // of higher index that the parameterization folds around. The field is computed again with
  // d_sing halved, twice at most, and its runs are kept when they do better; the last field gets
  // kLastFieldRuns runs, h shrinking further. Feline at K = 700 to 1100 (d_sing = 6 h) had all
  // runs fold into another topology and came back as its input copied (49,864 vertices); at
  // K = 1000 even 8 runs down to 0.37 h did. At K = 850 the fifth run of the last field keeps it.
  // A field that comes out as one before (no singularities were as close as d_sing: 60 spheres
  // at K = 600) would only repeat its runs: the runs along that one go on instead.
  constexpr int kFieldRetries = 2, kLastFieldRuns = 8;
  for (int retry = 1;
       retry <= kFieldRetries && !chosen->best().topologyKept && !options.dSing && runs.mayRefine;
       ++retry) {
    SolvedField finer = computeField(std::ldexp(1.0, -retry));
    context.throwIfCanceled();
    const int maxRuns = retry == kFieldRetries ? kLastFieldRuns : kRunsAlongField;
    const auto same = std::find_if(fields.begin(), fields.end(), [&](const auto& along) {
      return sameForLattice(along->solved().field, finer.field);
    });
    RunsAlongField& again = same == fields.end() ? addField(std::move(finer)) : **same;
    again.runUpTo(maxRuns);  // a field remeshed before goes on from its last run
    if (again.best().betterThan(chosen->best())) chosen = &again;
  }
  chosen->finishBest();

  // Crease lines that meet at angles other than multiples of 60° (a box's 90° corners) cannot all
  // be lattice lines; a field that follows them all twists between them. The field that follows
  // only a compatible subset (latticeCompatibleCreases) is remeshed too, and its remesh is kept
  // when it keeps the input's topology, copies no more components and meets the vertex count as
  // well, and comes closer to the quality goals: angle SD / kGoalAngleSd + Hausdorff distance /
  // kGoalHausdorffPct is lower (the creases it does not follow are cut by lattice rows, which
  // costs distance). Measured (angle SD, Hausdorff distance, all creases -> compatible ones): an
  // L-bracket at K = 2000 5.2° 0.63% -> 3.8° 0.59%, a plate with a hole 11.9° 0.66% -> 6.2°
  // 0.71%; fandisk at K = 1562 keeps all of its creases (5.8° 0.93% against 6.6° 0.84%).
  constexpr double kGoalAngleSd = 4.0;
  constexpr double kGoalHausdorffPct = 0.5;
  const TriMesh& reference = unrefined ? *unrefined : mesh;
  std::optional<QualityReport> metrics;
  auto start = Clock::now();
  std::optional<RosyField> compatibleField =
      computeCompatibleCreaseField(mesh, chosen->solved().field, chosen->solved().options, context);
  if (compatibleField) {
    addTiming(result.timings, stage::kField, secondsSince(start));
    context.throwIfCanceled();
    RunsAlongField& compatible =
        addField(SolvedField{std::move(*compatibleField), chosen->solved().options});
    compatible.runUpTo(kRunsAlongField);
    compatible.finishBest();
    // What comes before the shape: the topology, no part lost, the components copied, the
    // vertex count.
    const auto essentials = [&](const RunsAlongField& along) {
      const LatticeRun& r = along.best();
      return std::make_tuple(!r.topologyKept, !r.shapeKept, r.remesh.report.componentsKept,
                             r.countError > kCountTolerance);
    };
    bool takeCompatible = essentials(compatible) < essentials(*chosen);
    if (essentials(compatible) == essentials(*chosen)) {
      start = Clock::now();
      QualityReport all = measureRemesh(chosen->best().remesh, reference);
      QualityReport fewer = measureRemesh(compatible.best().remesh, reference);
      addTiming(result.timings, stage::kMetrics, secondsSince(start));
      const auto toGoals = [&](const QualityReport& q) {
        return q.angleSd / kGoalAngleSd + q.distance->hausdorffPct / kGoalHausdorffPct;
      };
      takeCompatible = toGoals(fewer) < toGoals(all);
      metrics = takeCompatible ? std::move(fewer) : std::move(all);
    }
    if (takeCompatible) chosen = &compatible;
  }
  result.sizeIterations = 0;
  for (const auto& along : fields) result.sizeIterations += along->runsMade();
  result.singularityDistance = chosen->solved().options.singularityDistance;
  result.singularities = chosen->solved().field.singularities;
  result.warnings = remeshWarnings(chosen->best(), chosen->misses(), options);
  Parameterization param = std::move(chosen->best().param);
  result.remesh = std::move(chosen->best().remesh);
  result.edgeLength = param.edgeLength;
  result.flippedParamTriangles = param.flippedTriangles;
  context.throwIfCanceled();

  // Textured input and metrics.
  {
    ScopedTimer timer(result.timings, "texture");
    result.textured = texturedSoup(mesh, param);
  }
  context.report(stage::kMetrics, 0.0);
  if (!metrics) {
    const auto start = Clock::now();
    metrics = measureRemesh(result.remesh, reference);
    addTiming(result.timings, stage::kMetrics, secondsSince(start));
  }
  result.metrics = std::move(*metrics);
  context.report(stage::kMetrics, 1.0);
  result.peakMemoryMiB = peakMemoryMiB();
  return result;
}

}  // namespace hexcover
