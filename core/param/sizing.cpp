#include "core/param/sizing.h"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/common/error.h"
#include "core/common/median.h"
#include "core/param/lattice.h"

namespace hexcover {

double edgeLengthForVertexCount(const TriMesh& mesh, int targetVertices, int n,
                                const std::vector<double>& vertexSizing) {
  if (targetVertices < 1)
    throw Error(ErrorCode::InvalidOption, "target vertex count must be at least 1");
  double sizedArea = 0.0;
  for (const auto fh : mesh.faces()) {
    double s = vertexSizing.empty() ? 1.0 : 0.0;
    if (!vertexSizing.empty())
      for (const auto vh : fh.vertices()) s += vertexSizing[vh.idx()] / 3.0;
    sizedArea += mesh.calc_face_area(fh) * s * s;
  }
  // Per vertex: two lattice triangles (N = 6) or one lattice square (N = 4) of area c·h².
  const double areaPerVertexOverH2 = 2.0 * latticeTriangleArea(n);
  return std::sqrt(sizedArea / (areaPerVertexOverH2 * targetVertices));
}

std::vector<double> curvatureSizing(const std::vector<double>& absMaxCurvature, double minScale,
                                    double maxScale) {
  if (absMaxCurvature.empty()) throw Error(ErrorCode::InvalidOption, "no curvature values given");
  if (!(minScale > 0.0 && minScale <= maxScale))
    throw Error(ErrorCode::InvalidOption, "sizing range must satisfy 0 < min ≤ max");
  std::vector<double> finite;
  for (const double k : absMaxCurvature)
    if (std::isfinite(k)) finite.push_back(std::abs(k));
  const double typical = median(std::move(finite));
  std::vector<double> sizing(absMaxCurvature.size(), 1.0);
  if (!(typical > 0.0)) return sizing;
  for (std::size_t v = 0; v < sizing.size(); ++v) {
    const double k = std::isfinite(absMaxCurvature[v]) ? std::abs(absMaxCurvature[v]) : typical;
    sizing[v] = std::clamp(k / typical, minScale, maxScale);
  }
  return sizing;
}

std::vector<double> smoothSizing(const TriMesh& mesh, const std::vector<double>& sizing,
                                 double radius) {
  const int nV = static_cast<int>(mesh.n_vertices());
  if (static_cast<int>(sizing.size()) != nV)
    throw Error(ErrorCode::InvalidOption, "sizing has " + std::to_string(sizing.size()) +
                                              " values for " + std::to_string(nV) + " vertices");
  for (const double s : sizing)
    if (!(std::isfinite(s) && s > 0.0))
      throw Error(ErrorCode::InvalidOption, "sizing values must be positive and finite");
  double edgeSum = 0.0;
  for (const auto eh : mesh.edges()) edgeSum += mesh.calc_edge_length(eh);
  if (nV == 0 || mesh.n_edges() == 0 || !(radius > 0.0)) return sizing;
  const double meanEdge = edgeSum / static_cast<double>(mesh.n_edges());
  const double weight = (radius / meanEdge) * (radius / meanEdge);
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::VectorXd logSizing(nV);
  for (int v = 0; v < nV; ++v) {
    triplets.emplace_back(v, v, 1.0);
    logSizing[v] = std::log(sizing[v]);
  }
  for (const auto eh : mesh.edges()) {
    const int a = eh.v0().idx(), b = eh.v1().idx();
    triplets.emplace_back(a, a, weight);
    triplets.emplace_back(b, b, weight);
    triplets.emplace_back(a, b, -weight);
    triplets.emplace_back(b, a, -weight);
  }
  Eigen::SparseMatrix<double> system(nV, nV);
  system.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(system);
  const Eigen::VectorXd smoothed = solver.solve(logSizing);
  std::vector<double> out(nV);
  for (int v = 0; v < nV; ++v)
    out[v] = std::isfinite(smoothed[v]) ? std::exp(smoothed[v]) : sizing[v];
  return out;
}

}  // namespace hexcover
