#include "core/mesh/refine.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include "core/common/error.h"

namespace hexcover {

long long splitLongEdges(TriMesh& mesh, double maxLength, std::size_t maxFaces) {
  if (!(std::isfinite(maxLength) && maxLength > 0.0))
    throw Error(
        ErrorCode::InvalidOption,
        "the longest edge to keep must be finite and positive, got " + std::to_string(maxLength));
  // (length, edge): the longest first, then the lower index.
  using Entry = std::pair<double, int>;
  const auto longerFirst = [](const Entry& a, const Entry& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(longerFirst)> queue(longerFirst);
  const auto push = [&](OpenMesh::EdgeHandle e) {
    const double length = mesh.calc_edge_length(e);
    if (length > maxLength) queue.emplace(length, e.idx());
  };
  for (const auto e : mesh.edges()) push(e);
  long long splits = 0;
  while (!queue.empty() && mesh.n_faces() + 2 <= maxFaces) {
    const auto [length, index] = queue.top();
    queue.pop();
    const OpenMesh::EdgeHandle e(index);
    // A split shortens the edge it reuses: entries of an older length are stale.
    if (mesh.calc_edge_length(e) != length) continue;
    const auto h = mesh.halfedge_handle(e, 0);
    const TriMesh::Point midpoint =
        0.5 * (mesh.point(mesh.from_vertex_handle(h)) + mesh.point(mesh.to_vertex_handle(h)));
    const auto v = mesh.split_copy(e, midpoint);
    for (const auto out : mesh.voh_range(v)) push(mesh.edge_handle(out));
    ++splits;
  }
  return splits;
}

namespace {

using Vec3 = Eigen::Vector3d;

Vec3 position(const TriMesh& mesh, OpenMesh::VertexHandle v) { return toEigen(mesh.point(v)); }

/// Angle at corner b of triangle (a, b, c).
double angleAt(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = a - b, w = c - b;
  return std::atan2(u.cross(w).norm(), u.dot(w));
}

}  // namespace

long long flipFlatRegionsToDelaunay(TriMesh& mesh, int maxPasses) {
  long long flips = 0;
  for (int pass = 0; pass < maxPasses; ++pass) {
    long long passFlips = 0;
    for (const auto e : mesh.edges()) {
      if (mesh.is_boundary(e) || !mesh.is_flip_ok(e)) continue;
      // The edge (a, b) between triangles (a, b, c) and (b, a, d).
      const auto h = mesh.halfedge_handle(e, 0), g = mesh.halfedge_handle(e, 1);
      const Vec3 a = position(mesh, mesh.from_vertex_handle(h)),
                 b = position(mesh, mesh.to_vertex_handle(h)),
                 c = position(mesh, mesh.to_vertex_handle(mesh.next_halfedge_handle(h))),
                 d = position(mesh, mesh.to_vertex_handle(mesh.next_halfedge_handle(g)));
      const Vec3 n0 = (b - a).cross(c - a), n1 = (a - b).cross(d - b);
      if (!(n0.norm() > 0.0 && n1.norm() > 0.0) ||
          !(n0.normalized().dot(n1.normalized()) > kCoplanarCosine))
        continue;
      if (!(angleAt(a, c, b) + angleAt(b, d, a) > M_PI + 1e-12)) continue;
      // The new triangles (a, d, c) and (d, b, c) must keep the orientation (a convex quad).
      if (!((d - a).cross(c - a).dot(n0) > 0.0 && (b - d).cross(c - d).dot(n0) > 0.0)) continue;
      mesh.flip(e);
      ++passFlips;
    }
    flips += passFlips;
    if (passFlips == 0) break;
  }
  return flips;
}

long long relaxFlatRegions(TriMesh& mesh, int rounds) {
  long long moves = 0;
  std::vector<std::pair<Vec3, Vec3>> rim;  // the far edges (a, b) of v's triangles (v, a, b)
  for (int round = 0; round < rounds; ++round) {
    for (const auto v : mesh.vertices()) {
      if (mesh.is_boundary(v) || mesh.is_isolated(v)) continue;
      const Vec3 p = position(mesh, v);
      // Flat: every triangle non-degenerate and coplanar with the first one (normal n).
      Vec3 n = Vec3::Zero(), centroid = Vec3::Zero();
      bool flat = true;
      rim.clear();
      for (const auto h : mesh.voh_range(v)) {
        const Vec3 a = position(mesh, mesh.to_vertex_handle(h)),
                   b = position(mesh, mesh.to_vertex_handle(mesh.next_halfedge_handle(h)));
        const Vec3 normal = (a - p).cross(b - p);
        if (n.isZero() && normal.norm() > 0.0) n = normal.normalized();
        flat = normal.norm() > 0.0 && n.dot(normal.normalized()) > kCoplanarCosine;
        if (!flat) break;
        rim.emplace_back(a, b);
        centroid += a;
      }
      if (!flat) continue;
      centroid /= static_cast<double>(rim.size());
      centroid -= (centroid - p).dot(n) * n;  // in the plane
      if (std::all_of(rim.begin(), rim.end(), [&](const auto& edge) {
            return (edge.first - centroid).cross(edge.second - centroid).dot(n) > 0.0;
          })) {
        mesh.set_point(v, toOpenMesh(centroid));
        ++moves;
      }
    }
    flipFlatRegionsToDelaunay(mesh);
  }
  return moves;
}

long long refineLongEdges(TriMesh& mesh, double maxLength, std::size_t maxFaces) {
  const long long splits = splitLongEdges(mesh, maxLength, maxFaces);
  if (splits > 0) {
    flipFlatRegionsToDelaunay(mesh);
    relaxFlatRegions(mesh, kFlatRelaxationRounds);
  }
  return splits;
}

}  // namespace hexcover
