#pragma once
// Boundary and hole handling on indexed triangle sets (internal to core/extract): boundary loops
// of the lattice triangles, nearest points on the input boundary, resampling of an input boundary
// loop, the strip between a lattice front and the input boundary, and hole filling.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "core/mesh/mesh.h"

namespace hexcover::extract_detail {

using Triangle = std::array<int, 3>;

/// The triangle's corners rotated so that the smallest comes first (its orientation kept): one
/// key per triangle.
inline Triangle canonicalTriangle(Triangle t) {
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}

/// The directed edges (u, v) of a triangle set, grouped by u, each with the third vertex of its
/// triangle, in triangle order. A lookup scans u's few edges: several times faster than a hash
/// table of edges on the extraction's hundreds of thousands of triangles.
class DirectedEdges {
 public:
  explicit DirectedEdges(const std::vector<Triangle>& triangles);

  /// u's edges are [begin(u), end(u)), in triangle order.
  int begin(int u) const { return hasVertex(u) ? first_[u] : 0; }
  int end(int u) const { return hasVertex(u) ? first_[u + 1] : 0; }
  /// Index of the first edge (u, v) in triangle order, or −1.
  int find(int u, int v) const {
    for (int e = begin(u); e < end(u); ++e)
      if (to_[e] == v) return e;
    return -1;
  }
  /// Index of edge k (0, 1, 2: from corner k to corner k + 1) of triangle t.
  int edgeOf(std::size_t t, int k) const { return slot_[3 * t + k]; }
  int to(int edge) const { return to_[edge]; }
  int apex(int edge) const { return apex_[edge]; }
  /// Number of edges: three per triangle.
  std::size_t size() const { return to_.size(); }

 private:
  bool hasVertex(int u) const { return u >= 0 && u + 1 < static_cast<int>(first_.size()); }

  std::vector<int> first_;  ///< u's edges are [first_[u], first_[u + 1]) (#vertices + 1 entries)
  std::vector<int> to_, apex_;
  std::vector<int> slot_;  ///< per triangle corner: its edge's index
};

/// Closed boundary loops of a triangle set in which every directed edge belongs to at most one
/// triangle. Each loop lists its vertices in the triangles' direction (triangles on the left);
/// at a vertex where several fans meet, each loop stays in the fan it arrived in. Deterministic:
/// loops start at the first boundary edge in triangle order. A set that reuses a directed edge
/// may give open stretches instead of loops, but the trace ends.
std::vector<std::vector<int>> traceBoundaryLoops(const std::vector<Triangle>& triangles);
/// The same with the triangles' directed edges already at hand.
std::vector<std::vector<int>> traceBoundaryLoops(const std::vector<Triangle>& triangles,
                                                 const DirectedEdges& edges);

/// The input surface's boundary loops as polylines, with a uniform grid for nearest-point queries.
class BoundaryIndex {
 public:
  /// loops[i]: the points of closed loop i in order (the segment from the last to the first
  /// point closes it). cellSize > 0: grid spacing (about the query radius). loopComponent[i]:
  /// the input component of loop i (empty: one component), for nearestInComponent.
  BoundaryIndex(std::vector<std::vector<Eigen::Vector3d>> loops, double cellSize,
                std::vector<int> loopComponent = {});

  struct Hit {
    int loop = -1;  ///< -1: nothing within the radius
    double distance = std::numeric_limits<double>::infinity();
    double arc = 0.0;  ///< arc length of the nearest point from the loop's first point
  };
  /// Nearest point of any loop (or only of `onlyLoop` when ≥ 0) within `radius` of p.
  Hit nearest(const Eigen::Vector3d& p, double radius, int onlyLoop = -1) const;
  /// Nearest point within `radius` of p of the loops of input component `component`: a lattice
  /// point's boundary is its own component's (a scan's loose triangles beside or inside a surface
  /// are not the surface's boundary).
  Hit nearestInComponent(const Eigen::Vector3d& p, double radius, int component) const;

  /// Nearest point of loop i to p, by a scan of the loop's segments.
  Hit nearestOnLoop(const Eigen::Vector3d& p, int i) const;

  /// The point of loop i strictly between arc lengths `from` < `to` (unwrapped: `to` may exceed
  /// the loop's length by up to one loop) farthest from the chord pointAt(from)–pointAt(to):
  /// its distance from the chord and its arc length in [0, loopLength(i)). The loop's own
  /// points are the candidates (the polyline is straight between them); loop = −1 when there
  /// are none.
  Hit farthestFromChord(int i, double from, double to) const;

  int loopCount() const { return static_cast<int>(loops_.size()); }
  const std::vector<Eigen::Vector3d>& loop(int i) const { return loops_[i]; }
  double loopLength(int i) const { return arcs_[i].back(); }
  /// Arc length (or a difference of arc lengths) s of loop i taken modulo its length, in
  /// [0, loopLength(i)).
  double wrappedArc(int i, double s) const {
    return s - loopLength(i) * std::floor(s / loopLength(i));
  }
  /// The point at arc length s ∈ [0, loopLength(i)] of loop i.
  Eigen::Vector3d pointAt(int i, double s) const;

 private:
  std::vector<std::vector<Eigen::Vector3d>> loops_;
  std::vector<int> loopComponent_;         ///< per loop (empty: one component)
  std::vector<std::vector<double>> arcs_;  ///< per loop: cumulative length at each point, + total
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::array<int, 2>>> grid_;  ///< {loop, segment}
  std::uint64_t cellKey(const Eigen::Vector3d& p) const;
  /// Nearest point within `radius` of p of the loops that `admit(loop)` accepts.
  template <typename Admit>
  Hit nearestAdmitted(const Eigen::Vector3d& p, double radius, const Admit& admit) const;
};

/// Arc-length positions (ascending in [0, loopLength)) of the points of input boundary loop `loop`
/// where its polyline turns by more than `sharpAngleDeg` (sharp corners), skipping a corner within
/// half a `spacing` of the previous one. `turnDegrees` (optional): per corner, by how much the
/// polyline turns there.
std::vector<double> sharpCorners(const BoundaryIndex& index, int loop, double spacing,
                                 double sharpAngleDeg, std::vector<double>* turnDegrees = nullptr);

/// Arc-length positions of the samples that replace input boundary loop `loop`: about one per
/// `spacing`, always including the points whose polyline turns by more than `sharpAngleDeg`
/// (sharp corners) unless within half a spacing of the previous corner, at least 3. Ascending in
/// [0, loopLength).
/// `corner` (optional): per returned sample, whether it is a kept sharp corner.
std::vector<double> sampleBoundaryLoop(const BoundaryIndex& index, int loop, double spacing,
                                       double sharpAngleDeg, std::vector<bool>* corner = nullptr);

/// The samples of one input loop in loop order, as output vertices: `vertex[k]` sits at arc
/// length `arc[k]` (ascending in [0, loopLength)); corners stay where they are.
struct LoopSamples {
  int loop = -1;
  double spacing = 0.0;  ///< the spacing they were sampled at
  std::vector<int> vertex;
  std::vector<double> arc;
  std::vector<bool> corner;
};

/// Slides every sample that is not a corner along its input loop, between its neighbours (kept
/// 0.3 spacings away, so samples never crowd), to the best of 16 evenly spaced positions: the
/// one whose triangles in `region` have the smallest largest angleBadness (fan_geometry.h; ties:
/// the smallest sum of the squared deviations of the angles from 60°), none
/// turned against its normal before the slide, among the positions where the input loop stays
/// within a quarter spacing of the sample's two edges (or no farther than before the slide).
/// Two passes; the output boundary stays on the input boundary. Updates `positions` and the
/// samples' arcs; returns the number of moves. N = 4: region triangles that are halves of one of
/// `squares` (Assembly::squares) are judged as that square: its worst corner's deviation from
/// 90° over kQuadCornerWindow, and the squared deviations of its corners.
int slideBoundarySamples(const BoundaryIndex& index, std::vector<LoopSamples>& samples,
                         const std::vector<Triangle>& region,
                         std::vector<Eigen::Vector3d>& positions,
                         const std::vector<std::array<int, 4>>& squares = {});

/// Triangulates the strip between an outer loop (samples on the input boundary, the surface on
/// its left) and an inner front (a boundary loop of the lattice triangles, which lie on its left),
/// both closed and running the same way, starting from the pair (outer[0], front[0]).
/// outerParam: ascending positions of the samples along the outer loop, of total length
/// `length`; frontParam: positions of the front vertices along the same loop (made
/// non-decreasing); normals: the surface normal at each front vertex (indexed like positions).
/// Each step adds the triangle on the next sample edge or on the next front edge, whichever faces
/// along the normals with the larger smallest angle, without letting either side run ahead of the
/// other (advancing by position when neither faces the right way), and not the one after which
/// the other side's next triangle, facing the right way now, would face backwards unless both
/// steps would do that (that side could then only close in a fan of slivers). Appends to `out`.
void stitchStrip(const std::vector<Eigen::Vector3d>& positions,
                 const std::vector<Eigen::Vector3d>& normals, const std::vector<int>& outer,
                 const std::vector<double>& outerParam, const std::vector<int>& front,
                 const std::vector<double>& frontParam, double length,
                 std::vector<Triangle>& out);

/// Rotates a front so that it starts at the vertex nearest (along the loop) to the first sample,
/// and turns its arc positions frontArc (in [0, loopLength)) into unwrapped positions that start
/// near outerArc[0], for stitchStrip.
void alignFrontToLoop(const std::vector<double>& outerArc, std::vector<int>& front,
                      std::vector<double>& frontArc, double loopLength);

/// Step 8 of extraction: flips the interior edges of triangles at the boundary of `mesh` whose
/// smallest angle is below `belowDegrees`, when the flip raises the pair's smallest angle, or
/// whose largest is above `aboveDegrees`, when the flip lowers it and not the smallest, and
/// both new triangles face within 60° of the pair's area-weighted normal (up to 3 passes).
/// Returns the number of flips. Faces marked by `fixed` (a face property of `mesh`; an invalid
/// handle marks none) keep their vertices (N = 4: the halves of squares).
long long flipBoundarySlivers(TriMesh& mesh, double belowDegrees, double aboveDegrees = 180.0,
                              OpenMesh::FPropHandleT<bool> fixed = OpenMesh::FPropHandleT<bool>());

/// Step 8, before the flips: a boundary vertex of `mesh` whose boundary runs straight (its
/// triangles' angles sum to 180° ± `straightWithin`, so not a corner), or curls so little that
/// the boundary without it stays within a quarter of its edges' mean length, and that has a
/// triangle with an angle below `belowDegrees` is collapsed into the boundary neighbour for which
/// the smallest angle of its remaining triangles is largest, when that is larger than before and no
/// triangle turns by more than 60° (up to 3 passes). Where the input boundary curls in a lip
/// narrower than an edge length, the strip fans from one lattice vertex to boundary samples
/// almost in line with it; fewer samples make fewer slivers. A convex corner whose boundary turns
/// by more than 2 · `straightWithin` never moves: a loose triangle's 32.7° corner went into a
/// sample 0.3 edge lengths away, cut off. A vertex of a face marked by `fixed`
/// (as in flipBoundarySlivers) stays. Returns the number of collapses; garbage-collects `mesh`
/// after any (its properties move along).
long long collapseBoundarySlivers(
    TriMesh& mesh, double belowDegrees, double straightWithin,
    OpenMesh::FPropHandleT<bool> fixed = OpenMesh::FPropHandleT<bool>());

/// What step 8 did (repairBoundarySlivers).
struct SliverRepairs {
  long long collapses = 0;
  long long flips = 0;
};

/// Step 8 of extraction: collapseBoundarySlivers, then flipBoundarySlivers, with the same
/// `fixed` faces.
SliverRepairs repairBoundarySlivers(
    TriMesh& mesh, double sliverDegrees, double obtuseDegrees, double straightWithin,
    OpenMesh::FPropHandleT<bool> fixed = OpenMesh::FPropHandleT<bool>());

/// Closes a hole bounded by `loop` (a boundary loop of the triangles, triangles on its left):
/// one triangle for 3 vertices, the shorter diagonal for 4, else a fan around a new vertex at the
/// loop's centroid (appended to `positions`). Appends the triangles to `out`; returns how many.
int fillHole(const std::vector<int>& loop, std::vector<Eigen::Vector3d>& positions,
             std::vector<Triangle>& out);

/// Lawson flips inside `region` (the triangles that stitching and hole filling added): an edge
/// between two region triangles is flipped when that raises the smaller of their two minimum
/// angles, the new edge exists nowhere yet (in `region` or `others`), and both new triangles face
/// within 60° of the pair's area-weighted normal. Repeats while a flip helps (at most 20 passes). The
/// lattice triangles (`others`) are not touched. Returns the number of flips.
int improveByFlips(const std::vector<Eigen::Vector3d>& positions,
                   const std::vector<Triangle>& others, std::vector<Triangle>& region);

}  // namespace hexcover::extract_detail
