#include "core/extract/boundary_zone.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/extract/fan_geometry.h"

namespace hexcover::extract_detail {
namespace {

using Vec3 = Eigen::Vector3d;

/// A flip never creates an edge longer than this many target lengths.
constexpr double kLongEdge = 4.0 / 3.0;
/// Edges shorter than this many target lengths are collapsed when that helps.
constexpr double kShortEdge = 0.5;
/// A boundary vertex with a single triangle that has an angle below this (degrees) is the tip of
/// a poor ear: removed even when it is a corner.
constexpr double kEarAngle = 20.0;
/// A boundary vertex where the boundary turns by more than this (degrees) is a corner: kept.
constexpr double kCornerTurn = 30.0;
/// A flip that improves the valences may lower the pair's smallest angle only down to this
/// (degrees).
constexpr double kFlipMinAngle = 25.0;

class BoundaryZone {
 public:
  BoundaryZone(const ClosestPointQuery& input, TriMesh& mesh, double targetLength)
      : input_(input), mesh_(mesh), length_(targetLength) {}

  long long flipTowardsRegularValence() {
    markZone();
    long long flips = 0;
    for (const auto e : mesh_.edges()) {
      if (!inZone(e) || !mesh_.is_flip_ok(e)) continue;
      const auto h = e.h0();
      const auto a = h.from(), b = h.to(), c = h.next().to(), d = h.opp().next().to();
      const auto deviation = [&](OpenMesh::SmartVertexHandle v, int change) {
        const int off = static_cast<int>(v.valence()) + change - (mesh_.is_boundary(v) ? 4 : 6);
        return off * off;
      };
      const int before = deviation(a, 0) + deviation(b, 0) + deviation(c, 0) + deviation(d, 0);
      const int after = deviation(a, -1) + deviation(b, -1) + deviation(c, 1) + deviation(d, 1);
      const std::array<Vec3, 3> old1{position(a), position(b), position(c)};
      const std::array<Vec3, 3> old2{position(b), position(a), position(d)};
      const std::array<Vec3, 3> new1{position(a), position(d), position(c)};
      const std::array<Vec3, 3> new2{position(d), position(b), position(c)};
      const Vec3 normal = (triangleNormal(old1) + triangleNormal(old2)).normalized();
      if (!(triangleNormal(new1).dot(normal) > kMinNormalCosine &&
            triangleNormal(new2).dot(normal) > kMinNormalCosine))
        continue;
      const double oldMin = std::min(angleRange(old1)[0], angleRange(old2)[0]);
      const double newMin = std::min(angleRange(new1)[0], angleRange(new2)[0]);
      const bool better = (after < before && newMin >= std::min(oldMin, kFlipMinAngle)) ||
                          (after == before && newMin > oldMin);
      if (!better || (position(c) - position(d)).norm() > kLongEdge * length_) continue;
      mesh_.flip(e);
      ++flips;
    }
    return flips;
  }

  /// Collapses edges shorter than kShortEdge target lengths into one end (see
  /// mayRemoveAlong), when that lowers the largest deviation from 60° of the triangles around the
  /// removed end without turning one by more than 60° or making an edge longer than kLongEdge.
  long long collapseShortEdges() {
    markZone();
    long long collapses = 0;
    for (const auto e : mesh_.edges()) {
      const bool isShort = mesh_.calc_edge_length(e) < kShortEdge * length_;
      for (const auto h : {e.h0(), e.h1()})
        if (((isShort && mayRemoveAlong(h)) || isPoorEarAlong(h)) && collapseHelps(h)) {
          mesh_.collapse(h);
          ++collapses;
          break;
        }
    }
    return collapses;
  }

  /// Moves interior zone vertices (next to the boundary) towards their neighbours' centroid,
  /// projected onto the input, when that lowers the largest deviation of their triangles' angles
  /// from 60°.
  long long smooth() {
    markZone();
    long long moves = 0;
    for (const auto v : mesh_.vertices()) {
      if (ring_[v.idx()] != 1) continue;
      Vec3 centroid = Vec3::Zero();
      double count = 0.0;
      for (const auto w : v.vertices()) centroid += position(w), count += 1.0;
      const Vec3 candidate = input_.closest(centroid / count).point;
      if (fanAngleBadness(mesh_, v, candidate) < fanAngleBadness(mesh_, v, position(v))) {
        mesh_.set_point(v, toOpenMesh(candidate));
        ++moves;
      }
    }
    return moves;
  }

 private:
  const ClosestPointQuery& input_;
  TriMesh& mesh_;
  const double length_;
  /// Per vertex: 0 on the boundary, 1 next to it, 2 farther inside.
  std::vector<int> ring_;

  Vec3 position(OpenMesh::VertexHandle v) const { return toEigen(mesh_.point(v)); }

  void markZone() {
    ring_.assign(mesh_.n_vertices(), 2);
    for (const auto v : mesh_.vertices())
      if (mesh_.is_boundary(v)) ring_[v.idx()] = 0;
    for (const auto v : mesh_.vertices())
      if (ring_[v.idx()] == 0)
        for (const auto w : v.vertices()) ring_[w.idx()] = std::min(ring_[w.idx()], 1);
  }

  /// h's start may be removed by collapsing h: an interior vertex next to the boundary, or a
  /// boundary vertex that is not a corner, along a boundary edge.
  bool mayRemoveAlong(OpenMesh::SmartHalfedgeHandle h) const {
    const auto from = h.from();
    if (ring_[from.idx()] == 1) return true;
    if (ring_[from.idx()] != 0 || !mesh_.is_boundary(h.edge())) return false;
    // The boundary's turn at `from`: between the boundary edges into and out of it.
    const auto out = from.halfedge();  // the outgoing boundary halfedge of a boundary vertex
    const Vec3 before = position(from) - position(out.prev().from());
    const Vec3 after = position(out.to()) - position(from);
    return before.normalized().dot(after.normalized()) > std::cos(kCornerTurn * M_PI / 180.0);
  }

  /// h's start is the tip of an ear (a boundary vertex with a single triangle) whose triangle has
  /// an angle below kEarAngle, and h the shorter of its two boundary edges: collapsing h removes
  /// the ear, even at a corner of the boundary.
  bool isPoorEarAlong(OpenMesh::SmartHalfedgeHandle h) const {
    const auto from = h.from();
    if (!mesh_.is_boundary(from) || from.valence() != 2 || !mesh_.is_boundary(h.edge()))
      return false;
    const auto out = from.halfedge(), in = out.prev();
    const Vec3 p = position(from), a = position(out.to()), b = position(in.from());
    const double other = (h.edge() == out.edge() ? b - p : a - p).norm();
    return angleRange({p, a, b})[0] < kEarAngle && mesh_.calc_edge_length(h) <= other;
  }

  bool collapseHelps(OpenMesh::SmartHalfedgeHandle h) const {
    if (!mesh_.is_collapse_ok(h)) return false;
    const auto from = h.from(), to = h.to();
    const Vec3 target = position(to);
    for (const auto w : from.vertices())
      if ((position(w) - target).norm() > kLongEdge * length_) return false;
    double before = 0.0, after = 0.0;
    for (const auto f : from.faces()) {
      const auto old = facePositions(mesh_, f, OpenMesh::VertexHandle(), target);
      const auto oldRange = angleRange(old);
      before = std::max(before, angleBadness(oldRange));
      bool removed = false;
      for (const auto w : f.vertices()) removed = removed || w == to;
      if (removed) continue;
      const auto moved = facePositions(mesh_, f, from, target);
      if (!(triangleNormal(old).dot(triangleNormal(moved)) > kMinNormalCosine)) return false;
      const auto range = angleRange(moved);
      after = std::max(after, angleBadness(range));
    }
    return after < before;
  }

  /// An interior edge with an end on or next to the boundary.
  bool inZone(OpenMesh::SmartEdgeHandle e) const {
    return !mesh_.is_boundary(e) && std::min(ring_[e.v0().idx()], ring_[e.v1().idx()]) <= 1;
  }
};

}  // namespace

BoundaryZoneCounts improveBoundaryZone(const ClosestPointQuery& input, TriMesh& remesh,
                                       double targetLength, int iterations) {
  BoundaryZoneCounts counts;
  const bool hasBoundary = std::any_of(remesh.vertices().begin(), remesh.vertices().end(),
                                       [&](auto v) { return remesh.is_boundary(v); });
  if (!hasBoundary || !(targetLength > 0.0)) return counts;
  remesh.request_vertex_status();
  remesh.request_edge_status();
  remesh.request_halfedge_status();
  remesh.request_face_status();
  BoundaryZone zone(input, remesh, targetLength);
  for (int i = 0; i < iterations; ++i) {
    const long long collapses = zone.collapseShortEdges();
    const long long flips = zone.flipTowardsRegularValence();
    const long long moves = zone.smooth();
    counts.collapses += collapses;
    counts.flips += flips;
    counts.smoothed += moves;
    if (collapses + flips + moves == 0) break;
  }
  remesh.garbage_collection();
  remesh.release_vertex_status();
  remesh.release_edge_status();
  remesh.release_halfedge_status();
  remesh.release_face_status();
  return counts;
}

}  // namespace hexcover::extract_detail
