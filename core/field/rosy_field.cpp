#include "core/field/rosy_field.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "core/common/concurrency.h"
#include "core/common/error.h"
#include "core/field/clustering.h"
#include "core/field/connection.h"
#include "core/field/singularities.h"
#include "core/field/smooth_solve.h"
#include "core/geometry/sharp_edges.h"

namespace hexcover {
namespace {

using field::Complex;

/// Most clustering rounds (collapse, re-solve) per run; later rounds only touch leftovers.
constexpr int kClusteringRounds = 6;

template <typename Step>
auto timed(Timings& timings, const char* name, Step&& step) {
  const ScopedTimer timer(timings, name);
  return step();
}

/// Representative angles θ_f = arg(u_f) / N of a power-representation field.
std::vector<double> anglesOf(const std::vector<Complex>& u, int n) {
  std::vector<double> angles(u.size());
  for (std::size_t f = 0; f < u.size(); ++f) angles[f] = std::arg(u[f]) / n;
  return angles;
}

/// Soft directional constraints of section 3.2: at faces with at least two strong vertices
/// (ρ > t_ρ) whose averaged curvature tensor is cylindrical, the maximum direction θ where φ > 0
/// and the minimum direction θ + π/2 where φ < 0 (for N = 4 the power representation holds both).
void addCurvatureConstraints(const TriMesh& mesh, const field::FieldGeometry& geometry,
                             const Curvature& curvature, const FieldOptions& options,
                             field::SmoothSolveInput& input) {
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
    int strong = 0;
    for (const auto vh : fh.vertices()) {
      tensor += curvature.tensor(vh.idx()) / 3.0;
      if (curvature.strong[vh.idx()]) ++strong;
    }
    if (strong < 2) continue;
    const Eigen::Vector3d& x = geometry.frames.xAxis[f];
    const Eigen::Vector3d& y = geometry.frames.yAxis[f];
    const double a = x.dot(tensor * x), b = x.dot(tensor * y), c = y.dot(tensor * y);
    const double mean = 0.5 * (a + c), radius = std::hypot(0.5 * (a - c), b);
    const double kappaMax = mean + radius, kappaMin = mean - radius;
    const double rho = std::hypot(kappaMax, kappaMin);
    const double phi = std::atan2(kappaMax + kappaMin, kappaMax - kappaMin);
    if (classifyCurvature(rho, phi, curvature.planarRho) != CurvatureClass::Cylindrical) continue;
    const double theta = 0.5 * std::atan2(2.0 * b, a - c);
    const double direction = phi > 0.0 ? theta : theta + 0.5 * M_PI;
    input.softWeight[f] = options.constraintWeight;
    input.softTarget[f] = std::polar(1.0, options.n * direction);
  }
}

/// Faces with a boundary edge: one direction along the boundary (hard constraint). The tangent of
/// a boundary edge is the chord over `reach` boundary vertices on either side, so that the
/// zigzags of a scanned boundary do not each become a boundary singularity; a face with several
/// boundary edges follows its longest one.
void fixBoundaryFaces(const TriMesh& mesh, const field::FieldGeometry& geometry, int n, int reach,
                      field::SmoothSolveInput& input) {
  std::vector<double> longest(mesh.n_faces(), -1.0);
  std::vector<bool> visited(mesh.n_halfedges(), false);
  for (const auto start : mesh.halfedges()) {
    if (!start.is_boundary() || visited[start.idx()]) continue;
    // The loop's face-side halfedges in order (each runs u→w with the surface on its left).
    std::vector<TriMesh::HalfedgeHandle> loop;
    for (auto h = start; !visited[h.idx()]; h = h.next()) {
      visited[h.idx()] = true;
      loop.push_back(h.opp());
    }
    std::reverse(loop.begin(), loop.end());
    const int count = static_cast<int>(loop.size());
    for (int k = 0; k < count; ++k) {
      const auto h = loop[k];
      const int f = mesh.face_handle(h).idx();
      const double length = mesh.calc_edge_length(h);
      if (length <= longest[f]) continue;
      longest[f] = length;
      const auto from = mesh.from_vertex_handle(loop[((k - reach) % count + count) % count]);
      const auto to = mesh.to_vertex_handle(loop[(k + reach) % count]);
      const Eigen::Vector3d tangent = toEigen(mesh.point(to) - mesh.point(from));
      input.free[f] = false;
      input.value[f] = std::polar(1.0, n * geometry.frames.angleOf(f, tangent));
    }
  }
}

/// Faces with a sharp edge: one direction along it, a soft constraint of the given weight (a
/// crease may turn faster than the field can follow); a face with several sharp edges follows its
/// longest one.
void addSharpEdgeConstraints(const TriMesh& mesh, const field::FieldGeometry& geometry, int n,
                             const std::vector<bool>& sharp, double weight,
                             field::SmoothSolveInput& input) {
  std::vector<double> longest(mesh.n_faces(), -1.0);
  for (const auto eh : mesh.edges()) {
    if (!sharp[eh.idx()]) continue;
    const double length = mesh.calc_edge_length(eh);
    const Eigen::Vector3d tangent = toEigen(mesh.point(eh.v1()) - mesh.point(eh.v0()));
    for (const auto h : {eh.h0(), eh.h1()}) {
      const int f = h.face().idx();
      if (length <= longest[f] || !input.free[f]) continue;
      longest[f] = length;
      input.softWeight[f] = weight;
      input.softTarget[f] = std::polar(1.0, n * geometry.frames.angleOf(f, tangent));
    }
  }
}

/// What every clustering re-solve of a run shares: built once.
struct ClusterSolveInputs {
  const field::SmoothnessTerms& terms;  ///< with the dual graph's elimination order
  const field::EdgeGraph& graph;
  const std::vector<int>& vertexOrder;  ///< the vertex graph's elimination order
  const std::vector<bool>& solvable;    ///< #F: false at the boundary-aligned faces
};

/// What the clustering re-solves carry from one round to the next.
struct ClusterSolveState {
  std::vector<Complex> u;             ///< #F field in the power representation
  std::vector<double> corrections;    ///< #E connection corrections c
  std::vector<bool> changed;          ///< #F faces whose field `corrections` does not follow yet
  std::vector<double> matchingShift;  ///< #E corrections of the edges last re-solved (else 0)
};

/// One re-solve of section 3.3 after a clustering: the field in the region R (faces with a vertex
/// closer than d_sing to a collapsed singularity; boundary-aligned faces stay fixed) with
/// K̄ = 2π I / N at the remaining singularities and 0 at every other vertex of R. The connection:
/// across every edge at a fixed face, the fixed field's own turn (so the field is parallel
/// there); on the edges between free faces, the smallest change of `corrections` that gives
/// those holonomies. The boundary data is then compatible and the solve returns the parallel
/// field, whose singularities are the targets. Directional constraints are off. Updates every
/// member of `state` (see ClusterSolveState).
void resolveRegion(const TriMesh& mesh, const field::FieldGeometry& geometry,
                   const ClusterSolveInputs& inputs, const field::ClusteringResult& clusters,
                   double dSing, int n, ClusterSolveState& state) {
  const int nf = static_cast<int>(mesh.n_faces());
  const std::vector<double> distance =
      field::edgeGraphDistances(inputs.graph, clusters.collapsedVertices, dSing);
  field::SmoothSolveInput region;
  region.free.assign(nf, false);
  region.value.resize(nf);
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    const double magnitude = std::abs(state.u[f]);
    region.value[f] = magnitude > 0.0 ? state.u[f] / magnitude : Complex(1.0, 0.0);
    if (!inputs.solvable[f]) continue;
    for (const auto vh : fh.vertices())
      if (distance[vh.idx()] < dSing) region.free[f] = true;
  }
  std::vector<bool> touchesRegion(mesh.n_vertices(), false), freeEdges(mesh.n_edges(), false);
  for (const auto fh : mesh.faces())
    if (region.free[fh.idx()])
      for (const auto vh : fh.vertices()) touchesRegion[vh.idx()] = true;
  for (const auto eh : mesh.edges()) {
    if (mesh.is_boundary(eh)) continue;
    const int f0 = eh.h0().face().idx(), f1 = eh.h1().face().idx();
    freeEdges[eh.idx()] = region.free[f0] && region.free[f1];
    if (!freeEdges[eh.idx()] &&
        (state.changed[f0] || state.changed[f1])) {  // N δ_e = Arg(u_f1/(e^{iNρ} u_f0))
      const Complex rotation = std::polar(1.0, n * geometry.transport[eh.idx()]);
      state.corrections[eh.idx()] = std::arg(region.value[f1] / (rotation * region.value[f0])) / n;
    }
  }
  std::vector<double> target(mesh.n_vertices(), 0.0);
  for (const auto& node : clusters.nodes) target[node.vertex] += 2.0 * M_PI * node.index / n;
  state.corrections =
      field::ConnectionCorrector(mesh, geometry, touchesRegion, freeEdges, inputs.vertexOrder)
          .corrections(target, state.corrections);
  for (std::size_t e = 0; e < freeEdges.size(); ++e)
    if (freeEdges[e]) state.matchingShift[e] = state.corrections[e];
  state.changed = region.free;
  state.u = field::solveSmoothField(inputs.terms, geometry.transport, state.corrections,
                                    geometry.frames.area, n, region);
}

}  // namespace

std::string FieldOptions::validate() const {
  std::ostringstream message;
  if (n != 4 && n != 6)
    message << "n (the symmetry order) must be 4 or 6, got " << n;
  else if (!(constraintWeight >= 0.0) || !std::isfinite(constraintWeight))
    message << "constraintWeight must be a finite number >= 0, got " << constraintWeight;
  else if (!(curvatureFilterRadius >= 0.0 && curvatureFilterRadius <= 1.0))
    message
        << "curvatureFilterRadius must be in [0, 1] (fraction of the bounding-box diagonal), got "
        << curvatureFilterRadius;
  else if (!(singularityDistance >= 0.0) || !std::isfinite(singularityDistance))
    message << "singularityDistance must be a finite distance >= 0 (0: derived), got "
            << singularityDistance;
  else if (!(singularityDistanceFraction > 0.0 && singularityDistanceFraction <= 1.0))
    message << "singularityDistanceFraction must be in (0, 1], got " << singularityDistanceFraction;
  else if (maxMergedIndex < 0)
    message << "maxMergedIndex must be >= 0 (0: no limit), got " << maxMergedIndex;
  else if (boundaryTangentReach < 0 || boundaryTangentReach > 16)
    message << "boundaryTangentReach must be in [0, 16], got " << boundaryTangentReach;
  else if (!(sharpEdgeAngle >= 0.0 && sharpEdgeAngle <= 180.0))
    message << "sharpEdgeAngle must be in [0, 180] degrees (0: no creases), got " << sharpEdgeAngle;
  else if (!(sharpLineLength >= 0.0) || !std::isfinite(sharpLineLength))
    message << "sharpLineLength must be a finite length >= 0, got " << sharpLineLength;
  else if (!(sharpEdgeWeight > 0.0) || !std::isfinite(sharpEdgeWeight))
    message << "sharpEdgeWeight must be a finite number > 0, got " << sharpEdgeWeight;
  else if (threads < 1)
    message << "threads must be >= 1, got " << threads;
  else if (const auto problem = curvature.validate(); !problem.empty())
    message << "curvature." << problem;
  return message.str();
}

RosyField rosyFieldFromDirections(const TriMesh& mesh, std::vector<Eigen::Vector3d> directions,
                                  int n) {
  if (n < 2 || n % 2 != 0)
    throw Error(
        ErrorCode::InvalidOption,
        "rosy field: symmetry order N must be even and at least 2, got " + std::to_string(n));
  if (directions.size() != mesh.n_faces())
    throw Error(ErrorCode::InvalidOption, "rosy field: " + std::to_string(directions.size()) +
                                              " directions for " + std::to_string(mesh.n_faces()) +
                                              " faces");
  for (std::size_t f = 0; f < directions.size(); ++f)
    if (!directions[f].allFinite())
      throw Error(ErrorCode::InvalidOption,
                  "rosy field: the direction of face " + std::to_string(f) + " is not finite");
  const field::FieldGeometry geometry(mesh);
  std::vector<double> angles(directions.size());
  for (std::size_t f = 0; f < directions.size(); ++f)
    angles[f] = geometry.frames.angleOf(static_cast<int>(f), directions[f]);
  return field::rosyFieldFromAngles(mesh, geometry, angles, n);
}

RosyField computeRosyField(const TriMesh& mesh, const FieldOptions& options,
                           const RunContext& context) {
  if (const auto problem = options.validate(); !problem.empty())
    throw Error(ErrorCode::InvalidOption, "field options: " + problem);
  if (mesh.n_faces() == 0) throw Error(ErrorCode::InvalidMesh, "field: the mesh has no faces");
  const int n = options.n;
  const int nf = static_cast<int>(mesh.n_faces());
  const double diagonal = boundingBoxDiagonal(mesh);
  Timings timings;
  const auto step = [&](double fraction) {
    context.throwIfCanceled();
    context.report(stage::kField, fraction);
  };

  step(0.0);
  const auto start = std::chrono::steady_clock::now();
  // Two phases of two independent tasks each, on two threads when options.threads allows (the
  // second task's timings are appended after the first's).
  Timings sideTimings;
  std::optional<field::FieldGeometry> geometryOf;
  std::vector<int> vertexOrder;
  field::SmoothnessTerms terms;
  std::optional<field::EdgeGraph> graph;
  // 1. The frames and transport, and the vertex graph's elimination order (one for every
  //    connection solve of the run); the solve's terms with the face graph's order.
  runBoth(
      options.threads,
      [&] {
        geometryOf.emplace(timed(timings, "geometry", [&] { return field::FieldGeometry(mesh); }));
        vertexOrder = timed(timings, "connection", [&] { return field::vertexGraphOrder(mesh); });
      },
      [&] {
        terms = timed(sideTimings, "initial_solve", [&] { return field::smoothnessTerms(mesh); });
        graph.emplace(mesh);
      });
  const field::FieldGeometry& geometry = *geometryOf;

  // 2. The connection corrected for K̄; the curvature and the constraints.
  step(0.1);
  field::SmoothSolveInput input;
  std::vector<bool> sharp;  // #E, or empty without sharp-edge constraints
  std::vector<double> density;
  std::vector<double> initialCorrections;
  runBoth(
      options.threads,
      [&] {
        const field::ConnectionCorrector corrector = timed(timings, "connection", [&] {
          return field::ConnectionCorrector(mesh, geometry, field::interiorVertices(mesh),
                                            field::interiorEdges(mesh), vertexOrder);
        });
        const std::vector<double> filtered = timed(timings, "filter_gauss_curvature", [&] {
          return field::filterGaussCurvature(
              mesh, geometry, field::filterSteps(mesh, options.curvatureFilterRadius * diagonal),
              options.threads);
        });
        initialCorrections = timed(timings, "filter_gauss_curvature",
                                   [&] { return corrector.corrections(filtered); });
      },
      [&] {
        const Curvature curvature = timed(
            sideTimings, "curvature", [&] { return computeCurvature(mesh, options.curvature); });
        input = timed(sideTimings, "constraints", [&] {
          field::SmoothSolveInput in;
          in.free.assign(nf, true);
          in.value.assign(nf, Complex(0.0, 0.0));
          in.softWeight.assign(nf, 0.0);
          in.softTarget.assign(nf, Complex(0.0, 0.0));
          if (options.curvatureConstraints)
            addCurvatureConstraints(mesh, geometry, curvature, options, in);
          if (options.boundary == BoundaryAlignment::Tangent)
            fixBoundaryFaces(mesh, geometry, n, options.boundaryTangentReach, in);
          if (options.sharpEdgeAngle > 0.0) {
            sharp = sharpEdges(mesh, options.sharpEdgeAngle, options.sharpLineLength);
            if (options.compatibleCreasesOnly) sharp = latticeCompatibleCreases(mesh, sharp, n);
            addSharpEdgeConstraints(mesh, geometry, n, sharp, options.sharpEdgeWeight, in);
          }
          return in;
        });
        // The Gauss curvature density K/A that weighs merged positions (section 3.3).
        density.assign(mesh.n_vertices(), 0.0);
        for (std::size_t v = 0; v < density.size(); ++v)
          density[v] = curvature.area[v] > 0.0 ? curvature.gauss[v] / curvature.area[v] : 0.0;
      });
  timings.insert(timings.end(), sideTimings.begin(), sideTimings.end());

  step(0.3);
  const std::vector<Complex> initial = timed(timings, "initial_solve", [&] {
    return field::solveSmoothField(terms, geometry.transport, initialCorrections,
                                   geometry.frames.area, n, input);
  });
  RosyField initialField = timed(timings, "initial_singularities", [&] {
    return field::rosyFieldFromAngles(mesh, geometry, anglesOf(initial, n), n);
  });
  const int initialCount = static_cast<int>(initialField.singularities.size());
  const double dSing = options.singularityDistance > 0.0
                           ? options.singularityDistance
                           : options.singularityDistanceFraction * diagonal;

  // Clustering rounds (section 3.3): collapse the singularity graph, re-solve in R with K̄ at the
  // remaining singularities. The smooth re-solve places a singularity on a neighbouring vertex or
  // leaves a close ± pair now and then, so the rounds repeat on the new field (R shrinks to the
  // new collapses) until nothing is collapsed or kClusteringRounds is reached.
  const ClusterSolveInputs inputs{terms, *graph, vertexOrder, input.free};
  RosyField result = std::move(initialField);
  ClusterSolveState state{initial, initialCorrections, std::vector<bool>(nf, true),
                          std::vector<double>(mesh.n_edges(), 0.0)};
  std::vector<int> previousIndex;  // #V: the nodes left by the last clustering (0 elsewhere)
  int previousCollapses = std::numeric_limits<int>::max();
  for (int round = 0; options.clusterSingularities && round < kClusteringRounds; ++round) {
    step(0.6 + 0.1 * round);
    const field::ClusteringResult clusters = timed(timings, "clustering", [&] {
      // Singularities that the last clustering left in place were checked against each other.
      std::vector<field::ClusterNode> nodes;
      std::vector<bool> settled;
      for (const auto& s : result.singularities) {
        if (s.onBoundary) continue;
        nodes.push_back({s.vertex, s.index});
        settled.push_back(!previousIndex.empty() && previousIndex[s.vertex] == s.index);
      }
      return field::clusterSingularities(mesh, *graph, nodes, density, dSing,
                                         options.maxMergedIndex, settled, options.threads);
    });
    // Stop when a round does not collapse fewer pairs than the one before: the re-solve is then
    // recreating the pairs it cancels (see the known limitation in rosy_field.h).
    if (clusters.collapses == 0 || clusters.collapses >= previousCollapses) break;
    previousCollapses = clusters.collapses;
    previousIndex.assign(mesh.n_vertices(), 0);
    for (const auto& node : clusters.nodes) previousIndex[node.vertex] = node.index;
    timed(timings, "cluster_solve",
          [&] { resolveRegion(mesh, geometry, inputs, clusters, dSing, n, state); });
    result = timed(timings, "cluster_singularities", [&] {
      return field::rosyFieldFromAngles(mesh, geometry, anglesOf(state.u, n), n,
                                        state.matchingShift);
    });
  }
  // Interior singularities of a higher index than the lattice takes that clustering left (the
  // smoothest field's zero of order N at the centre of a flat cap) are split into first-order
  // ones around their vertex, away from boundaries and creases, and the field is re-solved there
  // as after a clustering.
  if (options.maxMergedIndex > 0) {
    const field::ClusteringResult split = timed(timings, "split", [&] {
      std::vector<field::ClusterNode> nodes;
      for (const auto& s : result.singularities)
        if (!s.onBoundary) nodes.push_back({s.vertex, s.index});
      // Boundary and crease vertices: no split-off singularity goes there.
      std::vector<bool> blocked(mesh.n_vertices(), false);
      for (const auto vh : mesh.vertices()) blocked[vh.idx()] = mesh.is_boundary(vh);
      if (!sharp.empty())
        for (const auto eh : mesh.edges())
          if (sharp[eh.idx()]) blocked[eh.v0().idx()] = blocked[eh.v1().idx()] = true;
      return field::splitHighOrderNodes(mesh, *graph, nodes, geometry.angleDefect, blocked, n,
                                        options.maxMergedIndex, dSing);
    });
    if (split.collapses > 0) {
      timed(timings, "split_solve",
            [&] { resolveRegion(mesh, geometry, inputs, split, dSing, n, state); });
      result = timed(timings, "split_singularities", [&] {
        return field::rosyFieldFromAngles(mesh, geometry, anglesOf(state.u, n), n,
                                          state.matchingShift);
      });
    }
  }
  result.singularitiesInitial = initialCount;
  if (std::find(sharp.begin(), sharp.end(), true) != sharp.end()) result.sharpEdges = sharp;
  result.singularityDistance = dSing;
  result.timings = std::move(timings);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  context.report(stage::kField, 1.0);
  return result;
}

std::optional<RosyField> computeCompatibleCreaseField(const TriMesh& mesh, const RosyField& field,
                                                      const FieldOptions& options,
                                                      const RunContext& context) {
  if (field.sharpEdges.empty() ||
      latticeCompatibleCreases(mesh, field.sharpEdges, field.n) == field.sharpEdges)
    return std::nullopt;
  FieldOptions compatible = options;
  compatible.compatibleCreasesOnly = true;
  return computeRosyField(mesh, compatible, context);
}

}  // namespace hexcover
