#include "core/field/smooth_solve.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/common/error.h"
#include "core/common/sparse_cholesky.h"

namespace hexcover::field {
namespace {

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

constexpr int kPowerIterations = 30;
constexpr double kPowerTolerance = 1e-6;  ///< change of the unit iterate that ends the iteration

}  // namespace

SmoothnessTerms smoothnessTerms(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> centroid(mesh.n_faces());
  for (const auto fh : mesh.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto vh : fh.vertices()) c += toEigen(mesh.point(vh));
    centroid[fh.idx()] = c / 3.0;
  }
  SmoothnessTerms terms;
  for (const auto eh : mesh.edges()) {
    if (mesh.is_boundary(eh)) continue;
    const int f0 = eh.h0().face().idx(), f1 = eh.h1().face().idx();
    const double length = mesh.calc_edge_length(eh);
    const double dual = (centroid[f0] - centroid[f1]).norm();
    const double w = dual > 0.0 ? length / dual : 1e3;
    terms.edge.push_back(eh.idx());
    terms.face0.push_back(f0);
    terms.face1.push_back(f1);
    terms.weight.push_back(std::clamp(std::isfinite(w) ? w : 1e3, 1e-3, 1e3));
  }
  std::vector<std::pair<int, int>> dualEdges(terms.face0.size());
  for (std::size_t t = 0; t < dualEdges.size(); ++t)
    dualEdges[t] = {terms.face0[t], terms.face1[t]};
  terms.faceOrder = minimumDegreeOrder(static_cast<int>(mesh.n_faces()), dualEdges);
  return terms;
}

std::vector<Complex> solveSmoothField(const SmoothnessTerms& terms,
                                      const std::vector<double>& transport,
                                      const std::vector<double>& corrections,
                                      const std::vector<double>& faceArea, int n,
                                      const SmoothSolveInput& input) {
  const int nf = static_cast<int>(input.free.size());
  std::vector<int> unknown(nf, -1);
  int m = 0;
  for (const int f : terms.faceOrder)  // numbered in elimination order
    if (input.free[f]) unknown[f] = m++;
  std::vector<Complex> u = input.value;
  u.resize(nf);
  if (m == 0) return u;

  // Groups of free faces, and whether each is anchored by a fixed face or a soft constraint.
  std::vector<int> parent(m);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<bool> anchored(m, false);
  const auto soft = [&](int f) { return input.softWeight.empty() ? 0.0 : input.softWeight[f]; };

  std::vector<Eigen::Triplet<Complex>> triplets;
  triplets.reserve(terms.weight.size() + m);
  std::vector<double> diagonal(m, 0.0);
  Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(m);
  for (std::size_t t = 0; t < terms.weight.size(); ++t) {
    const int f0 = terms.face0[t], f1 = terms.face1[t];
    const int i0 = unknown[f0], i1 = unknown[f1];
    if (i0 < 0 && i1 < 0) continue;
    const double w = terms.weight[t];
    const int e = terms.edge[t];
    const Complex r = std::polar(1.0, n * (transport[e] + corrections[e]));
    if (i0 >= 0) diagonal[i0] += w;
    if (i1 >= 0) diagonal[i1] += w;
    if (i0 >= 0 && i1 >= 0) {  // ∂E/∂ū1 = w (u1 − r u0), ∂E/∂ū0 = w (u0 − r̄ u1)
      // Only the lower triangle is factorized: entry (i1, i0) = −w r, (i0, i1) = −w r̄.
      if (i1 > i0)
        triplets.emplace_back(i1, i0, -w * r);
      else
        triplets.emplace_back(i0, i1, -w * std::conj(r));
      const int a = findRoot(parent, i0), b = findRoot(parent, i1);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    } else if (i0 >= 0) {
      rhs[i0] += w * std::conj(r) * u[f1];
      anchored[i0] = true;
    } else if (i1 >= 0) {
      rhs[i1] += w * r * u[f0];
      anchored[i1] = true;
    }
  }
  for (int f = 0; f < nf; ++f) {
    const int i = unknown[f];
    if (i < 0 || !(soft(f) > 0.0)) continue;
    diagonal[i] += soft(f);
    rhs[i] += soft(f) * input.softTarget[f];
    anchored[i] = true;
  }
  std::vector<bool> groupAnchored(m, false);
  for (int i = 0; i < m; ++i)
    if (anchored[i]) groupAnchored[findRoot(parent, i)] = true;
  bool anyFloating = false;
  for (int i = 0; i < m; ++i) {
    const bool floating = !groupAnchored[findRoot(parent, i)];
    anyFloating = anyFloating || floating;
    // A floating group's L may be singular (a flat connection): shift it slightly.
    triplets.emplace_back(
        i, i, diagonal[i] * (floating ? 1.0 + 1e-9 : 1.0) + (diagonal[i] > 0 ? 0.0 : 1.0));
  }
  Eigen::SparseMatrix<Complex> matrix(m, m);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  const SparseCholesky<Complex> solver(matrix, RowOrder::AsGiven);
  if (!solver.ok())
    throw Error(ErrorCode::NumericalFailure,
                "field: the smoothness system could not be factorized");
  Eigen::VectorXcd x = solver.solve(rhs);

  if (anyFloating) {  // inverse power iteration L y ← M y on the floating groups only
    std::vector<double> mass(m, 0.0);
    for (int f = 0; f < nf; ++f)
      if (unknown[f] >= 0) mass[unknown[f]] = faceArea[f];
    Eigen::VectorXcd y = Eigen::VectorXcd::Zero(m);
    for (int i = 0; i < m; ++i)
      if (!groupAnchored[findRoot(parent, i)]) y[i] = 1.0;
    std::vector<double> norm(m, 0.0);
    Eigen::VectorXcd previous = Eigen::VectorXcd::Zero(m);
    for (int iteration = 0; iteration < kPowerIterations; ++iteration) {
      // Per group: yᴴ M y = 1.
      std::fill(norm.begin(), norm.end(), 0.0);
      for (int i = 0; i < m; ++i) norm[findRoot(parent, i)] += mass[i] * std::norm(y[i]);
      for (int i = 0; i < m; ++i) {
        const double n2 = norm[findRoot(parent, i)];
        y[i] = n2 > 0.0 ? y[i] / std::sqrt(n2) : y[i];
      }
      // (L⁻¹ M) scales every generalized eigencomponent by a positive number, so the
      // normalized iterate settles (phase included) once the smallest eigenvector dominates;
      // the change is measured in the norm of M, in which each group's iterate has norm 1.
      double change = 0.0;
      for (int i = 0; i < m; ++i) change += mass[i] * std::norm(y[i] - previous[i]);
      if (change < kPowerTolerance * kPowerTolerance) break;
      previous = y;
      for (int i = 0; i < m; ++i) y[i] *= mass[i];
      y = solver.solve(y);
    }
    // The phase is free: per group, the one that makes the plain sum of the iterate real and
    // positive (see the header).
    std::vector<Complex> sum(m, Complex(0.0, 0.0));
    for (int i = 0; i < m; ++i) sum[findRoot(parent, i)] += y[i];
    for (int i = 0; i < m; ++i) {
      const int root = findRoot(parent, i);
      if (groupAnchored[root]) continue;
      const double magnitude = std::abs(sum[root]);
      x[i] = magnitude > 0.0 ? y[i] * std::conj(sum[root]) / magnitude : y[i];
    }
  }
  for (int f = 0; f < nf; ++f)
    if (unknown[f] >= 0) u[f] = x[unknown[f]];
  return u;
}

}  // namespace hexcover::field
