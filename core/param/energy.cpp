#include "core/param/energy.h"

#include <cmath>

#include "core/param/lattice.h"

namespace hexcover::param_detail {
namespace {

using Triplet = Eigen::Triplet<double>;

// Crease edges further than this from a lattice direction in their face's chart are left free.
constexpr double kCreaseAngleTolerance = 10.0 * M_PI / 180.0;

// The rows of the creases after the face rows `faceRows`: their triplets (their weights in
// ls.rowWeight stay 0 until setLatticeScale and setCreaseTargets).
void addCreaseRows(const Unknowns& u, const std::vector<CreaseEdge>& creases, int faceRows,
                   std::vector<Triplet>& triplets, LeastSquares& ls) {
  ls.rowWeight = Eigen::VectorXd::Zero(kRowsPerCrease * static_cast<int>(creases.size()));
  for (std::size_t i = 0; i < creases.size(); ++i) {
    const auto& crease = creases[i];
    const int first = faceRows + kRowsPerCrease * static_cast<int>(i);
    const auto add = [&](int row, int wedge, double sign) {
      for (int coordinate = 0; coordinate < 2; ++coordinate)
        for (const auto& [column, value] : u.wedgeRows[wedge][coordinate])
          triplets.emplace_back(row, column, sign * crease.across[coordinate] * value);
    };
    add(first, crease.wedgeTo, 1.0);
    add(first, crease.wedgeFrom, -1.0);
    add(first + 1, crease.wedgeFrom, 1.0);
    add(first + 2, crease.wedgeTo, 1.0);
  }
}

}  // namespace

FaceGeometry computeFaceGeometry(const TriMesh& mesh, const RosyField& field, const CutGraph& cut) {
  const int nF = static_cast<int>(mesh.n_faces());
  FaceGeometry g;
  g.area.resize(nF);
  g.grad.resize(nF);
  g.local.resize(nF);
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    std::array<Eigen::Vector3d, 3> p;
    int i = 0;
    for (const auto h : mesh.fh_range(fh)) p[i++] = toEigen(mesh.point(mesh.to_vertex_handle(h)));
    const Eigen::Vector3d cross = (p[1] - p[0]).cross(p[2] - p[0]);
    const double doubleArea = cross.norm();
    g.area[f] = 0.5 * doubleArea;
    if (!(doubleArea > 0.0)) {
      for (auto& v : g.grad[f]) v.setZero();
      for (auto& v : g.local[f]) v.setZero();
      continue;
    }
    const Eigen::Vector3d normal = cross / doubleArea;
    Eigen::Vector3d d = field.faceDirection[f] - field.faceDirection[f].dot(normal) * normal;
    if (!(d.norm() > 1e-12)) d = p[1] - p[0];
    d.normalize();
    const double angle = 2.0 * M_PI * cut.faceRotation[f] / cut.n;
    const Eigen::Vector3d x = std::cos(angle) * d + std::sin(angle) * normal.cross(d);
    const Eigen::Vector3d y = normal.cross(x);
    for (int c = 0; c < 3; ++c) {
      // ∇φ_c = n × e_c / (2A), e_c the edge opposite corner c, counter-clockwise.
      const Eigen::Vector3d e = p[(c + 2) % 3] - p[(c + 1) % 3];
      const Eigen::Vector3d gradient = normal.cross(e) / doubleArea;
      g.grad[f][c] = {gradient.dot(x), gradient.dot(y)};
      g.local[f][c] = {(p[c] - p[0]).dot(x), (p[c] - p[0]).dot(y)};
    }
  }
  return g;
}

std::vector<CreaseEdge> findCreases(const TriMesh& mesh, const CutMesh& cm,
                                    const FaceGeometry& geometry, const RosyField& field,
                                    double weight) {
  std::vector<CreaseEdge> creases;
  if (field.sharpEdges.empty() || !(weight > 0.0)) return creases;
  const int n = field.n;
  const double step = 2.0 * M_PI / n;  // lattice directions: multiples of π/3 (N = 6), π/2
  const Eigen::Matrix2d toLattice = latticeBasis(n).inverse();  // Cartesian p ↦ (a, b)
  // The lattice coordinate across direction k: b along e1, a along e2, a + b along e2 − e1.
  const std::array<Eigen::Vector2d, 3> acrossInLattice{
      Eigen::Vector2d(0.0, 1.0), Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(1.0, 1.0)};
  for (const auto eh : mesh.edges()) {
    if (!field.sharpEdges[eh.idx()]) continue;
    for (const auto h : {eh.h0(), eh.h1()}) {
      const auto fh = h.face();
      const int f = fh.idx();
      if (!(geometry.area[f] > 0.0)) continue;
      int corner = 0, cTo = -1, cFrom = -1;
      for (const auto g : mesh.fh_range(fh)) {
        if (g == h) cTo = corner;
        if (g == h.prev()) cFrom = corner;
        ++corner;
      }
      const Eigen::Vector2d d = geometry.local[f][cTo] - geometry.local[f][cFrom];
      const double angle = std::atan2(d.y(), d.x());
      const int k = wrapIndex(static_cast<int>(std::lround(angle / step)), n / 2);
      if (std::abs(std::remainder(angle - k * step, M_PI)) > kCreaseAngleTolerance) continue;
      CreaseEdge crease;
      crease.wedgeFrom = cm.halfedgeWedge[h.prev().idx()];
      crease.wedgeTo = cm.halfedgeWedge[h.idx()];
      crease.face = f;
      crease.length = d.norm();
      crease.across = toLattice.transpose() * acrossInLattice[k];
      creases.push_back(crease);
    }
  }
  return creases;
}

LeastSquares buildLeastSquares(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u,
                               const FaceGeometry& geometry, double conformalWeight,
                               const std::vector<CreaseEdge>& creases) {
  const int nF = static_cast<int>(mesh.n_faces());
  const int rows = kRowsPerFace * nF + kRowsPerCrease * static_cast<int>(creases.size());
  const double rootWeight = std::sqrt(conformalWeight);
  LeastSquares ls;
  ls.target = Eigen::VectorXd::Zero(rows);
  ls.faceArea = Eigen::VectorXd::Zero(nF);
  std::vector<Triplet> triplets;
  triplets.reserve(static_cast<std::size_t>(nF) * 72);
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    if (!(geometry.area[f] > 0.0)) continue;
    ls.faceArea[f] = geometry.area[f];
    const int row = kRowsPerFace * f;
    int c = 0;
    for (const auto h : mesh.fh_range(fh)) {
      const auto& rows = u.wedgeRows[cm.halfedgeWedge[h.idx()]];
      const Eigen::Vector2d& g = geometry.grad[f][c++];
      for (int coordinate = 0; coordinate < 2; ++coordinate)
        for (const auto& [column, value] : rows[coordinate])
          for (int axis = 0; axis < 2; ++axis)
            triplets.emplace_back(row + 2 * coordinate + axis, column, value * g[axis]);
      if (rootWeight == 0.0) continue;
      for (const auto& [column, value] : rows[0]) {  // u
        triplets.emplace_back(row + 4, column, rootWeight * value * g[1]);
        triplets.emplace_back(row + 5, column, -rootWeight * value * g[0]);
      }
      for (const auto& [column, value] : rows[1]) {  // v
        triplets.emplace_back(row + 4, column, rootWeight * value * g[0]);
        triplets.emplace_back(row + 5, column, rootWeight * value * g[1]);
      }
    }
  }
  addCreaseRows(u, creases, kRowsPerFace * nF, triplets, ls);
  ls.gradient.resize(rows, u.columns());
  ls.gradient.setFromTriplets(triplets.begin(), triplets.end());
  return ls;
}

void setLatticeScale(const std::vector<double>& faceScale, double creaseWeight,
                     std::vector<CreaseEdge>& creases, LeastSquares& ls) {
  for (int f = 0; f < static_cast<int>(faceScale.size()); ++f)
    if (ls.faceArea[f] > 0.0)
      ls.target[kRowsPerFace * f] = ls.target[kRowsPerFace * f + 3] = faceScale[f];
  for (std::size_t i = 0; i < creases.size(); ++i) {
    CreaseEdge& crease = creases[i];
    crease.weight = creaseWeight * crease.length * faceScale[crease.face];
    ls.rowWeight[kRowsPerCrease * i] = crease.weight;
  }
}

void setCreaseTargets(const Unknowns& u, const std::vector<CreaseEdge>& creases,
                      const Eigen::VectorXd& x, LeastSquares& ls) {
  const int faceRows =
      static_cast<int>(ls.target.size()) - kRowsPerCrease * static_cast<int>(creases.size());
  for (std::size_t i = 0; i < creases.size(); ++i) {
    const auto& crease = creases[i];
    const double mean = 0.5 * crease.across.dot(wedgePosition(u, crease.wedgeFrom, x) +
                                                wedgePosition(u, crease.wedgeTo, x));
    const int first = faceRows + kRowsPerCrease * static_cast<int>(i);
    ls.target[first + 1] = ls.target[first + 2] = std::round(mean);
    ls.rowWeight[kRowsPerCrease * i + 1] = ls.rowWeight[kRowsPerCrease * i + 2] = crease.weight;
  }
}

}  // namespace hexcover::param_detail
