#include "core/param/conformal_scale.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/common/sparse_cholesky.h"
#include "core/geometry/frames.h"

namespace hexcover {
namespace {

/// x reduced by whole multiples of `period` into [−period/2, period/2].
double reduce(double x, double period) { return x - std::round(x / period) * period; }

/// cot of the corner of face(h) opposite to the edge of h.
double oppositeCotangent(const TriMesh& mesh, OpenMesh::SmartHalfedgeHandle h) {
  const Eigen::Vector3d apex = toEigen(mesh.point(h.next().to()));
  const Eigen::Vector3d a = toEigen(mesh.point(h.from())) - apex;
  const Eigen::Vector3d b = toEigen(mesh.point(h.to())) - apex;
  const double sine = a.cross(b).norm();
  return sine > 0.0 ? a.dot(b) / sine : 0.0;
}

}  // namespace

std::vector<double> conformalFaceScale(const TriMesh& mesh, const RosyField& field,
                                       double maxLogScale, double maxLogGrowth) {
  if (field.faceDirection.size() != mesh.n_faces() || field.edgeMatching.size() != mesh.n_edges())
    throw Error(ErrorCode::InvalidOption, "conformal scale: the field does not belong to this mesh");
  const FaceFrames frames = computeFaceFrames(mesh);
  const std::vector<double> transport = edgeTransportAngles(mesh, frames);
  const FaceComponents components = faceComponents(mesh);
  const int nV = static_cast<int>(mesh.n_vertices());
  const double period = 2.0 * M_PI / field.n;

  // L φ = Dᵀ δ with the cotangent Laplacian (weights clamped positive, which only reweights
  // the least squares) and the field's turn δ_e across interior edges.
  constexpr double kMinWeight = 1e-3;
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nV);
  for (const auto eh : mesh.edges()) {
    const auto h0 = eh.h0(), h1 = eh.h1();
    double weight = 0.0;
    if (!h0.is_boundary()) weight += 0.5 * oppositeCotangent(mesh, h0);
    if (!h1.is_boundary()) weight += 0.5 * oppositeCotangent(mesh, h1);
    weight = std::max(weight, kMinWeight);
    const int a = h0.from().idx(), b = h0.to().idx();
    triplets.emplace_back(a, a, weight);
    triplets.emplace_back(b, b, weight);
    triplets.emplace_back(a, b, -weight);
    triplets.emplace_back(b, a, -weight);
    if (mesh.is_boundary(eh)) continue;
    const int f0 = h0.face().idx(), f1 = h1.face().idx();
    const double delta = reduce(frames.angleOf(f1, field.faceDirection[f1]) -
                                    frames.angleOf(f0, field.faceDirection[f0]) - transport[eh.idx()],
                                period);
    rhs[b] += delta;
    rhs[a] -= delta;
  }
  // Gauge: φ = 0 at the first vertex of each component (and at isolated vertices).
  std::vector<bool> pinned(nV, false);
  std::vector<bool> componentPinned(components.count, false);
  for (const auto vh : mesh.vertices()) {
    if (mesh.is_isolated(vh)) {
      pinned[vh.idx()] = true;
      continue;
    }
    const int c = components.faceComponent[vh.faces().begin()->idx()];
    if (!componentPinned[c]) componentPinned[c] = pinned[vh.idx()] = true;
  }
  Eigen::SparseMatrix<double> laplacian(nV, nV);
  std::vector<Eigen::Triplet<double>> kept;
  kept.reserve(triplets.size() + nV);
  for (const auto& t : triplets)
    if (!pinned[t.row()] && !pinned[t.col()]) kept.push_back(t);
  for (int v = 0; v < nV; ++v)
    if (pinned[v]) {
      kept.emplace_back(v, v, 1.0);
      rhs[v] = 0.0;
    }
  laplacian.setFromTriplets(kept.begin(), kept.end());
  const SparseCholesky<double> solver(laplacian);
  if (!solver.ok())
    throw Error(ErrorCode::NumericalFailure, "conformal scale: the Laplacian could not be factorized");
  const Eigen::VectorXd phi = solver.solve(rhs);

  // Face values, normalized per component to a mean lattice unit of 1, then clamped.
  std::vector<double> logScale(mesh.n_faces(), 0.0);
  std::vector<double> area(mesh.n_faces(), 0.0);
  std::vector<double> scaledLength(components.count, 0.0), totalArea(components.count, 0.0);
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    for (const auto vh : fh.vertices()) logScale[f] += phi[vh.idx()] / 3.0;
    if (!std::isfinite(logScale[f])) logScale[f] = 0.0;
    area[f] = frames.area[f];
    scaledLength[components.faceComponent[f]] += area[f] * std::exp(-logScale[f]);
    totalArea[components.faceComponent[f]] += area[f];
  }
  std::vector<double> scale(mesh.n_faces(), 1.0);
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx(), c = components.faceComponent[f];
    const double shift = scaledLength[c] > 0.0 ? std::log(scaledLength[c] / totalArea[c]) : 0.0;
    if (area[f] > 0.0)
      scale[f] = std::exp(std::clamp(logScale[f] + shift, -maxLogGrowth, maxLogScale));
  }
  return scale;
}


double conformalVertexCountFactor(const TriMesh& mesh, const std::vector<double>& faceScale) {
  double area = 0.0, scaledArea = 0.0;
  for (const auto fh : mesh.faces()) {
    const double a = mesh.calc_face_area(fh);
    area += a;
    scaledArea += a * faceScale[fh.idx()] * faceScale[fh.idx()];
  }
  return area > 0.0 ? scaledArea / area : 1.0;
}

}  // namespace hexcover
