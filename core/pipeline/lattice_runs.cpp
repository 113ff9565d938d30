#include "core/pipeline/lattice_runs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include "core/geometry/closest_point.h"
#include "core/geometry/frames.h"
#include "core/param/hexcover.h"

namespace hexcover::pipeline_detail {
namespace {

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
/// Two h within this fraction of each other are the same lattice for the runs.
constexpr double kSameH = 0.005;

/// The smallest and largest corner angle of `mesh`'s triangles, in degrees.
std::pair<double, double> angleRangeDegrees(const TriMesh& mesh) {
  constexpr double kDegrees = 180.0 / M_PI;
  const std::vector<double> angles = cornerAngles(mesh);
  std::pair<double, double> range{180.0, 0.0};
  for (const auto h : mesh.halfedges()) {
    if (mesh.is_boundary(h)) continue;
    range.first = std::min(range.first, angles[h.idx()] * kDegrees);
    range.second = std::max(range.second, angles[h.idx()] * kDegrees);
  }
  return range;
}

}  // namespace

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

bool sameForLattice(const RosyField& a, const RosyField& b) {
  const auto sameSingularity = [](const Singularity& s, const Singularity& t) {
    return s.vertex == t.vertex && s.index == t.index && s.onBoundary == t.onBoundary;
  };
  return a.n == b.n && a.faceDirection == b.faceDirection && a.edgeMatching == b.edgeMatching &&
         a.sharpEdges == b.sharpEdges &&
         std::equal(a.singularities.begin(), a.singularities.end(), b.singularities.begin(),
                    b.singularities.end(), sameSingularity);
}

long long countedVertices(const Remesh& remesh) {
  const auto all = static_cast<long long>(remesh.triangles.n_vertices());
  const long long kept = remesh.report.keptVertices;
  return kept < all ? all - kept : all;
}

double countError(const Remesh& remesh, const LatticeRuns& runs) {
  if (!runs.targetGiven) return 0.0;
  const auto target = static_cast<double>(runs.target);
  return std::abs(static_cast<double>(countedVertices(remesh)) - target) / target;
}

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

int RunsAlongField::misses() const {
  return static_cast<int>(std::count_if(tried_.begin(), tried_.end(),
                                        [](const TriedLattice& t) { return !t.keptShape; }));
}

void RunsAlongField::runUpTo(int maxRuns) {
  constexpr double kTopologyRetryScale = 0.97;
  constexpr double kCoarseTopologyScale = 0.85;
  using Clock = std::chrono::steady_clock;
  const LatticeRuns& runs = runs_;
  const RosyField& field = solved_.field;
  const auto target = static_cast<double>(runs.target);
  const auto taken = [&](double next) {
    return std::any_of(tried_.begin(), tried_.end(),
                       [&](const TriedLattice& t) { return std::abs(t.h - next) < kSameH * next; });
  };
  // The finest h above `h` whose lattice missed the input's topology or shape (∞ without one),
  // and the coarsest h below it whose lattice kept them (0 without one).
  const auto finestMissAbove = [&](double h) {
    double finest = std::numeric_limits<double>::infinity();
    for (const TriedLattice& t : tried_)
      if (!t.keptShape && t.h > h) finest = std::min(finest, t.h);
    return finest;
  };
  const auto coarsestKeptBelow = [&](double h) {
    double coarsest = 0.0;
    for (const TriedLattice& t : tried_)
      if (t.keptShape && t.h < h) coarsest = std::max(coarsest, t.h);
    return coarsest;
  };
  // The coarsest lattice unit is h / (smallest sizing).
  const double coarsest =
      runs.sizing.empty() ? 1.0 : 1.0 / *std::min_element(runs.sizing.begin(), runs.sizing.end());
  while (!finished_ && runsMade() < maxRuns) {
    const int run = runsMade() + 1;
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
    if (field.n == 6 && report.componentsKept == 0) {
      std::tie(current.smallestAngle, current.largestAngle) =
          angleRangeDegrees(current.remesh.triangles);
      current.slivered =
          current.smallestAngle < kSliverDegrees || current.largestAngle > kBluntDegrees;
    }
    const auto vertices = static_cast<double>(countedVertices(current.remesh));
    current.countError = countError(current.remesh, runs);
    // The vertices of a remesh that lost a part do not measure h for the whole input either.
    // A run after a flaw keeps its h within the promise: a rescale would take it back.
    const double tolerance = flawRetries_ > 0 ? kCountPromise : kCountTolerance;
    const bool rescale =
        current.countError > tolerance && vertices > 0.0 && !latticeTooCoarse && current.shapeKept;
    const bool done = kept && !rescale;
    tried_.push_back({h_, kept});
    if (!best_ || current.betterThan(*best_)) best_ = std::move(current);
    // Runs beyond kRunsAlongField only look for the topology, not for the vertex count. A run
    // after a flaw that misses what the flawed one kept counts as one of its retries: the best
    // run is done but for the flaw.
    const bool shapeFound = best_->topologyKept && best_->shapeKept;
    const bool bestDone = done || (!kept && shapeFound && best_->countError <= tolerance);
    const bool retryFlaw = bestDone && best_->flawed() && flawRetries_ < kFlawRetries;
    finished_ = (bestDone && !retryFlaw) || (run >= kRunsAlongField && shapeFound);
    if (finished_) return;
    if (retryFlaw) {
      // A flaw's step goes towards K (fewer vertices when there are more than asked for), from
      // the run that is done; on an h already taken, it turns round.
      const double from = done ? h_ : best_->param.edgeLength;
      const double fromVertices =
          done ? vertices : static_cast<double>(countedVertices(best_->remesh));
      const double step = runs.targetGiven && fromVertices > target ? 1.0 / kTopologyRetryScale
                                                                    : kTopologyRetryScale;
      ++flawRetries_;
      h_ = taken(from * step) ? from / step : from * step;
      finished_ = taken(h_);  // both sides tried
      continue;
    }
    // Between a lattice that kept the input's topology and shape and a coarser one that missed
    // them, a rescale goes half-way (geometrically, and again onto an h not taken), and only
    // when that can bring the count within the promise; a topology step is not made (the runs
    // end with the best). Measured on the clean meshes at V/4 to V/64, the Stanford bunny at
    // K = 2000 to 9000 and generated shapes at K = 300 to 6000 (175 remeshes): past the miss the
    // rescales and steps missed again (fertility at K = 218 rescaled from 323 vertices back to
    // the h that missed), and the runs that kept the shape near it were worse (fertility at
    // K = 436: 539 instead of 624 vertices but Hausdorff distance 2.10% instead of 1.27%, an
    // angle of 18.7°; Schwarz P at K = 183: 190 instead of 238 vertices, 3.88% instead of 0.88%).
    double next = 0.0;
    if (rescale) {
      next = h_ * std::sqrt(vertices / target);
      const double miss = finestMissAbove(h_);
      const bool bracketed = next >= miss * (1.0 - kSameH);
      if (bracketed) next = std::sqrt(h_ * miss);
      // After a flaw or below a miss the rescale never goes onto an h already taken.
      if (bracketed || flawRetries_ > 0)
        while (taken(next) && std::abs(next - h_) > 0.01 * h_) next = 0.5 * (next + h_);
      const double expected = vertices * (h_ / next) * (h_ / next);
      finished_ = bracketed && std::abs(expected - target) > kCountPromise * target && shapeFound;
    } else if (coarsestKeptBelow(h_) > 0.0) {
      finished_ = true;
    } else {
      const double topologyStep =
          misses() > 1 && runs.mayRefine ? kCoarseTopologyScale : kTopologyRetryScale;
      next = h_ * topologyStep;
      // After a flaw a topology step goes one step further, never onto an h already taken.
      if (flawRetries_ > 0)
        while (taken(next)) next *= topologyStep;
    }
    if (finished_) return;
    h_ = next;
  }
}

}  // namespace hexcover::pipeline_detail
