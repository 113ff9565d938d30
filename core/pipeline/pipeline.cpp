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
#include "core/geometry/closest_point.h"
#include "core/geometry/curvature.h"
#include "core/geometry/frames.h"
#include "core/mesh/refine.h"
#include "core/mesh/repair.h"
#include "core/mesh/topology.h"
#include "core/param/hexcover.h"
#include "core/param/sizing.h"
#include "core/param/texture.h"

namespace hexcover {

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

/// Adds `seconds` to the timing named `step`, or appends it.
void addTiming(Timings& timings, const std::string& step, double seconds) {
  for (auto& t : timings)
    if (t.step == step) {
      t.seconds += seconds;
      return;
    }
  timings.push_back({step, seconds});
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The remesh measured against `reference`: its quads and their triangles for N = 4, its
/// triangles for N = 6.
QualityReport measureRemesh(const Remesh& remesh, const TriMesh& reference) {
  return remesh.quads.faceCount() > 0
             ? measurePolygonQuality(remesh.quads, remesh.triangles, &reference)
             : measureQuality(remesh.triangles, &reference);
}

/// |V − K| / K below which a run meets the target vertex count (the promise is 10%).
constexpr double kCountTolerance = 0.08;
/// |V − K| / K promised (`hexcover remesh --vertices K`).
constexpr double kCountPromise = 0.1;

/// An input vertex farther than this many of the coarsest lattice units from the remesh is on a
/// part of the input that the lattice lost: a limb thinner than it, folded away in the
/// parameterization and closed by the extraction's hole filling, which keeps the topology.
/// Measured: feline's arm at K = 650, 2.9 units (Hausdorff distance 13%); a finger of a sphere
/// at K = 200 and 400, 4.3 and 1.2 units (31% and 6.2%); every kept shape of the clean meshes at
/// K = V/4 to V/64, 0.02-0.7 units.
constexpr double kLostShapeInEdges = 1.0;
/// The input vertices checked for a lost part: every k-th, at most about this many.
constexpr std::size_t kShapeCheckVertices = 10000;

/// The largest distance from `input`'s vertices (every k-th of them, at most about
/// kShapeCheckVertices) to `remesh`, 0 for a remesh without faces.
double farthestInputVertex(const TriMesh& input, const TriMesh& remesh) {
  if (remesh.n_faces() == 0) return 0.0;
  const ClosestPointQuery query(remesh);
  const std::size_t stride = std::max<std::size_t>(1, input.n_vertices() / kShapeCheckVertices);
  double farthest = 0.0;
  for (std::size_t i = 0; i < input.n_vertices(); i += stride) {
    const auto v = input.vertex_handle(static_cast<int>(i));
    if (!input.is_isolated(v))
      farthest = std::max(farthest, query.closest(toEigen(input.point(v))).distance);
  }
  return farthest;
}

/// A remesh triangle whose centroid is farther than this many of the coarsest lattice units from
/// the input spans a hole or a fold: a strip zipped across a scanned hole narrower than an edge
/// (the Stanford bunny's base at K = 3594: 1.0 units, Hausdorff distance 2.7%; at K = 2500:
/// 0.64 units, 1.7%). Every other remesh of the clean meshes at K = V/4 to V/64 and of the bunny
/// at K = 2000 to 9000: at most 0.58 units (the bunny at K = 2250, Hausdorff distance 1.67%,
/// whose runs at h 3% off were no better).
constexpr double kStrayCentroidInEdges = 0.6;
/// A remesh with an angle outside [kSliverDegrees, kBluntDegrees] has a sliver well beyond the
/// floors of 20° and 130°, which another lattice may not have. Of 185 remeshes (the clean
/// meshes at K = V/4 to V/64, the Stanford bunny at K = 2000 to 9000) three had one: the bunny
/// at K = 1123 (13.1-147.1°, a fan of slivers where the strip meets its base's holes) and venus
/// at K = 11 (8.0°) are redone without (21.8-115.0°, 25.2-100.7°), the bunny at K = 6500 is not.
/// With the floors' bounds instead, 18 more would be redone, at 1-3 runs each, for 2 better.
constexpr double kSliverDegrees = 15.0;
constexpr double kBluntDegrees = 140.0;
/// Runs after one that kept the topology, the shape and the count but has a flaw (a triangle
/// off the input, kStrayCentroidInEdges, or a sliver, kSliverDegrees), with h 3% off: the
/// lattice falls differently.
constexpr int kFlawRetries = 2;

/// Whether a triangle of `mesh` has an angle below kSliverDegrees or above kBluntDegrees.
bool hasSliver(const TriMesh& mesh) {
  constexpr double kDegrees = 180.0 / M_PI;
  const std::vector<double> angles = cornerAngles(mesh);
  return std::any_of(mesh.halfedges_begin(), mesh.halfedges_end(), [&](const auto h) {
    if (mesh.is_boundary(h)) return false;
    const double degrees = angles[h.idx()] * kDegrees;
    return degrees < kSliverDegrees || degrees > kBluntDegrees;
  });
}

/// One parameterization and extraction.
struct LatticeRun {
  Parameterization param;
  Remesh remesh;
  bool topologyKept = false;
  bool shapeKept = true;       ///< no input vertex lost (kLostShapeInEdges); checked when
                               ///< topologyKept
  double farthestInput = 0.0;  ///< largest distance from the input's vertices to the remesh
  bool strayed = false;        ///< a triangle off the input (kStrayCentroidInEdges)
  bool slivered = false;       ///< a sliver (kSliverDegrees, kBluntDegrees)
  double countError = 0.0;     ///< |V − K| / K, 0 without a target count

  bool flawed() const { return strayed || slivered; }
  /// The input's topology first, then its shape, a vertex count within kCountPromise, no
  /// triangle off the input, no sliver, and the vertex count closest to K.
  bool betterThan(const LatticeRun& other) const {
    if (topologyKept != other.topologyKept) return topologyKept;
    if (shapeKept != other.shapeKept) return shapeKept;
    const bool counted = countError <= kCountPromise;
    if (counted != (other.countError <= kCountPromise)) return counted;
    if (strayed != other.strayed) return !strayed;
    if (slivered != other.slivered) return !slivered;
    return countError < other.countError;
  }
};

/// What every run along a field shares.
struct LatticeRuns {
  const TriMesh& mesh;
  const TriMesh* given;  ///< the input that `mesh` refines, or null (mesh is the input as given)
  const MeshTopology& inputTopology;
  const std::vector<double>& sizing;
  const ExtractOptions& extractOptions;
  long long target;                  ///< K
  bool targetGiven;                  ///< K was asked for (else it is the default, V/4)
  std::optional<double> edgeLength;  ///< h when given (else the first run derives it from K)
  bool mayRefine;  ///< h may shrink for topology (h from K below half the input's vertices)
};

/// Progress of the parameterization and extraction runs. The first reports its stages as they are;
/// each later one reports stage::kRerun over half of what remains of it (0 to 1/2, then to 3/4,
/// …), as their number is not known in advance. The parameterization takes kParameterizationShare
/// of a rerun.
class LatticeRunProgress {
 public:
  explicit LatticeRunProgress(const RunContext& job) : job_(job) {}

  /// The context of the next run.
  RunContext next() {
    ++started_;
    if (started_ == 1) return job_;
    constexpr double kParameterizationShare = 0.7;
    const double width = std::ldexp(1.0, -(started_ - 1));  // 1/2, 1/4, …
    const double begin = 1.0 - 2.0 * width;
    RunContext context;
    context.cancelRequested = job_.cancelRequested;
    context.progress = [job = job_, begin, width](std::string_view stage, double fraction) {
      if (stage != stage::kParameterization && stage != stage::kExtraction) return;
      const double done = stage == stage::kParameterization
                              ? kParameterizationShare * fraction
                              : kParameterizationShare + (1.0 - kParameterizationShare) * fraction;
      job.report(stage::kRerun, begin + width * done);
    };
    return context;
  }

 private:
  const RunContext& job_;
  int started_ = 0;
};

/// Runs along one field (RunsAlongField), unless its lattices keep missing the topology.
constexpr int kRunsAlongField = 4;

/// A direction field with the options it was computed with.
struct SolvedField {
  RosyField field;
  FieldOptions options;
};

/// Whether two fields give the same parameterizations: the same directions, matchings, creases
/// and singularities (all that computeParameterization reads of a field).
bool sameForLattice(const RosyField& a, const RosyField& b) {
  const auto sameSingularity = [](const Singularity& s, const Singularity& t) {
    return s.vertex == t.vertex && s.index == t.index && s.onBoundary == t.onBoundary;
  };
  return a.n == b.n && a.faceDirection == b.faceDirection && a.edgeMatching == b.edgeMatching &&
         a.sharpEdges == b.sharpEdges &&
         std::equal(a.singularities.begin(), a.singularities.end(), b.singularities.begin(),
                    b.singularities.end(), sameSingularity);
}

/// The vertices of a remesh that K counts: those of the components that took the lattice. A
/// component kept as it is (too small for the lattice: a scan's loose triangles) brings its own
/// vertices on top; counted, they would starve the rest (bunny_7k with 300 loose triangles,
/// 900 vertices, at K = 871: 263 vertices of bunny). All of them when every component was kept.
double countedVertices(const Remesh& remesh) {
  const auto all = static_cast<long long>(remesh.triangles.n_vertices());
  const long long kept = remesh.report.keptVertices;
  return static_cast<double>(kept < all ? all - kept : all);
}

/// The result's warnings (RemeshResult::warnings) about the remesh `chosen`.
std::vector<std::string> remeshWarnings(const LatticeRun& run, int misses,
                                        const RemeshOptions& options) {
  const double h = run.param.edgeLength;
  std::vector<std::string> warnings;
  const long long copied = run.remesh.report.componentsKept;
  const auto all = static_cast<long long>(run.remesh.triangles.n_vertices());
  const auto counted = static_cast<long long>(countedVertices(run.remesh));
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

/// |V − K| / K of a remesh of V counted vertices (countedVertices), 0 when K was not asked for.
double countError(const Remesh& remesh, const LatticeRuns& runs) {
  if (!runs.targetGiven) return 0.0;
  const auto target = static_cast<double>(runs.target);
  return std::abs(countedVertices(remesh) - target) / target;
}

/// Parameterization and extraction along a field, run by run (runUpTo). With a target vertex
/// count, h is rescaled by sqrt(V / K) until the remesh is within 8% of K (the promise is 10%). A
/// remesh whose topology differs from the repaired input's (fold-overs that neither the
/// parameterization nor the extraction's repair removed), or that lost a part of the input
/// (kLostShapeInEdges), is redone with h 3% smaller, where the lattice falls differently; a
/// second miss means the lattice is too coarse for the shape (a handle or a part narrower than a
/// few edge lengths), and h then shrinks by 15% per run when h comes from a vertex count K below
/// half the input's vertices. A remesh that keeps all that but has a triangle off the input
/// (kStrayCentroidInEdges) or a sliver (kSliverDegrees) is redone with h 3% off, towards K, up
/// to kFlawRetries times. The best run is kept (LatticeRun::betterThan). So a vertex count too
/// small for the shape gives a remesh with more vertices (and a warning that says why) rather
/// than the input copied unchanged (fertility at K = 218: 353 vertices; the input has 13,971)
/// or without a limb.
/// The runs can go on later (runUpTo a larger count): a field computed again that comes out the
/// same (sameForLattice) takes the next runs along this one instead of repeating these.
class RunsAlongField {
 public:
  RunsAlongField(SolvedField solved, const LatticeRuns& runs, Timings& timings,
                 LatticeRunProgress& progress)
      : solved_(std::move(solved)),
        runs_(runs),
        timings_(timings),
        progress_(progress),
        h_(runs.edgeLength.value_or(0.0)) {}

  /// Goes on until a run is done (kept, or good enough after kRunsAlongField runs), or until
  /// `maxRuns` runs along the field in all.
  void runUpTo(int maxRuns);

  /// Finishes the best run's remesh if its extraction left it unfinished (its lattice missed a
  /// component's topology, and no run along the field did better): extracted again with steps 7
  /// and 8 (ExtractOptions::finishOtherTopology).
  void finishBest();

  const SolvedField& solved() const { return solved_; }
  /// The best run so far; runUpTo has made one at least.
  const LatticeRun& best() const { return *best_; }
  LatticeRun& best() { return *best_; }
  int runsMade() const { return runCount_; }
  int misses() const { return misses_; }  ///< runs that did not keep the input's topology or shape

 private:
  SolvedField solved_;
  const LatticeRuns& runs_;
  Timings& timings_;
  LatticeRunProgress& progress_;
  std::optional<LatticeRun> best_;
  int runCount_ = 0;
  int misses_ = 0;
  int flawRetries_ = 0;
  std::vector<double> triedH_;  ///< the h of each run
  double h_;                    ///< of the next run (0: derived from K)
  bool finished_ = false;
};

void RunsAlongField::finishBest() {
  LatticeRun& best = *best_;
  if (!best.remesh.report.unfinished) return;
  const RunContext context = progress_.next();
  const auto start = std::chrono::steady_clock::now();
  ExtractOptions finish = runs_.extractOptions;
  finish.finishOtherTopology = true;
  best.remesh = extractRemesh(runs_.mesh, best.param, finish, context, runs_.given);
  addTiming(timings_, stage::kExtraction, secondsSince(start));
  best.countError = countError(best.remesh, runs_);
}

void RunsAlongField::runUpTo(int maxRuns) {
  constexpr double kTopologyRetryScale = 0.97;
  constexpr double kCoarseTopologyScale = 0.85;
  using Clock = std::chrono::steady_clock;
  const LatticeRuns& runs = runs_;
  const RosyField& field = solved_.field;
  const auto target = static_cast<double>(runs.target);
  const auto taken = [&](double next) {
    return std::any_of(triedH_.begin(), triedH_.end(),
                       [&](double t) { return std::abs(t - next) < 0.005 * next; });
  };
  // The coarsest lattice unit is h / (smallest sizing).
  const double coarsest =
      runs.sizing.empty() ? 1.0 : 1.0 / *std::min_element(runs.sizing.begin(), runs.sizing.end());
  while (!finished_ && runCount_ < maxRuns) {
    const int run = ++runCount_;
    const RunContext context = progress_.next();
    auto start = Clock::now();
    ParamOptions paramOptions;
    // The first run without an edge length derives h from the target (the parameterization
    // corrects it for its conformal scale); later runs rescale the h it used.
    if (run == 1 && !runs.edgeLength)
      paramOptions.targetVertices = static_cast<int>(runs.target);
    else
      paramOptions.edgeLength = h_;
    paramOptions.vertexSizing = runs.sizing;
    LatticeRun current;
    current.param = computeParameterization(runs.mesh, field, paramOptions, context);
    h_ = current.param.edgeLength;
    triedH_.push_back(h_);
    addTiming(timings_, stage::kParameterization, secondsSince(start));
    context.throwIfCanceled();

    start = Clock::now();
    current.remesh =
        extractRemesh(runs.mesh, current.param, runs.extractOptions, context, runs.given);
    addTiming(timings_, stage::kExtraction, secondsSince(start));
    // A component copied because its lattice triangles had another topology counts as a
    // topology miss, and so does, when the lattice may be refined, a remesh that is the input
    // copied whole (no component took the lattice): their vertices do not measure h, and the
    // next run takes the topology step.
    const ExtractionReport& report = current.remesh.report;
    const bool copiedWhole = report.components > 0 && report.componentsKept == report.components;
    const bool latticeTooCoarse =
        report.componentsKeptForTopology > 0 || (runs.mayRefine && copiedWhole);
    current.topologyKept =
        !latticeTooCoarse && computeTopology(current.remesh.triangles).sameAs(runs.inputTopology);
    if (current.topologyKept) {
      current.farthestInput = farthestInputVertex(runs.mesh, current.remesh.triangles);
      current.shapeKept = current.farthestInput <= kLostShapeInEdges * coarsest * h_;
    }
    const bool kept = current.topologyKept && current.shapeKept;
    current.strayed = report.farthestCentroid > kStrayCentroidInEdges * coarsest * h_;
    // A component copied unchanged has the input's triangles, slivers and all: no other lattice
    // changes them. Triangles only: a quad remesh's triangles are halves of quads, whose corners
    // run to 143° (redone for them, feline's quads took 19.8 s instead of 9.8 s).
    current.slivered =
        field.n == 6 && report.componentsKept == 0 && hasSliver(current.remesh.triangles);
    const double vertices = countedVertices(current.remesh);
    current.countError = countError(current.remesh, runs);
    // The vertices of a remesh that lost a part do not measure h for the whole input either.
    // A run after a flaw keeps its h within the promise: a rescale would take it back.
    const double tolerance = flawRetries_ > 0 ? kCountPromise : kCountTolerance;
    const bool rescale =
        current.countError > tolerance && vertices > 0.0 && !latticeTooCoarse && current.shapeKept;
    const bool done = kept && !rescale;
    misses_ += kept ? 0 : 1;
    if (!best_ || current.betterThan(*best_)) best_ = std::move(current);
    // Runs beyond kRunsAlongField only look for the topology, not for the vertex count.
    const bool shapeFound = best_->topologyKept && best_->shapeKept;
    const bool retryFlaw = done && best_->flawed() && flawRetries_ < kFlawRetries;
    finished_ = (done && !retryFlaw) || (run >= kRunsAlongField && shapeFound);
    if (finished_) return;
    // A flaw's step goes towards K (fewer vertices when there are more than asked for).
    const double step = retryFlaw
                            ? (runs.targetGiven && vertices > target ? 1.0 / kTopologyRetryScale
                                                                     : kTopologyRetryScale)
                        : rescale                       ? std::sqrt(vertices / target)
                        : misses_ > 1 && runs.mayRefine ? kCoarseTopologyScale
                                                        : kTopologyRetryScale;
    double next = h_ * step;
    // After a flaw the runs step back and forth, never onto an h already taken: a flaw's step
    // turns round, a rescale goes half-way (and again), a topology step one step further.
    if (retryFlaw) {
      ++flawRetries_;
      if (taken(next)) next = h_ / step;
    } else if (flawRetries_ > 0 && rescale) {
      while (taken(next) && std::abs(next - h_) > 0.01 * h_) next = 0.5 * (next + h_);
    } else if (flawRetries_ > 0) {
      while (taken(next)) next *= step;
    }
    h_ = next;
  }
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
