#include "core/extract/lattice_extractor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <utility>

#include "core/extract/exact_lattice.h"

namespace hexcover::extract_detail {
namespace {

using HH = TriMesh::HalfedgeHandle;
using FH = TriMesh::FaceHandle;
using VH = TriMesh::VertexHandle;

/// Sanitized parameterization: fixed-point corner coordinates on which the recomputed integer
/// transitions hold exactly (algorithm notes, "Extraction": sanitize first).
struct ExactChart {
  int n = 6;                         ///< lattice order: 6 (Eisenstein) or 4 (Gauss)
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

/// Squared length of a lattice-coordinate vector in the plane: Gram matrix [[1, ½], [½, 1]] of
/// the Eisenstein basis (n = 6), the identity for the Gauss basis (n = 4).
double planeNorm2(const Eigen::Vector2d& d, int n) {
  return d.x() * d.x() + (n == 6 ? d.x() * d.y() : 0.0) + d.y() * d.y();
}

/// Step 1a: each interior edge's transition from the corner coordinates on both sides.
std::vector<Transition> recomputeTransitions(const TriMesh& mesh, const Parameterization& param,
                                             ExtractionReport& report) {
  const int n = param.n;
  std::vector<Transition> crossing(mesh.n_edges(), Transition{0, {0, 0}, n});
  for (const auto e : mesh.edges()) {
    if (mesh.is_boundary(e)) continue;
    const HH h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    // h0 runs A -> B in f0, h1 runs B -> A in f1.
    const Eigen::Vector2d a0 = fromCoords(mesh, param, h0), b0 = param.cornerCoords[h0.idx()];
    const Eigen::Vector2d b1 = fromCoords(mesh, param, h1), a1 = param.cornerCoords[h1.idx()];
    const EdgeTransition& given = param.edgeTransition[e.idx()];
    int best = given.rotation;
    const Eigen::Vector2d d0 = b0 - a0, d1 = b1 - a1;
    if (planeNorm2(d0, n) > 1e-18) {
      double bestResidual = planeNorm2(rotate(d0, best, n) - d1, n);
      for (int r = 0; r < n; ++r) {
        const double residual = planeNorm2(rotate(d0, r, n) - d1, n);
        if (residual < bestResidual - 1e-12) best = r, bestResidual = residual;
      }
    }
    const Eigen::Vector2d t = 0.5 * ((a1 - rotate(a0, best, n)) + (b1 - rotate(b0, best, n)));
    Transition transition{best, {std::llround(t.x()), std::llround(t.y())}, n};
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
  chart.n = param.n;
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
      Transition holonomy{0, {0, 0}, param.n};
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
    const __int128 o =
        orient(chart.corner[h0.idx()], chart.corner[h1.idx()], chart.corner[h2.idx()]);
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

  /// Step 3: every unit lattice cell whose centre a counter-clockwise parameter triangle owns,
  /// with its corners found by walking from the centre. N = 6: the triangles
  /// {(a,b), (a+1,b), (a,b+1)} and {(a+1,b), (a+1,b+1), (a,b+1)} (centroids (a+⅓, b+⅓),
  /// (a+⅔, b+⅔)). N = 4: the squares {(a,b), (a+1,b), (a+1,b+1), (a,b+1)} (centre (a+½, b+½)), each
  /// as the two triangles on either side of its diagonal (a,b)-(a+1,b+1), and in
  /// Assembly::squares.
  void emitCells(Assembly& out) {
    for (const auto f : mesh_.faces()) {
      if ((f.idx() & 4095) == 0) context_.throwIfCanceled();
      if (chart_.orientation[f.idx()] <= 0) continue;
      const auto [h, q] = corners(f);
      const auto [lo, hi] = bounds(q);
      for (std::int64_t a = floorUnits(lo.a) - 1; a <= ceilUnits(hi.a); ++a)
        for (std::int64_t b = floorUnits(lo.b) - 1; b <= ceilUnits(hi.b); ++b) {
          if (chart_.n == 4) {
            const FixedPoint c{a * kUnit + kUnit / 2, b * kUnit + kUnit / 2};
            if (!ownsCentroid(f, h, q, c)) continue;
            const auto square =
                cellVertices<4>(f, c,
                                {latticePoint(a, b), latticePoint(a + 1, b),
                                 latticePoint(a + 1, b + 1), latticePoint(a, b + 1)});
            if (!square) continue;
            const auto& v = *square;
            out.squares.push_back(v);
            out.triangles.push_back({v[0], v[1], v[2]});
            out.triangles.push_back({v[0], v[2], v[3]});
            report_.latticeTriangles += 2;
            ++report_.latticeSquares;
            continue;
          }
          for (const int third : {1, 2}) {
            // Centroid (a + third/3, b + third/3) in fixed point (kUnit = 3 · 2^24).
            const FixedPoint c{a * kUnit + third * (kUnit / 3), b * kUnit + third * (kUnit / 3)};
            if (!ownsCentroid(f, h, q, c)) continue;
            const auto triangle = cellVertices<3>(
                f, c,
                third == 1
                    ? std::array<FixedPoint, 3>{latticePoint(a, b), latticePoint(a + 1, b),
                                                latticePoint(a, b + 1)}
                    : std::array<FixedPoint, 3>{latticePoint(a + 1, b), latticePoint(a + 1, b + 1),
                                                latticePoint(a, b + 1)});
            if (!triangle) continue;
            out.triangles.push_back(*triangle);
            ++report_.latticeTriangles;
          }
        }
    }
  }

 private:
  enum class Walk { Found, LeftSurface, Blocked };

  /// The lattice points emitted for the corners of a cell whose centre c lies in f, found by
  /// walking from c; nothing when a walk leaves the surface (the cell is cut by the boundary) or
  /// is blocked by a fold (a coverage gap), each counted.
  template <std::size_t K>
  std::optional<std::array<int, K>> cellVertices(FH f, const FixedPoint& c,
                                                 const std::array<FixedPoint, K>& corner) {
    std::array<int, K> vertex;
    Walk end = Walk::Found;
    for (std::size_t k = 0; k < K && end == Walk::Found; ++k)
      end = walk(f, c, corner[k], vertex[k]);
    if (end == Walk::Found) return vertex;
    ++(end == Walk::LeftSurface ? report_.boundaryClipped : report_.uncoveredTriangles);
    return std::nullopt;
  }

  int addVertex(Assembly& out, const Eigen::Vector3d& p, int face) {
    return out.addVertex(p, component_[face]);
  }

  std::pair<std::array<HH, 3>, std::array<FixedPoint, 3>> corners(FH f) const {
    const HH h0 = mesh_.halfedge_handle(f), h1 = mesh_.next_halfedge_handle(h0),
             h2 = mesh_.next_halfedge_handle(h1);
    return {{h0, h1, h2},
            {chart_.corner[h0.idx()], chart_.corner[h1.idx()], chart_.corner[h2.idx()]}};
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

  /// Whether f is the one face that emits the unit cell with centre c: c is in f's closed
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
        if (s[k] < 0 && orient(from, target, q[(k + 2) % 3]) <= 0 &&
            orient(from, target, q[k]) >= 0)
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

}  // namespace

void extractLattice(const TriMesh& mesh, const Parameterization& param,
                    const std::vector<int>& faceComponent, Assembly& out, ExtractionReport& report,
                    const RunContext& context) {
  context.report(stage::kExtraction, 0.0);
  out.latticeOrder = param.n;
  const ExactChart chart = [&] {
    ScopedTimer timer(report.timings, "sanitize");
    return sanitize(mesh, param, report, context);
  }();
  LatticeExtractor extractor(mesh, chart, faceComponent, report, context);
  {
    ScopedTimer timer(report.timings, "lattice points");
    context.report(stage::kExtraction, 0.1);
    extractor.emitPoints(out);
  }
  ScopedTimer timer(report.timings, param.n == 4 ? "lattice squares" : "lattice triangles");
  context.report(stage::kExtraction, 0.3);
  extractor.emitCells(out);
}

}  // namespace hexcover::extract_detail
