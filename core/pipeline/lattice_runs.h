#pragma once
// The pipeline's lattice runs (steps 3 and 4): parameterization and extraction along a field,
// rescaled towards the target vertex count and redone when a run loses the input's topology or
// shape or has a flaw, the best run kept. Internal to core/pipeline (pipeline.cpp runs them).

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/common/run_context.h"
#include "core/common/timings.h"
#include "core/extract/extract.h"
#include "core/field/rosy_field.h"
#include "core/mesh/mesh.h"
#include "core/mesh/topology.h"
#include "core/param/parameterization.h"

namespace hexcover::pipeline_detail {

/// |V − K| / K below which a run meets the target vertex count (the promise is 10%).
constexpr double kCountTolerance = 0.08;
/// |V − K| / K promised (`hexcover remesh --vertices K`).
constexpr double kCountPromise = 0.1;

/// Adds `seconds` to the timing named `step`, or appends it.
void addTiming(Timings& timings, const std::string& step, double seconds);

/// Seconds since `start`.
double secondsSince(std::chrono::steady_clock::time_point start);

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
  double smallestAngle = 0.0;  ///< of its triangles, in degrees, when checked for slivers
  double largestAngle = 0.0;
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
bool sameForLattice(const RosyField& a, const RosyField& b);

/// The vertices of a remesh that K counts: those of the components that took the lattice. A
/// component kept as it is (too small for the lattice: a scan's loose triangles) brings its own
/// vertices on top; counted, they would starve the rest (bunny_7k with 300 loose triangles,
/// 900 vertices, at K = 871: 263 vertices of bunny). All of them when every component was kept.
long long countedVertices(const Remesh& remesh);

/// |V − K| / K of a remesh of V counted vertices (countedVertices), 0 when K was not asked for.
double countError(const Remesh& remesh, const LatticeRuns& runs);

/// Parameterization and extraction along a field, run by run (runUpTo). With a target vertex
/// count, h is rescaled by sqrt(V / K) until the remesh is within 8% of K (the promise is 10%). A
/// remesh whose topology differs from the repaired input's (fold-overs that neither the
/// parameterization nor the extraction's repair removed), or that lost a part of the input
/// (kLostShapeInEdges), is redone with h 3% smaller, where the lattice falls differently; a
/// second miss means the lattice is too coarse for the shape (a handle or a part narrower than a
/// few edge lengths), and h then shrinks by 15% per run when h comes from a vertex count K below
/// half the input's vertices. A remesh that keeps all that but has a triangle off the input
/// (kStrayCentroidInEdges) or a sliver (kSliverDegrees) is redone with h 3% off, towards K, up
/// to kFlawRetries times (a retry that misses the topology or shape is one of them). Between a
/// lattice that kept the topology and shape and a coarser one that missed them, a rescale goes
/// half-way only when the count it expects is within the promise, and no topology step is made:
/// otherwise the runs end there. The best run is kept (LatticeRun::betterThan). So a vertex count
/// too small for the shape gives a remesh with more vertices (and a warning that says why) rather
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
  int runsMade() const { return static_cast<int>(tried_.size()); }
  int misses() const;  ///< runs that did not keep the input's topology or shape

 private:
  SolvedField solved_;
  const LatticeRuns& runs_;
  Timings& timings_;
  LatticeRunProgress& progress_;
  std::optional<LatticeRun> best_;
  int flawRetries_ = 0;
  struct TriedLattice {
    double h;
    bool keptShape;  ///< the input's topology and shape (LatticeRun::topologyKept, shapeKept)
  };
  std::vector<TriedLattice> tried_;  ///< each run's h and outcome
  double h_;                         ///< of the next run (0: derived from K)
  bool finished_ = false;
};

}  // namespace hexcover::pipeline_detail
