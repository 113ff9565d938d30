#include "core/param/hexcover.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "core/common/concurrency.h"
#include "core/common/error.h"
#include "core/param/conformal_scale.h"
#include "core/param/cut_graph.h"
#include "core/param/cut_mesh.h"
#include "core/param/energy.h"
#include "core/param/energy_system.h"
#include "core/param/fold_repair.h"
#include "core/param/lattice.h"
#include "core/param/rounding.h"
#include "core/param/sizing.h"

namespace hexcover {
namespace {

using param_detail::CutMesh;
using param_detail::EnergySystem;
using param_detail::FaceGeometry;
using param_detail::LeastSquares;
using param_detail::Orientation;
using param_detail::SnappedCoordinates;
using param_detail::Unknowns;

// A solution x of the system with its exact corner coordinates and their orientation.
struct Iterate {
  Eigen::VectorXd x;
  SnappedCoordinates snapped;
  Orientation orientation;
  std::vector<bool> flippedFaces;
};

// What the fold-over remedies work on: the cut mesh, its unknowns, the least squares with its
// factorized system, and the lattice scale per face.
struct Problem {
  const TriMesh& mesh;
  const CutMesh& cm;
  const Unknowns& unknowns;
  const LeastSquares& ls;
  EnergySystem& system;
  const std::vector<double>& faceScale;
  int n;
  int threads;
};

Iterate iterateAt(const Problem& p, Eigen::VectorXd x) {
  Iterate it;
  it.x = std::move(x);
  it.snapped = param_detail::snapCoordinates(p.mesh, p.cm, p.unknowns, it.x, p.n);
  it.orientation = param_detail::countOrientation(p.mesh, p.cm, it.snapped, &it.flippedFaces);
  return it;
}

// Fold-overs, cheapest remedy first. Local relaxation (before and after a rounding repair) is
// kept only when it removes every fold-over; otherwise the global stiffening starts from the
// rounding-repaired plain solution (a partial local change can lead it to a worse optimum).
// Degenerate triangles (zero area, no fold-over) come from the rounding: a rounding repair.
void repairLocally(const Problem& p, Iterate& solution, Parameterization& result) {
  const auto relax = [&](Iterate& it) {
    ScopedTimer timer(result.timings, "local relaxation");
    result.localRelaxations +=
        param_detail::relaxFoldsLocally(p.mesh, p.cm, p.unknowns, p.ls, p.faceScale, p.n, it.x,
                                        it.snapped, it.orientation, it.flippedFaces);
  };
  const auto repair = [&](Iterate& it) {
    ScopedTimer timer(result.timings, "rounding repair");
    param_detail::repairRounding(p.mesh, p.cm, p.unknowns, p.system, p.n, p.threads, it.x,
                                 it.snapped, it.orientation, it.flippedFaces);
  };
  if (solution.orientation.flipped > 0) {
    const Iterate plain = solution;
    Iterate chosen = plain;  // relax, then repair and relax again
    relax(chosen);
    if (chosen.orientation.flipped > 0) {
      // Relaxation keeps only steps with fewer flipped triangles: one that kept none left
      // `plain`, and the order below (repair, then relax) would redo the same steps.
      const bool relaxedNothing = chosen.orientation.flipped == plain.orientation.flipped;
      repair(chosen);
      const Iterate repairedPlain = relaxedNothing ? chosen : Iterate{};
      if (chosen.orientation.flipped > 0) relax(chosen);
      if (chosen.orientation.flipped > 0 && relaxedNothing) {
        chosen = repairedPlain;
      } else if (chosen.orientation.flipped > 0) {  // repair, then relax
        Iterate repaired = plain;
        repair(repaired);
        chosen = repaired;
        if (repaired.orientation.flipped > 0) relax(chosen);
        if (chosen.orientation.flipped > 0) chosen = std::move(repaired);
      }
    }
    solution = std::move(chosen);
  }
  if (solution.orientation.flipped == 0 && solution.orientation.degenerate > 0) repair(solution);
}

// Global stiffening: raise the weight of distorted triangles (weight += min(5·relative misfit,
// 20), doubled around flipped ones) and re-solve, each re-solve followed by a rounding repair.
// Stops after kStiffeningPatience re-solves without fewer flipped triangles: what remains is not a
// stiffness issue.
// A later re-solve can fold a triangle that an earlier one had unfolded, so the best iterate
// (fewest flipped, then fewest degenerate triangles; the later one on ties) is the result.
// Measured over the 73 stiffenings of 88 remeshes (the clean meshes at V/8 to V/64; clean,
// half-refined and turned ones at V/4): 52 ended this way, 4 found fewer flipped triangles after
// two re-solves without. With a patience of 2 instead of 3 the 52 coarse remeshes took 9% less
// time (feline at V/64 25.0 -> 20.9 s) at the same quality (geometric means: Hausdorff distance
// +0.9%, angle SD -1.1%); at V/4 only spot's three remeshes changed (Hausdorff 1.45 / 1.61 /
// 1.62 -> 1.42 / 1.36 / 1.31%, angle SD +0.06 to +0.18°).
constexpr int kStiffeningPatience = 2;

void stiffen(const Problem& p, int maxIterations, Eigen::VectorXd& faceWeight, Iterate& it,
             Parameterization& result, const RunContext& context) {
  const int integerCount = p.unknowns.integerCount;
  int best = it.orientation.flipped + it.orientation.degenerate, sinceBest = 0;
  Iterate bestIterate = it;
  while ((it.orientation.flipped > 0 || it.orientation.degenerate > 0) &&
         result.stiffeningIterations < maxIterations && sinceBest < kStiffeningPatience) {
    context.throwIfCanceled();
    const Eigen::VectorXd residual = p.ls.gradient * it.x - p.ls.target;
    for (int f = 0; f < static_cast<int>(p.mesh.n_faces()); ++f) {
      const double misfit =
          residual.segment<param_detail::kEnergyRows>(param_detail::kRowsPerFace * f)
              .squaredNorm() /
          (2.0 * p.faceScale[f] * p.faceScale[f]);
      faceWeight[f] += std::min(5.0 * misfit, 20.0);
    }
    // Flipped triangles and the triangles around their corners are stiffened twofold.
    std::vector<bool> stiffened(p.mesh.n_faces(), false);
    for (const auto fh : p.mesh.faces())
      if (it.flippedFaces[fh.idx()])
        for (const auto vh : fh.vertices())
          for (const auto gh : vh.faces()) stiffened[gh.idx()] = true;
    for (int f = 0; f < static_cast<int>(p.mesh.n_faces()); ++f)
      if (stiffened[f]) faceWeight[f] *= 2.0;
    p.system.setFaceWeights(faceWeight, false);
    it = iterateAt(p, p.system.withReals(it.x.tail(integerCount)));
    ++result.stiffeningIterations;
    context.report(stage::kParameterization,
                   0.7 + 0.25 * result.stiffeningIterations / maxIterations);
    // Stiffening moves the real unknowns; a rounding move may now remove what is left.
    if (it.orientation.flipped > 0 || it.orientation.degenerate > 0)
      param_detail::repairRounding(p.mesh, p.cm, p.unknowns, p.system, p.n, p.threads, it.x,
                                   it.snapped, it.orientation, it.flippedFaces);
    const int remaining = it.orientation.flipped + it.orientation.degenerate;
    sinceBest = remaining < best ? 0 : sinceBest + 1;
    best = std::min(best, remaining);
    if (!param_detail::fewerFaults(bestIterate.orientation, it.orientation)) bestIterate = it;
  }
  it = std::move(bestIterate);
}

// The result's corner coordinates, transitions and singularities from the solution.
void storeSolution(const TriMesh& mesh, const RosyField& field, const CutGraph& cut,
                   const CutMesh& cm, const Unknowns& unknowns, const Iterate& solution,
                   Parameterization& result) {
  const double quantum = std::ldexp(1.0, -solution.snapped.exponent);
  result.cornerCoords.assign(mesh.n_halfedges(), Eigen::Vector2d::Zero());
  for (const auto h : mesh.halfedges()) {
    const int w = cm.halfedgeWedge[h.idx()];
    if (w < 0) continue;
    result.cornerCoords[h.idx()] = {static_cast<double>(solution.snapped.wedge[w][0]) * quantum,
                                    static_cast<double>(solution.snapped.wedge[w][1]) * quantum};
  }
  result.edgeTransition.assign(mesh.n_edges(), EdgeTransition{});
  result.cutEdge = cut.cutEdge;
  result.faceRotation = cut.faceRotation;
  result.cutLength = cut.cutLength;
  const std::vector<std::int64_t> rounded = param_detail::roundedFreeUnknowns(unknowns, solution.x);
  for (const auto eh : mesh.edges()) {
    const int pair = cm.edgePair[eh.idx()];
    if (pair < 0) continue;
    auto& transition = result.edgeTransition[eh.idx()];
    transition.rotation = cut.combedMatching[eh.idx()];
    for (int j = 0; j < 2; ++j)
      transition.translation[j] =
          static_cast<int>(param_detail::integerValue(unknowns, rounded, 2 * pair + j));
  }
  for (const auto& s : field.singularities) {
    ParamSingularity ps;
    ps.coords.setZero();
    ps.vertex = s.vertex;
    ps.index = s.index;
    for (const auto h : mesh.vih_range(mesh.vertex_handle(s.vertex)))
      if (!mesh.is_boundary(h)) {
        ps.coords = result.cornerCoords[h.idx()];
        break;
      }
    result.singularities.push_back(ps);
  }
}

double angleAt(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d u = b - a, v = c - a;
  return std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u.dot(v));
}

// Distortion: corner angles and log area ratio of parameter (scaled by h/s) vs surface triangles.
DistortionStats measureDistortion(const TriMesh& mesh, const FaceGeometry& geometry,
                                  const std::vector<double>& faceScale, int n,
                                  const std::vector<Eigen::Vector2d>& cornerCoords) {
  const Eigen::Matrix2d basis = latticeBasis(n);
  DistortionStats distortion;
  double angleSum = 0.0, areaSum = 0.0;
  int angleCount = 0, areaCount = 0;
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    if (!(geometry.area[f] > 0.0)) continue;
    std::array<Eigen::Vector2d, 3> p;
    int c = 0;
    for (const auto h : mesh.fh_range(fh)) p[c++] = basis * cornerCoords[h.idx()];
    const auto& q = geometry.local[f];
    for (int k = 0; k < 3; ++k) {
      const double difference = std::abs(angleAt(p[k], p[(k + 1) % 3], p[(k + 2) % 3]) -
                                         angleAt(q[k], q[(k + 1) % 3], q[(k + 2) % 3])) *
                                180.0 / M_PI;
      angleSum += difference;
      distortion.angleMax = std::max(distortion.angleMax, difference);
      ++angleCount;
    }
    const Eigen::Vector2d a = p[1] - p[0], b = p[2] - p[0];
    const double parameterArea = 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    if (parameterArea > 0.0) {
      const double ratio = parameterArea / (faceScale[f] * faceScale[f] * geometry.area[f]);
      const double logRatio = std::abs(std::log(ratio));
      areaSum += logRatio;
      distortion.areaMax = std::max(distortion.areaMax, logRatio);
      ++areaCount;
    }
  }
  distortion.angleMean = angleCount > 0 ? angleSum / angleCount : 0.0;
  distortion.areaMean = areaCount > 0 ? areaSum / areaCount : 0.0;
  return distortion;
}

}  // namespace

void ParamOptions::validate() const {
  const auto fail = [](const std::string& message) {
    throw Error(ErrorCode::InvalidOption, message);
  };
  if (!std::isfinite(edgeLength) || edgeLength < 0.0)
    fail("edge length must be a positive finite number (or 0 for automatic)");
  if (targetVertices < 0) fail("target vertex count must be positive (or 0 for automatic)");
  for (const double s : vertexSizing)
    if (!std::isfinite(s) || s <= 0.0) fail("vertex sizing values must be positive and finite");
  if (!(greedyBatchFraction > 0.0 && greedyBatchFraction <= 1.0))
    fail("greedy batch fraction must be in (0, 1]");
  if (maxStiffeningIterations < 0) fail("stiffening iterations must be ≥ 0");
  if (!(std::isfinite(conformalWeight) && conformalWeight >= 0.0))
    fail("conformal weight must be a finite number ≥ 0");
  if (!(std::isfinite(creaseWeight) && creaseWeight >= 0.0))
    fail("crease weight must be a finite number ≥ 0");
  if (threads < 1) fail("threads must be at least 1, got " + std::to_string(threads));
}

FieldOptions parameterizationFieldOptions(int n, double edgeLength, double singularityDistance,
                                          double featureAngle) {
  FieldOptions options;
  options.n = n;
  options.maxMergedIndex = kMergedIndexForLattice;
  options.singularityDistance = singularityDistance;
  options.sharpEdgeAngle = featureAngle;
  options.sharpLineLength = kCreaseLineInEdges * edgeLength;
  return options;
}

Parameterization computeParameterization(const TriMesh& mesh, const RosyField& field,
                                         const ParamOptions& options, const RunContext& context) {
  options.validate();
  if (mesh.n_faces() == 0) throw Error(ErrorCode::InvalidMesh, "the mesh has no faces to parameterize");
  if (!options.vertexSizing.empty() && options.vertexSizing.size() != mesh.n_vertices())
    throw Error(ErrorCode::InvalidOption,
                "vertex sizing has " + std::to_string(options.vertexSizing.size()) +
                    " values for " + std::to_string(mesh.n_vertices()) + " vertices");
  const int n = field.n;
  Parameterization result;
  result.n = n;

  // The conformal scale (a solve on the whole mesh) runs on a second thread while the cut graph,
  // the unknowns, the least squares' matrix and the symbolic analysis of its normal equations,
  // none of which depends on the lattice scale, are built on this one.
  context.report(stage::kParameterization, 0.0);
  std::vector<double> conformal;
  Timings sideTimings;
  CutGraph cut;
  CutMesh cm;
  Unknowns unknowns;
  LeastSquares ls;
  FaceGeometry geometry;
  std::vector<param_detail::CreaseEdge> creases;
  std::optional<EnergySystem> energySystem;
  runBoth(
      options.threads,
      [&] {
        {
          ScopedTimer timer(result.timings, "cut graph");
          cut = computeCutGraph(mesh, field);
          cm = param_detail::buildCutMesh(mesh, cut);
        }
        context.throwIfCanceled();
        {
          ScopedTimer timer(result.timings, "integer constraints");
          unknowns = param_detail::buildUnknowns(mesh, cm, n);
        }
        context.throwIfCanceled();
        ScopedTimer timer(result.timings, "assembly");
        geometry = param_detail::computeFaceGeometry(mesh, field, cut);
        creases = param_detail::findCreases(mesh, cm, geometry, field, options.creaseWeight);
        ls = param_detail::buildLeastSquares(mesh, cm, unknowns, geometry, options.conformalWeight,
                                             creases);
        energySystem.emplace(ls, unknowns.realCount,
                             param_detail::integerGroups(mesh, cut, cm, unknowns), options.solver,
                             options.threads);
        energySystem->analyze();
      },
      [&] {
        if (!options.conformalScale) return;
        ScopedTimer timer(sideTimings, "conformal scale");
        conformal = conformalFaceScale(mesh, field);
      });
  result.timings.insert(result.timings.end(), sideTimings.begin(), sideTimings.end());
  EnergySystem& system = *energySystem;
  result.integerVariables = unknowns.integerCount;
  context.throwIfCanceled();

  int usedVertices = 0;
  for (const auto vh : mesh.vertices()) usedVertices += mesh.is_isolated(vh) ? 0 : 1;
  result.edgeLength = options.edgeLength;
  if (!(result.edgeLength > 0.0)) {
    // From the vertex count; the conformal scale varies the lattice unit around h, so h is
    // corrected to keep the count.
    result.edgeLength = edgeLengthForVertexCount(
        mesh, options.targetVertices > 0 ? options.targetVertices : std::max(4, usedVertices / 4),
        isLatticeOrder(n) ? n : 6, options.vertexSizing);
    if (!conformal.empty()) result.edgeLength *= std::sqrt(conformalVertexCountFactor(mesh, conformal));
  }
  std::vector<double> faceScale(mesh.n_faces(), 1.0 / result.edgeLength);
  if (!options.vertexSizing.empty())
    for (const auto fh : mesh.faces()) {
      double s = 0.0;
      for (const auto vh : fh.vertices()) s += options.vertexSizing[vh.idx()] / 3.0;
      faceScale[fh.idx()] = s / result.edgeLength;
    }
  for (std::size_t f = 0; f < conformal.size(); ++f) faceScale[f] *= conformal[f];
  param_detail::setLatticeScale(faceScale, options.creaseWeight, creases, ls);
  context.report(stage::kParameterization, 0.2);

  // Local step: the minimizer over all unknowns.
  const int integerCount = unknowns.integerCount;
  Eigen::VectorXd faceWeight = Eigen::VectorXd::Ones(mesh.n_faces());
  Eigen::VectorXd x;
  {
    ScopedTimer timer(result.timings, "local solve");
    system.setFaceWeights(faceWeight, true);
    x = system.withReals(system.solveIntegers(std::vector<bool>(integerCount, false),
                                              Eigen::VectorXd::Zero(integerCount)));
  }
  result.localEnergy = system.energy(x);
  context.throwIfCanceled();
  context.report(stage::kParameterization, 0.4);

  // Global step: the integer unknowns rounded, then the final solve.
  {
    ScopedTimer timer(result.timings, "rounding");
    result.latticeDescentMoves =
        param_detail::roundIntegers(system, unknowns, options, n, x, context);
  }
  {
    ScopedTimer timer(result.timings, "final solve");
    x = system.withReals(x.tail(integerCount));
    if (!creases.empty()) {
      param_detail::setCreaseTargets(unknowns, creases, x, ls);
      system.setFaceWeights(faceWeight, false);  // the integers are fixed from here on
      x = system.withReals(x.tail(integerCount));
    }
  }
  context.report(stage::kParameterization, 0.7);

  // Fold-overs and degenerate triangles.
  const Problem problem{mesh, cm, unknowns, ls, system, faceScale, n, options.threads};
  Iterate solution = iterateAt(problem, std::move(x));
  result.flippedBeforeStiffening = solution.orientation.flipped;
  repairLocally(problem, solution, result);
  {
    ScopedTimer timer(result.timings, "stiffening");
    stiffen(problem, options.maxStiffeningIterations, faceWeight, solution, result, context);
  }
  result.flippedTriangles = solution.orientation.flipped;
  result.degenerateTriangles = solution.orientation.degenerate;
  result.energy = system.energy(solution.x);

  ScopedTimer timer(result.timings, "output");
  storeSolution(mesh, field, cut, cm, unknowns, solution, result);
  result.distortion = measureDistortion(mesh, geometry, faceScale, n, result.cornerCoords);
  context.report(stage::kParameterization, 1.0);
  return result;
}

}  // namespace hexcover
