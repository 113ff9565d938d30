#include "core/geometry/sharp_edges.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace hexcover {
namespace {

/// Largest turn of a crease line at one of its vertices; a sharper turn is a corner that ends it
/// (and a cluster of folds at a spike of a scan breaks into short pieces).
constexpr double kMaxLineTurn = 45.0 * M_PI / 180.0;

Eigen::Vector3d faceNormal(const TriMesh& mesh, OpenMesh::SmartFaceHandle f) {
  std::array<Eigen::Vector3d, 3> p;
  int i = 0;
  for (const auto v : f.vertices()) p[i++] = toEigen(mesh.point(v));
  const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
  return n.norm() > 0.0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
}

}  // namespace

std::vector<double> dihedralAngles(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> normal(mesh.n_faces());
  for (const auto f : mesh.faces()) normal[f.idx()] = faceNormal(mesh, f);
  std::vector<double> angle(mesh.n_edges(), 0.0);
  for (const auto e : mesh.edges()) {
    if (e.is_boundary()) continue;
    const Eigen::Vector3d& n0 = normal[e.h0().face().idx()];
    const Eigen::Vector3d& n1 = normal[e.h1().face().idx()];
    if (n0.isZero() || n1.isZero()) continue;
    angle[e.idx()] = std::acos(std::clamp(n0.dot(n1), -1.0, 1.0)) * 180.0 / M_PI;
  }
  return angle;
}

std::vector<bool> sharpEdges(const TriMesh& mesh, double minDihedralDegrees,
                             double minLineLength) {
  std::vector<bool> sharp(mesh.n_edges(), false);
  if (!(minDihedralDegrees > 0.0)) return sharp;
  const std::vector<double> dihedral = dihedralAngles(mesh);
  for (const auto e : mesh.edges()) sharp[e.idx()] = dihedral[e.idx()] >= minDihedralDegrees;
  std::vector<int> sharpAt(mesh.n_vertices(), 0);
  for (const auto e : mesh.edges())
    if (sharp[e.idx()]) ++sharpAt[e.v0().idx()], ++sharpAt[e.v1().idx()];
  // Lines: from each unvisited sharp edge, walk both ways through vertices with exactly two sharp
  // edges that turn by at most kMaxLineTurn; lines shorter than minLineLength are dropped.
  std::vector<bool> visited(mesh.n_edges(), false);
  for (const auto first : mesh.edges()) {
    if (!sharp[first.idx()] || visited[first.idx()]) continue;
    std::vector<int> line{first.idx()};
    visited[first.idx()] = true;
    double length = mesh.calc_edge_length(first);
    for (const auto end : {first.v0(), first.v1()}) {
      auto v = end;
      auto previous = first;
      while (sharpAt[v.idx()] == 2) {
        OpenMesh::SmartEdgeHandle next;
        for (const auto e : v.edges())
          if (sharp[e.idx()] && e != previous) next = e;
        if (!next.is_valid() || visited[next.idx()]) break;
        const auto across = [&](OpenMesh::SmartEdgeHandle e) { return e.v0() == v ? e.v1() : e.v0(); };
        const Eigen::Vector3d in = toEigen(mesh.point(v) - mesh.point(across(previous)));
        const Eigen::Vector3d out = toEigen(mesh.point(across(next)) - mesh.point(v));
        if (in.dot(out) < std::cos(kMaxLineTurn) * in.norm() * out.norm()) break;
        visited[next.idx()] = true;
        line.push_back(next.idx());
        length += mesh.calc_edge_length(next);
        v = across(next);
        previous = next;
      }
    }
    if (length < minLineLength)
      for (const int e : line) sharp[e] = false;
  }
  return sharp;
}

}  // namespace hexcover
