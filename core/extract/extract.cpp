#include "core/extract/extract.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

#include "core/common/error.h"
#include "core/extract/boundary.h"
#include "core/extract/exact_lattice.h"
#include "core/extract/surface_fit.h"

namespace hexcover {

using namespace extract_detail;

void ExtractOptions::validate() const {
  if (!(boundarySnapDistance > 0.0 && boundarySnapDistance < 1.0))
    throw Error(ErrorCode::InvalidOption, "boundarySnapDistance must be in (0, 1), got " +
                                              std::to_string(boundarySnapDistance));
  if (!(sharpBoundaryAngle >= 0.0 && sharpBoundaryAngle <= 180.0))
    throw Error(ErrorCode::InvalidOption, "sharpBoundaryAngle must be in [0, 180] degrees, got " +
                                              std::to_string(sharpBoundaryAngle));
  if (!(featureSnapDistance >= 0.0 && featureSnapDistance < 1.0))
    throw Error(ErrorCode::InvalidOption, "featureSnapDistance must be in [0, 1), got " +
                                              std::to_string(featureSnapDistance));
  if (!(sliverAngle >= 0.0 && sliverAngle < 60.0))
    throw Error(ErrorCode::InvalidOption,
                "sliverAngle must be in [0, 60) degrees, got " + std::to_string(sliverAngle));
  if (!(creaseAngle >= 0.0 && creaseAngle <= 180.0))
    throw Error(ErrorCode::InvalidOption,
                "creaseAngle must be in [0, 180] degrees, got " + std::to_string(creaseAngle));
  if (threads < 1)
    throw Error(ErrorCode::InvalidOption,
                "threads must be at least 1, got " + std::to_string(threads));
}

namespace {

using HH = TriMesh::HalfedgeHandle;
using FH = TriMesh::FaceHandle;
using VH = TriMesh::VertexHandle;

/// Sanitized parameterization: fixed-point corner coordinates on which the recomputed integer
/// transitions hold exactly (algorithm notes, "Extraction": sanitize first).
struct ExactChart {
  std::vector<FixedPoint> corner;    ///< #halfedges: to_vertex(h) in face(h)
  std::vector<Transition> crossing;  ///< #E: chart of face(halfedge(e,0)) -> chart of the other
  std::vector<int> orientation;      ///< #F: +1 counter-clockwise, 0 degenerate, -1 flipped

  /// The transition from face(h)'s chart into the chart of the face across h.
  Transition across(const TriMesh& mesh, HH h) const {
    const auto e = mesh.edge_handle(h);
    return mesh.halfedge_handle(e, 0) == h ? crossing[e.idx()] : crossing[e.idx()].inverse();
  }
};

/// Lattice coordinates (in face(h)) of from_vertex(h): the corner of the previous halfedge.
Eigen::Vector2d fromCoords(const TriMesh& mesh, const Parameterization& param, HH h) {
  return param.cornerCoords[mesh.prev_halfedge_handle(h).idx()];
}

/// Squared length of a lattice-coordinate vector in the plane (Gram matrix [[1, ½], [½, 1]]).
double planeNorm2(const Eigen::Vector2d& d) { return d.x() * d.x() + d.x() * d.y() + d.y() * d.y(); }

/// Step 1a: each interior edge's transition from the corner coordinates on both sides.
std::vector<Transition> recomputeTransitions(const TriMesh& mesh, const Parameterization& param,
                                             ExtractionReport& report) {
  std::vector<Transition> crossing(mesh.n_edges());
  for (const auto e : mesh.edges()) {
    if (mesh.is_boundary(e)) continue;
    const HH h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    // h0 runs A -> B in f0, h1 runs B -> A in f1.
    const Eigen::Vector2d a0 = fromCoords(mesh, param, h0), b0 = param.cornerCoords[h0.idx()];
    const Eigen::Vector2d b1 = fromCoords(mesh, param, h1), a1 = param.cornerCoords[h1.idx()];
    const EdgeTransition& given = param.edgeTransition[e.idx()];
    int best = given.rotation;
    const Eigen::Vector2d d0 = b0 - a0, d1 = b1 - a1;
    if (planeNorm2(d0) > 1e-18) {
      double bestResidual = planeNorm2(rotate(d0, best) - d1);
      for (int r = 0; r < 6; ++r) {
        const double residual = planeNorm2(rotate(d0, r) - d1);
        if (residual < bestResidual - 1e-12) best = r, bestResidual = residual;
      }
    }
    const Eigen::Vector2d t = 0.5 * ((a1 - rotate(a0, best)) + (b1 - rotate(b0, best)));
    Transition transition{best, {std::llround(t.x()), std::llround(t.y())}};
    if (transition.rotation != given.rotation ||
        transition.translation != given.translation.cast<std::int64_t>())
      ++report.transitionsCorrected;
    crossing[e.idx()] = transition;
  }
  return crossing;
}

/// The incoming halfedges of v in faces, in counter-clockwise order; for a boundary vertex from
/// the face after the boundary gap. Returns whether the fan closes (interior vertex).
bool incomingFan(const TriMesh& mesh, VH v, std::vector<HH>& fan) {
  fan.clear();
  HH start;
  for (const auto h : mesh.vih_range(v))
    if (!mesh.is_boundary(h) && mesh.is_boundary(mesh.opposite_halfedge_handle(h))) start = h;
  const bool closed = !start.is_valid();
  if (closed) {
    for (const auto h : mesh.vih_range(v)) {
      start = h;
      break;
    }
  }
  if (!start.is_valid()) return false;
  // Counter-clockwise about v: from h (into v in f), cross the edge of next(h) into g.
  HH h = start;
  do {
    fan.push_back(h);
    h = mesh.opposite_halfedge_handle(mesh.next_halfedge_handle(h));
  } while (h != start && !mesh.is_boundary(h));
  return closed;
}

/// Step 1b: fixed-point corner coordinates, propagated around each vertex through the exact
/// transitions; a vertex whose holonomy rotates sits exactly on the holonomy's fixed point.
ExactChart sanitize(const TriMesh& mesh, const Parameterization& param, ExtractionReport& report,
                    const RunContext& context) {
  ExactChart chart;
  chart.crossing = recomputeTransitions(mesh, param, report);
  chart.corner.assign(mesh.n_halfedges(), FixedPoint{});
  std::vector<HH> fan;
  for (const auto v : mesh.vertices()) {
    if ((v.idx() & 4095) == 0) context.throwIfCanceled();
    const bool closed = incomingFan(mesh, v, fan);
    if (fan.empty()) continue;
    FixedPoint z = quantize(param.cornerCoords[fan[0].idx()]);
    if (closed) {
      // Holonomy: the composed transitions once around v, from fan[0]'s chart to itself.
      Transition holonomy;
      for (const HH h : fan)
        holonomy = chart.across(mesh, mesh.next_halfedge_handle(h)).after(holonomy);
      if (holonomy.rotation != 0)
        z = fixedPoint(holonomy);
      else if (holonomy.translation != Eigen::Matrix<std::int64_t, 2, 1>::Zero())
        ++report.inconsistentVertices;
    }
    for (const HH h : fan) {
      chart.corner[h.idx()] = z;
      z = chart.across(mesh, mesh.next_halfedge_handle(h))(z);
    }
  }
  chart.orientation.assign(mesh.n_faces(), 0);
  for (const auto f : mesh.faces()) {
    const HH h0 = mesh.halfedge_handle(f), h1 = mesh.next_halfedge_handle(h0),
             h2 = mesh.next_halfedge_handle(h1);
    const __int128 o = orient(chart.corner[h0.idx()], chart.corner[h1.idx()], chart.corner[h2.idx()]);
    chart.orientation[f.idx()] = o > 0 ? 1 : (o < 0 ? -1 : 0);
    if (o < 0) ++report.flippedParamTriangles;
    if (o == 0) ++report.degenerateParamTriangles;
  }
  return chart;
}

/// (face, a, b): lattice point (a, b) in the chart of a face.
struct FacePoint {
  int face;
  std::int64_t a, b;
  friend bool operator==(const FacePoint&, const FacePoint&) = default;
};
struct FacePointHash {
  std::size_t operator()(const FacePoint& p) const {
    std::uint64_t h = static_cast<std::uint64_t>(p.face) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(p.a) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(p.b) + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

FacePoint facePoint(int face, const FixedPoint& p) { return {face, p.a / kUnit, p.b / kUnit}; }

/// The output under construction: vertices (with the input component they belong to) and
/// triangles as indices.
struct Assembly {
  std::vector<Eigen::Vector3d> positions;
  std::vector<int> component;
  std::vector<Triangle> triangles;
  /// Vertices that make up the output's boundary loops (samples on the input boundary, or the
  /// lattice fronts in BoundaryMode::Lattice); holes through other vertices are gaps to fill.
  std::vector<bool> onBoundary;

  int addVertex(const Eigen::Vector3d& p, int inputComponent) {
    positions.push_back(p);
    component.push_back(inputComponent);
    onBoundary.push_back(false);
    return static_cast<int>(positions.size()) - 1;
  }
};

class LatticeExtractor {
 public:
  LatticeExtractor(const TriMesh& mesh, const ExactChart& chart, const std::vector<int>& component,
                   ExtractionReport& report, const RunContext& context)
      : mesh_(mesh), chart_(chart), component_(component), report_(report), context_(context) {}

  /// Step 2: every lattice point of every counter-clockwise parameter triangle, once.
  void emitPoints(Assembly& out) {
    std::vector<int> vertexPoint(mesh_.n_vertices(), -1);
    points_.reserve(mesh_.n_faces());
    for (const auto f : mesh_.faces()) {
      if ((f.idx() & 4095) == 0) context_.throwIfCanceled();
      if (chart_.orientation[f.idx()] <= 0) continue;
      const auto [h, q] = corners(f);
      const __int128 area = orient(q[0], q[1], q[2]);
      const auto [lo, hi] = bounds(q);
      for (std::int64_t a = ceilUnits(lo.a); a <= floorUnits(hi.a); ++a) {
        for (std::int64_t b = ceilUnits(lo.b); b <= floorUnits(hi.b); ++b) {
          const FixedPoint z = latticePoint(a, b);
          // s[k]: orientation of z against the edge of halfedge h[k] (corner k-1 -> corner k),
          // proportional to the barycentric weight of corner k+1.
          std::array<__int128, 3> s;
          int zeros = 0;
          bool inside = true;
          for (int k = 0; k < 3; ++k) {
            s[k] = orient(q[(k + 2) % 3], q[k], z);
            inside = inside && s[k] >= 0;
            zeros += s[k] == 0;
          }
          if (!inside) continue;
          const FacePoint key = facePoint(f.idx(), z);
          int id = -1;
          if (zeros == 2) {  // a corner: the mesh vertex itself
            int k = 0;
            while (!(q[k] == z)) ++k;
            const VH v = mesh_.to_vertex_handle(h[k]);
            if (vertexPoint[v.idx()] < 0)
              vertexPoint[v.idx()] = addVertex(out, toEigen(mesh_.point(v)), f.idx());
            id = vertexPoint[v.idx()];
          } else if (zeros == 1) {  // on an edge: shared with the face across it
            int k = 0;
            while (s[k] != 0) ++k;
            const HH opposite = mesh_.opposite_halfedge_handle(h[k]);
            const FH g = mesh_.face_handle(opposite);
            if (g.is_valid() && chart_.orientation[g.idx()] > 0) {
              const FacePoint across = facePoint(g.idx(), chart_.across(mesh_, h[k])(z));
              const auto found = points_.find(across);
              id = found != points_.end() ? found->second
                                          : addVertex(out, interpolate(h, s, area), f.idx());
              points_.emplace(across, id);
            }
          }
          if (id < 0) id = addVertex(out, interpolate(h, s, area), f.idx());
          points_.emplace(key, id);
        }
      }
    }
    report_.latticePoints = static_cast<long long>(out.positions.size());
  }

  /// Step 3: every unit lattice triangle whose centroid a counter-clockwise parameter triangle
  /// owns, with its corners found by walking from the centroid.
  void emitTriangles(Assembly& out) {
    for (const auto f : mesh_.faces()) {
      if ((f.idx() & 4095) == 0) context_.throwIfCanceled();
      if (chart_.orientation[f.idx()] <= 0) continue;
      const auto [h, q] = corners(f);
      const auto [lo, hi] = bounds(q);
      for (std::int64_t a = floorUnits(lo.a) - 1; a <= ceilUnits(hi.a); ++a) {
        for (std::int64_t b = floorUnits(lo.b) - 1; b <= ceilUnits(hi.b); ++b) {
          for (const int third : {1, 2}) {
            // Centroid (a + third/3, b + third/3) in fixed point (kUnit = 3 · 2^24).
            const FixedPoint c{a * kUnit + third * (kUnit / 3), b * kUnit + third * (kUnit / 3)};
            if (!ownsCentroid(f, h, q, c)) continue;
            const std::array<FixedPoint, 3> corner =
                third == 1 ? std::array<FixedPoint, 3>{latticePoint(a, b), latticePoint(a + 1, b),
                                                       latticePoint(a, b + 1)}
                           : std::array<FixedPoint, 3>{latticePoint(a + 1, b),
                                                       latticePoint(a + 1, b + 1),
                                                       latticePoint(a, b + 1)};
            Triangle t;
            Walk end = Walk::Found;
            for (int k = 0; k < 3 && end == Walk::Found; ++k) end = walk(f, c, corner[k], t[k]);
            if (end == Walk::Found) {
              out.triangles.push_back(t);
              ++report_.latticeTriangles;
            } else if (end == Walk::LeftSurface) {
              ++report_.boundaryClipped;
            } else {
              ++report_.uncoveredTriangles;
            }
          }
        }
      }
    }
  }

 private:
  enum class Walk { Found, LeftSurface, Blocked };

  int addVertex(Assembly& out, const Eigen::Vector3d& p, int face) {
    return out.addVertex(p, component_[face]);
  }

  std::pair<std::array<HH, 3>, std::array<FixedPoint, 3>> corners(FH f) const {
    const HH h0 = mesh_.halfedge_handle(f), h1 = mesh_.next_halfedge_handle(h0),
             h2 = mesh_.next_halfedge_handle(h1);
    return {{h0, h1, h2}, {chart_.corner[h0.idx()], chart_.corner[h1.idx()], chart_.corner[h2.idx()]}};
  }

  static std::pair<FixedPoint, FixedPoint> bounds(const std::array<FixedPoint, 3>& q) {
    return {{std::min({q[0].a, q[1].a, q[2].a}), std::min({q[0].b, q[1].b, q[2].b})},
            {std::max({q[0].a, q[1].a, q[2].a}), std::max({q[0].b, q[1].b, q[2].b})}};
  }

  /// Barycentric interpolation of the corner positions; s[k] weighs corner k+1.
  Eigen::Vector3d interpolate(const std::array<HH, 3>& h, const std::array<__int128, 3>& s,
                              __int128 area) const {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      p += (static_cast<double>(s[k]) / static_cast<double>(area)) *
           toEigen(mesh_.point(mesh_.to_vertex_handle(h[(k + 1) % 3])));
    return p;
  }

  /// Whether f is the one face that emits the unit triangle with centroid c: c is in f's closed
  /// triangle, and when it is on an edge or a vertex, f has the lowest index among the
  /// counter-clockwise faces that contain it.
  bool ownsCentroid(FH f, const std::array<HH, 3>& h, const std::array<FixedPoint, 3>& q,
                    const FixedPoint& c) const {
    int zeros = 0, onEdge = -1;
    for (int k = 0; k < 3; ++k) {
      const __int128 s = orient(q[(k + 2) % 3], q[k], c);
      if (s < 0) return false;
      if (s == 0) ++zeros, onEdge = k;
    }
    if (zeros == 0) return true;
    if (zeros == 1) {
      const FH g = mesh_.face_handle(mesh_.opposite_halfedge_handle(h[onEdge]));
      return !g.is_valid() || chart_.orientation[g.idx()] <= 0 || f.idx() < g.idx();
    }
    int k = 0;
    while (!(q[k] == c)) ++k;
    for (const auto g : mesh_.vf_range(mesh_.to_vertex_handle(h[k])))
      if (chart_.orientation[g.idx()] > 0 && g.idx() < f.idx()) return false;
    return true;
  }

  /// Walks the segment from `from` (in f's closed triangle) to `target` across parameter
  /// triangles, applying the transitions, until a triangle contains `target`; `vertex` is then
  /// the lattice point emitted for it.
  Walk walk(FH f, FixedPoint from, FixedPoint target, int& vertex) const {
    constexpr int kMaxSteps = 256;
    for (int step = 0; step < kMaxSteps; ++step) {
      const auto [h, q] = corners(f);
      std::array<__int128, 3> s;
      for (int k = 0; k < 3; ++k) s[k] = orient(q[(k + 2) % 3], q[k], target);
      if (s[0] >= 0 && s[1] >= 0 && s[2] >= 0) {
        const auto found = points_.find(facePoint(f.idx(), target));
        if (found == points_.end()) return Walk::Blocked;
        vertex = found->second;
        return Walk::Found;
      }
      // Leave through the edge the segment crosses: target beyond it, its start corner on the
      // right of the segment and its end corner on the left.
      int exit = -1;
      for (int k = 0; k < 3 && exit < 0; ++k)
        if (s[k] < 0 && orient(from, target, q[(k + 2) % 3]) <= 0 && orient(from, target, q[k]) >= 0)
          exit = k;
      if (exit < 0) return Walk::Blocked;
      const HH opposite = mesh_.opposite_halfedge_handle(h[exit]);
      if (mesh_.is_boundary(opposite)) return Walk::LeftSurface;
      const FH g = mesh_.face_handle(opposite);
      if (chart_.orientation[g.idx()] <= 0) return Walk::Blocked;
      const Transition t = chart_.across(mesh_, h[exit]);
      from = t(from);
      target = t(target);
      f = g;
    }
    return Walk::Blocked;
  }

  const TriMesh& mesh_;
  const ExactChart& chart_;
  const std::vector<int>& component_;
  ExtractionReport& report_;
  const RunContext& context_;
  std::unordered_map<FacePoint, int, FacePointHash> points_;
};

/// Connected components of faces (through edges), numbered in order of their lowest face.
std::vector<int> faceComponents(const TriMesh& mesh, int& count) {
  std::vector<int> component(mesh.n_faces(), -1);
  count = 0;
  std::vector<FH> stack;
  for (const auto seed : mesh.faces()) {
    if (component[seed.idx()] >= 0) continue;
    component[seed.idx()] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const FH f = stack.back();
      stack.pop_back();
      for (const auto g : mesh.ff_range(f))
        if (component[g.idx()] < 0) component[g.idx()] = count, stack.push_back(g);
    }
    ++count;
  }
  return component;
}

/// Step 4a: drops triangles with a repeated corner and triangles that reuse a directed edge
/// (a lattice triangle covered twice, or overlapping ones at a fold), keeping the first.
void dropDegenerateAndOverlapping(std::vector<Triangle>& triangles, ExtractionReport& report) {
  const DirectedEdges edges(triangles);
  std::vector<char> used(edges.size(), 0);  // per directed edge: in a kept triangle
  const auto isUsed = [&](int u, int v) {
    for (int e = edges.begin(u); e < edges.end(u); ++e)
      if (edges.to(e) == v && used[e]) return true;
    return false;
  };
  std::vector<Triangle> kept;
  kept.reserve(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const Triangle& t = triangles[i];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++report.degenerateTriangles;
      continue;
    }
    bool overlaps = false;
    for (int k = 0; k < 3; ++k) overlaps = overlaps || isUsed(t[k], t[(k + 1) % 3]);
    if (overlaps) {
      ++report.overlappingTriangles;
      continue;
    }
    for (int k = 0; k < 3; ++k) used[edges.edgeOf(i, k)] = 1;
    kept.push_back(t);
  }
  triangles = std::move(kept);
}

/// Mean length of the triangle edges at each vertex (0 where none): the local edge length.
std::vector<double> localEdgeLength(const Assembly& out) {
  std::vector<double> sum(out.positions.size(), 0.0);
  std::vector<int> count(out.positions.size(), 0);
  for (const auto& t : out.triangles)
    for (int k = 0; k < 3; ++k) {
      const double len = (out.positions[t[k]] - out.positions[t[(k + 1) % 3]]).norm();
      for (const int v : {t[k], t[(k + 1) % 3]}) sum[v] += len, ++count[v];
    }
  for (std::size_t v = 0; v < sum.size(); ++v)
    if (count[v] > 0) sum[v] /= count[v];
  return sum;
}

/// Per vertex: the number of distinct neighbours in the triangles.
std::vector<int> vertexValences(const Assembly& out) {
  std::vector<std::vector<int>> neighbours(out.positions.size());
  for (const auto& t : out.triangles)
    for (int k = 0; k < 3; ++k) {
      neighbours[t[k]].push_back(t[(k + 1) % 3]);
      neighbours[t[k]].push_back(t[(k + 2) % 3]);
    }
  std::vector<int> valence(out.positions.size(), 0);
  for (std::size_t v = 0; v < neighbours.size(); ++v) {
    std::sort(neighbours[v].begin(), neighbours[v].end());
    valence[v] = static_cast<int>(std::unique(neighbours[v].begin(), neighbours[v].end()) -
                                  neighbours[v].begin());
  }
  return valence;
}

/// Area-weighted normal of the triangles at each vertex (zero where none).
std::vector<Eigen::Vector3d> vertexNormals(const Assembly& out) {
  std::vector<Eigen::Vector3d> normal(out.positions.size(), Eigen::Vector3d::Zero());
  for (const auto& t : out.triangles) {
    const Eigen::Vector3d n = (out.positions[t[1]] - out.positions[t[0]])
                                  .cross(out.positions[t[2]] - out.positions[t[0]]);
    for (const int v : t) normal[v] += n;
  }
  return normal;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

/// The input's boundary loops (vertex positions in face order, surface on the left) and the
/// component of each.
void inputBoundaryLoops(const TriMesh& mesh, const std::vector<int>& faceComponent,
                        std::vector<std::vector<Eigen::Vector3d>>& loops,
                        std::vector<int>& loopComponent) {
  std::vector<bool> seen(mesh.n_halfedges(), false);
  for (const auto start : mesh.halfedges()) {
    if (!mesh.is_boundary(start) || seen[start.idx()]) continue;
    // Boundary halfedges run against the faces; collect, then reverse to face order.
    std::vector<Eigen::Vector3d> loop;
    HH h = start;
    do {
      seen[h.idx()] = true;
      loop.push_back(toEigen(mesh.point(mesh.from_vertex_handle(h))));
      h = mesh.next_halfedge_handle(h);
    } while (h != start);
    std::reverse(loop.begin(), loop.end());
    loops.push_back(std::move(loop));
    loopComponent.push_back(
        faceComponent[mesh.face_handle(mesh.opposite_halfedge_handle(start)).idx()]);
  }
}

/// Removes the vertices listed in `drop` with their triangles.
void removeVertices(Assembly& out, const std::vector<bool>& drop) {
  std::erase_if(out.triangles, [&](const Triangle& t) { return drop[t[0]] || drop[t[1]] || drop[t[2]]; });
}

/// Fills the stretches of a boundary loop that are not on the output boundary: the whole loop
/// when none of it is, else each run of off-boundary vertices together with the boundary
/// vertices on either side (a notch in the boundary).
void fillGap(const std::vector<int>& loop, Assembly& out, std::vector<Triangle>& added,
             ExtractionReport& report) {
  const std::size_t n = loop.size();
  const auto fill = [&](const std::vector<int>& polygon) {
    if (polygon.size() < 3) return;
    const std::size_t before = out.positions.size();
    report.holeTriangles += fillHole(polygon, out.positions, added);
    for (std::size_t v = before; v < out.positions.size(); ++v) {
      out.component.push_back(out.component[polygon[0]]);
      out.onBoundary.push_back(false);
    }
    ++report.holesFilled;
  };
  std::size_t first = n;
  for (std::size_t k = 0; k < n && first == n; ++k)
    if (out.onBoundary[loop[k]] && !out.onBoundary[loop[(k + 1) % n]]) first = k;
  if (first == n) {
    if (!out.onBoundary[loop[0]]) fill(loop);  // no boundary vertex at all: a hole
    return;
  }
  // Runs start after a boundary vertex and end at the next boundary vertex.
  std::vector<int> polygon;
  for (std::size_t step = 0; step <= n; ++step) {
    const int v = loop[(first + step) % n];
    if (!polygon.empty() || (!out.onBoundary[v] && step > 0)) {
      if (polygon.empty()) polygon.push_back(loop[(first + step + n - 1) % n]);
      polygon.push_back(v);
      if (out.onBoundary[v]) {
        fill(polygon);
        polygon.clear();
      }
    }
  }
}

/// Samples up to this many places from a corner share its move (see stitchFrontByValence).
constexpr int kCornerSpread = 2;
/// A corner moves the nearest sample at most this many sample spacings; a corner farther from
/// every free sample is not resolved at this edge length, unless it is sharper than
/// kOwnSampleCornerAngle.
constexpr double kCornerReach = 0.5;
/// A boundary corner that turns by more than this many degrees gets a sample of its own when no
/// free sample is within kCornerReach spacings (at the price of a valence-7 front vertex).
constexpr double kOwnSampleCornerAngle = 80.0;

/// Stitches a front to its single input loop so that every front vertex gets valence 6 (paper
/// 5.2: irregular vertices only at singularities). A front vertex with a = latticeValence lattice
/// edges is joined
/// to d = max(1, 6 − a) consecutive boundary samples; neighbouring front vertices share one, so
/// the loop gets Σ(d − 1) samples. The sample shared by two front vertices sits at the middle of
/// their arc positions on the loop, the others of a front vertex evenly between its shared ones.
/// Each sharp corner of the loop takes the place of the nearest free sample within kCornerReach
/// spacings. Returns false (and adds nothing) for a front that runs back along the loop, corners
/// that would reorder the samples, or fewer than 3 samples.
bool stitchFrontByValence(const BoundaryIndex& index, int loop, int component,
                          const std::vector<int>& front, const std::vector<double>& frontArc,
                          const std::vector<int>& latticeValence, double spacing,
                          const ExtractOptions& options, Assembly& out,
                          std::vector<Triangle>& added, std::vector<LoopSamples>& loopSamples,
                          ExtractionReport& report) {
  const std::size_t n = front.size();
  const double length = index.loopLength(loop);
  if (frontArc.back() - frontArc.front() > length) return false;
  // Front vertex j is joined to samples first[j] .. first[j + 1] (indices modulo the count).
  std::vector<int> first(n + 1, 0);
  for (std::size_t j = 0; j < n; ++j)
    first[j + 1] = first[j] + std::max(1, 6 - latticeValence[front[j]]) - 1;
  int m = first[n];
  if (m < 3) return false;

  // Unwrapped arcs: sample m is sample 0 one loop later.
  const auto arcOf = [&](std::size_t j) { return j < n ? frontArc[j] : frontArc[j - n] + length; };
  std::vector<double> sum(m + 1, 0.0), count(m + 1, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    sum[first[j + 1]] += 0.5 * (arcOf(j) + arcOf(j + 1));
    count[first[j + 1]] += 1.0;
  }
  sum[0] += sum[m] - count[m] * length;
  count[0] += count[m];
  std::vector<double> arc(m + 1, 0.0);
  for (int k = 0; k < m; ++k)
    if (count[k] > 0.0) arc[k] = sum[k] / count[k];
  arc[m] = arc[0] + length;
  for (std::size_t j = 0; j < n; ++j)
    for (int k = first[j] + 1; k < first[j + 1]; ++k)
      arc[k] = arc[first[j]] + (arc[first[j + 1]] - arc[first[j]]) * (k - first[j]) /
                                   (first[j + 1] - first[j]);
  const auto wrapped = [&](double a) { return a - length * std::floor(a / length); };
  // Sharp corners are samples: the nearest sample moves onto each corner, and the samples up to
  // kCornerSpread places away follow a decreasing part of its move, so that the strip's
  // triangles around the corner share the distortion.
  std::vector<bool> corner(m, false);
  std::vector<double> shift(m, 0.0);
  // Corners in loop order from arc[0], each on the nearest sample after the previous corner's.
  std::vector<double> turns;
  const std::vector<double> cornerArcs =
      sharpCorners(index, loop, spacing, options.sharpBoundaryAngle, &turns);
  std::vector<std::pair<double, double>> corners;  // (unwrapped arc, degrees the loop turns)
  for (std::size_t c = 0; c < cornerArcs.size(); ++c)
    corners.emplace_back(arc[0] + wrapped(cornerArcs[c] - arc[0]), turns[c]);
  std::sort(corners.begin(), corners.end());
  int next = 0;
  for (const auto& [at, turn] : corners) {
    int nearest = next;
    for (int k = next + 1; k < m; ++k)
      if (std::abs(arc[k] - at) < std::abs(arc[nearest] - at)) nearest = k;
    if (nearest < m && std::abs(arc[nearest] - at) <= kCornerReach * spacing) {
      corner[nearest] = true;
      shift[nearest] = at - arc[nearest];
      next = nearest + 1;
      continue;
    }
    // No free sample within kCornerReach spacings: a corner sharper than kOwnSampleCornerAngle
    // gets a sample of its own, in the fan of the front vertex whose samples bracket it, which
    // then has valence 7 (a square plate at h = 0.1 lost two of its corners: 3.2% Hausdorff
    // distance); a blunter one is not resolved at this edge length.
    if (!(turn > kOwnSampleCornerAngle)) continue;
    const int atIndex = static_cast<int>(
        std::upper_bound(arc.begin() + std::max(next, 1), arc.begin() + m, at) - arc.begin());
    arc.insert(arc.begin() + atIndex, at);
    corner.insert(corner.begin() + atIndex, true);
    shift.insert(shift.begin() + atIndex, 0.0);
    for (int& f : first) f += f >= atIndex ? 1 : 0;
    ++m;
    next = atIndex + 1;
  }
  std::vector<double> moved(arc.begin(), arc.begin() + m);
  for (int k = 0; k < m; ++k) {
    if (corner[k]) {
      moved[k] += shift[k];
      continue;
    }
    // The nearest corner sample on either side within kCornerSpread places.
    double move = 0.0, weight = 0.0;
    for (int d = 1; d <= kCornerSpread; ++d)
      for (const int i : {(k + d) % m, (k - d + m) % m})
        if (corner[i]) {
          const double w = 1.0 - static_cast<double>(d) / (kCornerSpread + 1);
          move += w * shift[i];
          weight += 1.0;
        }
    if (weight > 0.0) moved[k] += move / weight;
  }
  for (int k = 0; k < m; ++k) {
    const double following = k + 1 < m ? moved[k + 1] : moved[0] + length;
    if (!(moved[k] < following)) return false;  // the corners would reorder the samples
  }
  std::copy(moved.begin(), moved.end(), arc.begin());
  arc[m] = arc[0] + length;
  std::vector<int> sample(m);
  for (int k = 0; k < m; ++k) {
    sample[k] = out.addVertex(index.pointAt(loop, wrapped(arc[k])), component);
    out.onBoundary[sample[k]] = true;
  }
  report.boundarySamples += m;
  // Triangles in the zip's orientation (see stitchStrip): outer steps {s_k, s_k+1, f_j}, then
  // the front step {f_j+1, f_j, s}.
  for (std::size_t j = 0; j < n; ++j) {
    for (int k = first[j]; k < first[j + 1]; ++k)
      added.push_back({sample[k % m], sample[(k + 1) % m], front[j]});
    added.push_back({front[(j + 1) % n], front[j], sample[first[j + 1] % m]});
  }
  // For the slides: the samples in ascending arc order in [0, length).
  LoopSamples samples{loop, spacing, {}, {}, {}};
  std::vector<int> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::rotate(order.begin(),
              std::min_element(order.begin(), order.end(),
                               [&](int a, int b) { return wrapped(arc[a]) < wrapped(arc[b]); }),
              order.end());
  for (const int k : order) {
    samples.vertex.push_back(sample[k]);
    samples.arc.push_back(wrapped(arc[k]));
    samples.corner.push_back(corner[k]);
  }
  loopSamples.push_back(std::move(samples));
  return true;
}

/// Samples the input loops `inputs` at the front's edge length and stitches the strip between
/// them and the lattice front (step 5). With several input loops, the front visits them one after
/// the other; their samples are chained into one outer loop, each loop walked once around from
/// the sample where the front arrives and joined to the next by a bridge edge, so the strip (a
/// sphere with 1 + k holes) is triangulated in one zip. A front along a single loop is stitched
/// by valence when it can be (stitchFrontByValence).
void stitchFront(const BoundaryIndex& index, const std::vector<int>& inputLoopComponent,
                 const std::vector<int>& inputs, std::vector<int> front,
                 const std::vector<double>& h, const std::vector<int>& latticeValence,
                 const std::vector<Eigen::Vector3d>& normals, const ExtractOptions& options,
                 Assembly& out, std::vector<Triangle>& added, std::vector<Triangle>& regular,
                 std::vector<LoopSamples>& loopSamples, ExtractionReport& report) {
  const std::size_t n = front.size();
  std::vector<double> frontH;
  for (const int v : front) frontH.push_back(h[v]);
  const double spacing = median(frontH);
  // The nearest of the input loops for each front vertex, and the arc position on it.
  std::vector<int> label(n);
  std::vector<double> arc(n);
  for (std::size_t j = 0; j < n; ++j) {
    BoundaryIndex::Hit best;
    for (const int i : inputs) {
      const auto hit = index.nearestOnLoop(out.positions[front[j]], i);
      if (hit.distance < best.distance) best = hit;
    }
    label[j] = best.loop, arc[j] = best.arc;
  }
  const auto addSamples = [&](int i) {
    std::vector<bool> corner;
    std::vector<double> sampleArc =
        sampleBoundaryLoop(index, i, spacing, options.sharpBoundaryAngle, &corner);
    std::vector<int> samples;
    for (const double s : sampleArc) {
      samples.push_back(out.addVertex(index.pointAt(i, s), inputLoopComponent[i]));
      out.onBoundary[samples.back()] = true;
    }
    report.boundarySamples += static_cast<long long>(samples.size());
    loopSamples.push_back({i, spacing, samples, sampleArc, corner});
    return std::pair{samples, sampleArc};
  };
  if (inputs.size() == 1) {
    std::vector<int> valenceFront = front;
    std::vector<double> valenceArc = arc;
    alignFrontToLoop({arc[0]}, valenceFront, valenceArc, index.loopLength(inputs[0]));
    for (std::size_t j = 1; j < n; ++j) valenceArc[j] = std::max(valenceArc[j], valenceArc[j - 1]);
    if (stitchFrontByValence(index, inputs[0], inputLoopComponent[inputs[0]], valenceFront,
                             valenceArc, latticeValence, spacing, options, out, regular,
                             loopSamples, report))
      return;
    const auto [samples, sampleArc] = addSamples(inputs[0]);
    alignFrontToLoop(sampleArc, front, arc, index.loopLength(inputs[0]));
    stitchStrip(out.positions, normals, samples, sampleArc, front, arc,
                index.loopLength(inputs[0]), added);
    return;
  }
  // Start the front where its label changes, so that each loop's first run begins a piece.
  std::size_t start = 0;
  for (std::size_t j = 0; j < n; ++j)
    if (label[j] != label[(j + n - 1) % n]) {
      start = j;
      break;
    }
  std::vector<int> order;  // the input loops in the order the front reaches them
  std::vector<double> entryArc;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t j = (start + k) % n;
    if (std::find(order.begin(), order.end(), label[j]) == order.end())
      order.push_back(label[j]), entryArc.push_back(arc[j]);
  }
  std::vector<int> outer;
  std::vector<double> outerParam;
  std::map<int, std::pair<double, double>> offsetAndStart;  // loop -> (offset, start arc)
  double offset = 0.0;
  for (std::size_t o = 0; o < order.size(); ++o) {
    const int i = order[o];
    const double length = index.loopLength(i);
    const auto [samples, sampleArc] = addSamples(i);
    const auto wrapped = [&](double d) { return d - length * std::floor(d / length); };
    std::size_t first = 0;
    for (std::size_t k = 1; k < samples.size(); ++k)
      if (std::min(wrapped(sampleArc[k] - entryArc[o]), length - wrapped(sampleArc[k] - entryArc[o])) <
          std::min(wrapped(sampleArc[first] - entryArc[o]), length - wrapped(sampleArc[first] - entryArc[o])))
        first = k;
    if (!outer.empty()) offset += (out.positions[outer.back()] - out.positions[samples[first]]).norm();
    offsetAndStart[i] = {offset, sampleArc[first]};
    for (std::size_t k = 0; k <= samples.size(); ++k) {
      const std::size_t at = (first + k) % samples.size();
      outer.push_back(samples[at]);
      outerParam.push_back(offset + (k == samples.size() ? length : wrapped(sampleArc[at] - sampleArc[first])));
    }
    offset = outerParam.back();
  }
  const double total = offset + (out.positions[outer.back()] - out.positions[outer.front()]).norm();
  std::vector<int> rotated(n);
  std::vector<double> param(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t j = (start + k) % n;
    rotated[k] = front[j];
    const auto [base, startArc] = offsetAndStart.at(label[j]);
    const double length = index.loopLength(label[j]);
    double d = arc[j] - startArc;
    d -= length * std::floor(d / length);
    if (d > 0.75 * length) d -= length;  // just before the piece's first sample
    param[k] = base + d;
  }
  stitchStrip(out.positions, normals, outer, outerParam, rotated, param, total, added);
}

/// Steps 4b and 5: resolves every boundary loop of the lattice triangles: a front along an input
/// boundary loop is stitched to that loop's samples (Follow) or left (Lattice); any other loop is
/// a coverage gap and is filled.
void closeBoundaries(const TriMesh& mesh, const std::vector<int>& faceComponent,
                     const ExtractOptions& options, Assembly& out, ExtractionReport& report) {
  std::vector<std::vector<Eigen::Vector3d>> inputLoops;
  std::vector<int> inputLoopComponent;
  inputBoundaryLoops(mesh, faceComponent, inputLoops, inputLoopComponent);
  std::vector<double> h = localEdgeLength(out);
  const double typical = median(std::vector<double>(h.begin(), h.end()));
  if (typical <= 0.0) return;  // no lattice triangles at all
  const BoundaryIndex index(inputLoops, 2.0 * typical);

  if (options.boundary == BoundaryMode::Follow && !inputLoops.empty()) {
    std::vector<bool> drop(out.positions.size(), false);
    for (std::size_t v = 0; v < out.positions.size(); ++v) {
      if (h[v] <= 0.0) continue;
      const auto hit = index.nearest(out.positions[v], options.boundarySnapDistance * h[v]);
      if (hit.loop >= 0) drop[v] = true, ++report.boundarySnapped;
    }
    removeVertices(out, drop);
    h = localEdgeLength(out);
  }

  // Classify the loops of the lattice triangles: a front when most of its vertices are within
  // reach of the input boundary, else a gap. Each input loop is stitched to the front that has
  // the most vertices near it; a front near several loops (the lattice does not fit between
  // them) is stitched to all of them at once.
  const auto loops = traceBoundaryLoops(out.triangles);
  std::vector<std::map<int, int>> votes(loops.size());
  std::vector<bool> isFront(loops.size(), false);
  for (std::size_t l = 0; l < loops.size(); ++l) {
    int near = 0;
    for (const int v : loops[l]) {
      const double reach = (options.boundarySnapDistance + 2.0) * std::max(h[v], typical);
      const auto hit = index.nearest(out.positions[v], reach);
      if (hit.loop >= 0) ++votes[l][hit.loop], ++near;
    }
    isFront[l] = 2 * near >= static_cast<int>(loops[l].size());
  }
  std::vector<int> owner(inputLoops.size(), -1);
  for (std::size_t l = 0; l < loops.size(); ++l) {
    if (!isFront[l]) continue;
    for (const auto& [i, count] : votes[l])
      if (count >= 2 && (owner[i] < 0 || count > votes[owner[i]].at(i))) owner[i] = static_cast<int>(l);
  }
  std::vector<std::vector<int>> assigned(loops.size());
  for (int i = 0; i < static_cast<int>(inputLoops.size()); ++i)
    if (owner[i] >= 0) assigned[owner[i]].push_back(i);

  std::vector<bool> componentHasLattice(*std::max_element(faceComponent.begin(), faceComponent.end()) + 1,
                                        false);
  for (const auto& t : out.triangles) componentHasLattice[out.component[t[0]]] = true;
  for (int i = 0; i < static_cast<int>(inputLoops.size()); ++i)
    if (owner[i] < 0 && componentHasLattice[inputLoopComponent[i]]) ++report.unmatchedBoundaryLoops;

  const std::vector<Eigen::Vector3d> normals = vertexNormals(out);
  const std::vector<int> latticeValence = vertexValences(out);
  // Strip and fill triangles: `added` may be flipped; `regular` (stitched by valence) keeps its
  // connectivity, which gives every front vertex valence 6.
  std::vector<Triangle> added, regular;
  std::vector<LoopSamples> loopSamples;  // the samples of every stitched input loop
  std::vector<int> gaps;
  for (std::size_t l = 0; l < loops.size(); ++l) {
    if (assigned[l].empty()) {
      gaps.push_back(static_cast<int>(l));
      continue;
    }
    if (options.boundary != BoundaryMode::Follow) {
      for (const int v : loops[l]) out.onBoundary[v] = true;
      continue;
    }
    const std::size_t before = added.size() + regular.size();
    stitchFront(index, inputLoopComponent, assigned[l], loops[l], h, latticeValence, normals,
                options, out, added, regular, loopSamples, report);
    report.stripTriangles += static_cast<long long>(added.size() + regular.size() - before);
  }
  std::sort(gaps.begin(), gaps.end());
  for (const int l : gaps) fillGap(loops[l], out, added, report);
  // Samples slide along the input boundary to open up the strip's thin triangles, then flips;
  // a second slide after the flips.
  const auto strips = [&] {
    std::vector<Triangle> all = added;
    all.insert(all.end(), regular.begin(), regular.end());
    return all;
  };
  report.boundarySlides += slideBoundarySamples(index, loopSamples, strips(), out.positions);
  out.triangles.insert(out.triangles.end(), regular.begin(), regular.end());
  report.stripFlips += improveByFlips(out.positions, out.triangles, added);
  report.boundarySlides += slideBoundarySamples(index, loopSamples, strips(), out.positions);
  out.triangles.insert(out.triangles.end(), added.begin(), added.end());
}

/// Vertices whose triangles do not form a single fan: their link (the edge opposite the vertex
/// in each triangle) is not one path or one cycle.
std::vector<int> nonManifoldVertices(const std::vector<Triangle>& triangles, std::size_t vertexCount) {
  // v's link edges are its outgoing directed edges (v, b) with their apex c: the edge b → c.
  const DirectedEdges edges(triangles);
  std::vector<int> bad;
  for (std::size_t v = 0; v < vertexCount; ++v) {
    const int first = edges.begin(static_cast<int>(v)), last = edges.end(static_cast<int>(v));
    const int count = last - first;
    if (count < 2) continue;
    const auto next = [&](int a) {
      for (int e = first; e < last; ++e)
        if (edges.to(e) == a) return edges.apex(e);
      return -1;
    };
    const auto incoming = [&](int a) {
      for (int e = first; e < last; ++e)
        if (edges.apex(e) == a) return true;
      return false;
    };
    // Start at a link vertex without an incoming edge (the fan's first edge) if there is one.
    int start = edges.to(first), starts = 0;
    for (int e = first; e < last; ++e)
      if (!incoming(edges.to(e))) start = edges.to(e), ++starts;
    int walked = 0;
    for (int a = start; walked <= count;) {
      a = next(a);
      if (a < 0) break;
      ++walked;
      if (a == start) break;
    }
    if (starts > 1 || walked != count) bad.push_back(static_cast<int>(v));
  }
  return bad;
}

/// Step 4c: what the previous steps left non-manifold is repaired locally: triangles that reuse
/// a directed edge are dropped, the triangles around a vertex with several fans are removed, and
/// the holes this leaves are filled (only their stretches off the output boundary).
void repairNonManifold(Assembly& out, ExtractionReport& report) {
  constexpr int kMaxPasses = 4;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    const std::size_t before = out.triangles.size();
    dropDegenerateAndOverlapping(out.triangles, report);
    const auto bad = nonManifoldVertices(out.triangles, out.positions.size());
    if (bad.empty() && out.triangles.size() == before) return;
    std::vector<bool> drop(out.positions.size(), false);
    for (const int v : bad) drop[v] = true;
    removeVertices(out, drop);
    report.nonManifoldVertices += static_cast<long long>(bad.size());
    std::vector<Triangle> added;
    for (const auto& loop : traceBoundaryLoops(out.triangles)) fillGap(loop, out, added, report);
    out.triangles.insert(out.triangles.end(), added.begin(), added.end());
  }
  // The passes ran out: the last fills may reuse a directed edge, which the boundary traces that
  // follow cannot take; such triangles go (buildMesh refuses what is still non-manifold).
  dropDegenerateAndOverlapping(out.triangles, report);
}

/// Euler characteristic, boundary loops and connected pieces of a triangle set (vertex indices
/// into any array).
struct SoupTopology {
  long long euler = 0;
  std::size_t boundaryLoops = 0;
  int pieces = 0;
  bool operator==(const SoupTopology& o) const {
    return euler == o.euler && boundaryLoops == o.boundaryLoops && pieces == o.pieces;
  }
};

SoupTopology soupTopology(const std::vector<Triangle>& triangles, std::size_t vertexCount) {
  // Union-find over the vertices (-1: not in the set); edges counted once per undirected pair.
  std::vector<int> parent(vertexCount, -1);
  const auto root = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  long long vertices = 0;
  for (const auto& t : triangles)
    for (const int v : t)
      if (parent[v] < 0) parent[v] = v, ++vertices;
  // Undirected edges: each directed edge (its first occurrence) whose reverse is absent, or
  // that runs upwards (u ≤ v).
  const DirectedEdges directed(triangles);
  long long edges = 0;
  for (std::size_t i = 0; i < triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int u = triangles[i][k], v = triangles[i][(k + 1) % 3];
      parent[root(u)] = root(v);
      if (directed.find(u, v) != directed.edgeOf(i, k)) continue;
      if (u <= v || directed.find(v, u) < 0) ++edges;
    }
  SoupTopology topology;
  topology.euler = vertices - edges + static_cast<long long>(triangles.size());
  topology.boundaryLoops = traceBoundaryLoops(triangles, directed).size();
  for (std::size_t v = 0; v < vertexCount; ++v)
    topology.pieces += parent[v] == static_cast<int>(v) ? 1 : 0;
  return topology;
}

/// Step 6: an input component is copied unchanged when no lattice triangle fits on it, or (Follow
/// mode) when its lattice triangles do not have its topology (Euler characteristic, boundary
/// loops, one piece): a component too small for the lattice, or one whose remesh would close a
/// hole (counted apart: the pipeline redoes such a run on another lattice).
void keepComponentsTooSmallForTheLattice(const TriMesh& mesh, const std::vector<int>& faceComponent,
                                         int componentCount, const ExtractOptions& options,
                                         Assembly& out, ExtractionReport& report) {
  // The input components' topology, from the mesh's connectivity (each is one piece). Not
  // computeTopology (core/mesh/topology.h): its components join faces through shared vertices,
  // these through shared edges.
  std::vector<SoupTopology> inputTopology(componentCount);
  for (auto& t : inputTopology) t.pieces = 1;
  std::vector<int> vertexComponent(mesh.n_vertices(), -1);
  for (const auto f : mesh.faces()) {
    const int c = faceComponent[f.idx()];
    inputTopology[c].euler += 1;
    for (const auto v : f.vertices()) vertexComponent[v.idx()] = c;
  }
  for (const auto v : mesh.vertices())
    if (vertexComponent[v.idx()] >= 0) inputTopology[vertexComponent[v.idx()]].euler += 1;
  for (const auto e : mesh.edges())
    if (const int c = vertexComponent[e.v0().idx()]; c >= 0) inputTopology[c].euler -= 1;
  std::vector<bool> seen(mesh.n_halfedges(), false);
  for (const auto h : mesh.halfedges()) {
    if (!h.is_boundary() || seen[h.idx()]) continue;
    for (auto g = h; !seen[g.idx()]; g = g.next()) seen[g.idx()] = true;
    ++inputTopology[vertexComponent[h.from().idx()]].boundaryLoops;
  }

  std::vector<std::vector<Triangle>> remeshed(componentCount);
  for (const auto& t : out.triangles) remeshed[out.component[t[0]]].push_back(t);
  // Fewer triangles than one hexagon's: the lattice is too coarse for the component (a single
  // lattice triangle inside an input triangle of a soup left the rest of it uncovered).
  constexpr std::size_t kMinRemeshedTriangles = 6;
  std::vector<bool> keep(componentCount, false);
  for (int c = 0; c < componentCount; ++c) {
    const bool tooFew = remeshed[c].size() < kMinRemeshedTriangles;
    const bool otherTopology =
        !tooFew && options.boundary == BoundaryMode::Follow &&
        !(soupTopology(remeshed[c], out.positions.size()) == inputTopology[c]);
    keep[c] = tooFew || otherTopology;
    report.componentsKeptForTopology += otherTopology ? 1 : 0;
  }
  std::erase_if(out.triangles, [&](const Triangle& t) { return keep[out.component[t[0]]]; });
  std::vector<int> copy(mesh.n_vertices(), -1);
  for (const auto f : mesh.faces()) {
    const int c = faceComponent[f.idx()];
    if (!keep[c]) continue;
    Triangle copied;
    int k = 0;
    for (const auto v : f.vertices()) {
      if (copy[v.idx()] < 0) copy[v.idx()] = out.addVertex(toEigen(mesh.point(v)), c);
      copied[k++] = copy[v.idx()];
    }
    out.triangles.push_back(copied);
  }
  for (int c = 0; c < componentCount; ++c) report.componentsKept += keep[c] ? 1 : 0;
}

/// The referenced vertices and the triangles as an OpenMesh mesh; faces OpenMesh refuses (they
/// would make a vertex or edge non-manifold) are counted, and the holes they leave (boundary
/// loops through no vertex of the output's boundary) are closed by a fan around the loop's
/// centroid, as in step 4.
TriMesh buildMesh(const Assembly& out, ExtractionReport& report) {
  TriMesh result;
  std::vector<VH> handle(out.positions.size());
  for (const auto& t : out.triangles)
    for (const int v : t)
      if (!handle[v].is_valid()) handle[v] = result.add_vertex(toOpenMesh(out.positions[v]));
  // OpenMesh refuses a face that would join two fans at a vertex in an order it cannot relink;
  // the same face usually goes in once its neighbours are there, so refused faces are retried
  // until no more can be added.
  std::vector<Triangle> pending = out.triangles;
  for (std::size_t before = pending.size() + 1; !pending.empty() && pending.size() < before;) {
    before = pending.size();
    std::vector<Triangle> refused;
    for (const auto& t : pending)
      if (!result.add_face(handle[t[0]], handle[t[1]], handle[t[2]]).is_valid()) refused.push_back(t);
    pending = std::move(refused);
  }
  report.nonManifoldFacesDropped = static_cast<long long>(pending.size());
  if (!pending.empty()) {
    std::vector<int> assemblyVertex(result.n_vertices(), -1);
    for (std::size_t v = 0; v < handle.size(); ++v)
      if (handle[v].is_valid()) assemblyVertex[handle[v].idx()] = static_cast<int>(v);
    std::vector<std::vector<OpenMesh::HalfedgeHandle>> holes;
    std::vector<bool> seen(result.n_halfedges(), false);
    for (const auto h : result.halfedges()) {
      if (!result.is_boundary(h) || seen[h.idx()]) continue;
      std::vector<OpenMesh::HalfedgeHandle> loop;
      bool outputBoundary = false;
      for (OpenMesh::HalfedgeHandle g = h; !seen[g.idx()]; g = result.next_halfedge_handle(g)) {
        seen[g.idx()] = true;
        loop.push_back(g);
        outputBoundary = outputBoundary || out.onBoundary[assemblyVertex[result.from_vertex_handle(g).idx()]];
      }
      if (!outputBoundary && loop.size() >= 3) holes.push_back(std::move(loop));
    }
    for (const auto& loop : holes) {
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (const auto g : loop) centroid += toEigen(result.point(result.from_vertex_handle(g)));
      const VH center = result.add_vertex(toOpenMesh(centroid / static_cast<double>(loop.size())));
      // The boundary halfedge a→b has no face: the face (a, b, center) takes it.
      for (const auto g : loop)
        result.add_face(result.from_vertex_handle(g), result.to_vertex_handle(g), center);
      ++report.holesFilled;
    }
  }
  // Vertices left without a face by refused faces are removed.
  if (report.nonManifoldFacesDropped > 0) {
    result.request_vertex_status();
    result.request_edge_status();
    result.request_face_status();
    for (const auto v : result.vertices())
      if (result.is_isolated(v)) result.delete_vertex(v, false);
    result.garbage_collection();
    result.release_vertex_status();
    result.release_edge_status();
    result.release_face_status();
  }
  return result;
}

}  // namespace

Remesh extractRemesh(const TriMesh& mesh, const Parameterization& param,
                     const ExtractOptions& options, const RunContext& context) {
  options.validate();
  if (param.n != 6)
    throw Error(ErrorCode::InvalidOption,
                "extraction supports the 6-RoSy (Eisenstein) lattice only; got N = " +
                    std::to_string(param.n));
  if (param.cornerCoords.size() != mesh.n_halfedges() || param.edgeTransition.size() != mesh.n_edges())
    throw Error(ErrorCode::InvalidOption,
                "the parameterization does not belong to this mesh (" +
                    std::to_string(param.cornerCoords.size()) + " corner coordinates for " +
                    std::to_string(mesh.n_halfedges()) + " halfedges)");
  Remesh result;
  ExtractionReport& report = result.report;
  int componentCount = 0;
  const std::vector<int> faceComponent = faceComponents(mesh, componentCount);
  Assembly out;
  {
    ScopedTimer timer(report.timings, "sanitize");
    context.report("extract", 0.0);
    const ExactChart chart = sanitize(mesh, param, report, context);
    LatticeExtractor extractor(mesh, chart, faceComponent, report, context);
    {
      ScopedTimer pointsTimer(report.timings, "lattice points");
      context.report("extract", 0.1);
      extractor.emitPoints(out);
    }
    ScopedTimer trianglesTimer(report.timings, "lattice triangles");
    context.report("extract", 0.3);
    extractor.emitTriangles(out);
  }
  {
    ScopedTimer timer(report.timings, "repair and boundary");
    context.report("extract", 0.7);
    context.throwIfCanceled();
    dropDegenerateAndOverlapping(out.triangles, report);
    if (componentCount > 0) closeBoundaries(mesh, faceComponent, options, out, report);
    repairNonManifold(out, report);
    keepComponentsTooSmallForTheLattice(mesh, faceComponent, componentCount, options, out, report);
    result.triangles = buildMesh(out, report);
  }
  // A remesh made only of components copied from the input (step 6) is the input as it is:
  // neither fitted nor rid of slivers.
  const bool onlyCopies = componentCount > 0 && report.componentsKept == componentCount;
  if (!onlyCopies) {
    ScopedTimer timer(report.timings, "surface fit");
    context.report("extract", 0.8);
    context.throwIfCanceled();
    if (options.fitToSurface && result.triangles.n_faces() > 0) {
      const ClosestPointQuery inputQuery(mesh);
      const auto counts = extract_detail::fitRemeshToSurface(
          mesh, inputQuery, result.triangles, options.featureSnapDistance, options.creaseAngle,
          options.balanceDeviation, options.threads);
      report.featureSnaps = counts.snapped;
      report.smoothedVertices = counts.smoothed;
      report.relaxedVertices = counts.relaxed;
      report.balancedVertices = counts.balanced;
    }
    if (options.sliverAngle > 0.0) {
      report.boundarySliverCollapses = collapseBoundarySlivers(
          result.triangles, options.sliverAngle, options.sharpBoundaryAngle);
      report.boundarySliverFlips = flipBoundarySlivers(result.triangles, options.sliverAngle);
    }
  }
  {
    ScopedTimer timer(report.timings, "hexagonal dual");
    context.report("extract", 0.9);
    result.hexDual = hexagonalDual(result.triangles);
  }
  context.report("extract", 1.0);
  return result;
}

}  // namespace hexcover
