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

/// A crease line: sharp edges through vertices where exactly two sharp edges meet and turn by at
/// most kMaxLineTurn, from corner to corner (or around a closed loop, whose ends coincide).
struct CreaseLine {
  std::vector<int> edges;
  double length = 0.0;
  std::array<int, 2> ends{};                    ///< end vertices
  std::array<Eigen::Vector3d, 2> directions{};  ///< unit direction of the line away from each end
};

std::vector<CreaseLine> creaseLines(const TriMesh& mesh, const std::vector<bool>& sharp) {
  std::vector<int> sharpAt(mesh.n_vertices(), 0);
  for (const auto e : mesh.edges())
    if (sharp[e.idx()]) ++sharpAt[e.v0().idx()], ++sharpAt[e.v1().idx()];
  const auto across = [](OpenMesh::SmartEdgeHandle e, OpenMesh::SmartVertexHandle v) {
    return e.v0() == v ? e.v1() : e.v0();
  };
  // From each unvisited sharp edge, walk both ways while the line goes on.
  std::vector<bool> visited(mesh.n_edges(), false);
  std::vector<CreaseLine> lines;
  for (const auto first : mesh.edges()) {
    if (!sharp[first.idx()] || visited[first.idx()]) continue;
    CreaseLine line;
    line.edges.push_back(first.idx());
    visited[first.idx()] = true;
    line.length = mesh.calc_edge_length(first);
    int side = 0;
    for (const auto end : {first.v0(), first.v1()}) {
      auto v = end;
      auto previous = first;
      while (sharpAt[v.idx()] == 2) {
        OpenMesh::SmartEdgeHandle next;
        for (const auto e : v.edges())
          if (sharp[e.idx()] && e != previous) next = e;
        if (!next.is_valid() || visited[next.idx()]) break;
        const Eigen::Vector3d in = toEigen(mesh.point(v) - mesh.point(across(previous, v)));
        const Eigen::Vector3d out = toEigen(mesh.point(across(next, v)) - mesh.point(v));
        if (in.dot(out) < std::cos(kMaxLineTurn) * in.norm() * out.norm()) break;
        visited[next.idx()] = true;
        line.edges.push_back(next.idx());
        line.length += mesh.calc_edge_length(next);
        v = across(next, v);
        previous = next;
      }
      line.ends[side] = v.idx();
      const Eigen::Vector3d away = toEigen(mesh.point(across(previous, v)) - mesh.point(v));
      line.directions[side++] =
          away.norm() > 0.0 ? Eigen::Vector3d(away.normalized()) : Eigen::Vector3d::Zero();
    }
    lines.push_back(std::move(line));
  }
  return lines;
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

std::vector<bool> sharpEdges(const TriMesh& mesh, double minDihedralDegrees, double minLineLength) {
  std::vector<bool> sharp(mesh.n_edges(), false);
  if (!(minDihedralDegrees > 0.0)) return sharp;
  const std::vector<double> dihedral = dihedralAngles(mesh);
  for (const auto e : mesh.edges()) sharp[e.idx()] = dihedral[e.idx()] >= minDihedralDegrees;
  for (const CreaseLine& line : creaseLines(mesh, sharp))
    if (line.length < minLineLength)
      for (const int e : line.edges) sharp[e] = false;
  return sharp;
}

std::vector<bool> latticeCompatibleCreases(const TriMesh& mesh, const std::vector<bool>& sharp,
                                           int n) {
  std::vector<CreaseLine> lines = creaseLines(mesh, sharp);
  std::stable_sort(lines.begin(), lines.end(),
                   [](const CreaseLine& a, const CreaseLine& b) { return a.length > b.length; });
  const double period = 360.0 / n;
  const auto compatible = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double angle = std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
    return std::abs(angle - period * std::round(angle / period)) <= kCompatibleCornerTolerance;
  };
  // The directions (away from the corner) of the kept lines that end at each vertex.
  std::vector<std::vector<Eigen::Vector3d>> keptEnds(mesh.n_vertices());
  std::vector<bool> kept(mesh.n_edges(), false);
  for (const CreaseLine& line : lines) {
    bool fits = line.ends[0] != line.ends[1] || compatible(line.directions[0], line.directions[1]);
    for (int end = 0; end < 2 && fits; ++end)
      for (const Eigen::Vector3d& other : keptEnds[line.ends[end]])
        fits = fits && compatible(line.directions[end], other);
    if (!fits) continue;
    for (int end = 0; end < 2; ++end) keptEnds[line.ends[end]].push_back(line.directions[end]);
    for (const int e : line.edges) kept[e] = true;
  }
  return kept;
}

}  // namespace hexcover
