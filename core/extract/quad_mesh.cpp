#include "core/extract/quad_mesh.h"

#include <algorithm>
#include <tuple>

#include "core/extract/fan_geometry.h"

namespace hexcover::extract_detail {
namespace {

using VH = TriMesh::VertexHandle;

/// A centred vertex's projection onto the input lies within this many local edge lengths of the
/// centroid of its neighbours, and its triangles come at most this many farther from the input.
constexpr double kCentreReach = 0.5;
constexpr double kCentreDeviation = 0.02;
/// Fit moves that leave a corner farther than kQuadCornerWindow from its ideal are taken back,
/// a fraction at a time, over kRestorePasses passes.
constexpr std::array<double, 2> kRestoreFractions{0.5, 1.0};
constexpr int kRestorePasses = 2;

/// The polygons at each vertex of a polygon mesh, its neighbours along polygon edges, and its
/// boundary vertices (on an edge of one polygon only).
struct PolygonAdjacency {
  std::vector<std::vector<int>> polygons, neighbours;
  std::vector<bool> onBoundary;

  explicit PolygonAdjacency(const PolygonSoup& soup)
      : polygons(soup.vertexCount()),
        neighbours(soup.vertexCount()),
        onBoundary(soup.vertexCount(), false) {
    for (std::size_t f = 0; f < soup.faceCount(); ++f)
      for (std::size_t k = soup.faceStarts[f]; k < soup.faceStarts[f + 1]; ++k)
        polygons[soup.cornerVertices[k]].push_back(static_cast<int>(f));
    const SoupEdges edges = soupEdges(soup);
    for (std::size_t e = 0; e < edges.edges.size(); ++e) {
      const auto [a, b] = edges.edges[e];
      neighbours[a].push_back(static_cast<int>(b));
      neighbours[b].push_back(static_cast<int>(a));
      if (edges.uses[e] == 1) onBoundary[a] = onBoundary[b] = true;
    }
  }
};

/// Largest deviation of a corner angle of v's polygons from its ideal (worstCornerDeviation), in
/// degrees, with v at p.
double worstCorner(const PolygonSoup& soup, const PolygonAdjacency& adjacency, int v,
                   const Eigen::Vector3d& p) {
  double worst = 0.0;
  std::vector<Eigen::Vector3d> corners;
  for (const int f : adjacency.polygons[v]) {
    corners.clear();
    for (std::size_t k = soup.faceStarts[f]; k < soup.faceStarts[f + 1]; ++k) {
      const int w = static_cast<int>(soup.cornerVertices[k]);
      corners.push_back(w == v ? p : soup.positions[w]);
    }
    worst = std::max(worst, worstCornerDeviation(corners));
  }
  return worst;
}

void moveVertex(PolygonSoup& quads, TriMesh& triangles, int v, const Eigen::Vector3d& p) {
  quads.positions[v] = p;
  triangles.set_point(VH(v), toOpenMesh(p));
}

}  // namespace

std::vector<int> squarePartners(const TriMesh& triangles,
                                const std::vector<std::array<int, 4>>& squares,
                                const std::vector<VH>& vertexOf) {
  std::vector<int> partner(triangles.n_faces(), kUnpaired);
  for (const auto& square : squares) {
    std::array<VH, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = vertexOf[square[k]];
    if (!std::all_of(v.begin(), v.end(), [](VH h) { return h.is_valid(); })) continue;
    // Triangle (0, 2, 3) holds the diagonal 0 -> 2, triangle (0, 1, 2) its opposite 2 -> 0.
    const auto h = triangles.find_halfedge(v[0], v[2]);
    if (!h.is_valid() || triangles.is_boundary(h) ||
        triangles.is_boundary(triangles.opposite_halfedge_handle(h)))
      continue;
    const auto o = triangles.opposite_halfedge_handle(h);
    const int f = triangles.face_handle(h).idx(), g = triangles.face_handle(o).idx();
    if (partner[f] >= 0 || partner[g] >= 0 ||
        triangles.to_vertex_handle(triangles.next_halfedge_handle(h)) != v[3] ||
        triangles.to_vertex_handle(triangles.next_halfedge_handle(o)) != v[1])
      continue;
    partner[f] = g;
    partner[g] = f;
  }
  return partner;
}

PolygonSoup pairSquares(const TriMesh& triangles, const std::vector<int>& partner) {
  PolygonSoup quads;
  quads.positions.reserve(triangles.n_vertices());
  for (const auto v : triangles.vertices()) quads.positions.push_back(toEigen(triangles.point(v)));
  for (const auto f : triangles.faces()) {
    const int g = partner[f.idx()];
    if (g >= 0 && g < f.idx()) continue;  // the square went in with its first triangle
    if (g < 0) {
      std::array<int, 3> t;
      int k = 0;
      for (const auto v : triangles.fv_range(f)) t[k++] = v.idx();
      quads.addFace(t);
      continue;
    }
    // f's edge shared with g, x -> y, gets g's third corner d between its ends.
    for (const auto h : triangles.fh_range(f)) {
      const auto o = triangles.opposite_halfedge_handle(h);
      if (triangles.face_handle(o).idx() != g) continue;
      const VH x = triangles.from_vertex_handle(h), y = triangles.to_vertex_handle(h);
      const VH z = triangles.to_vertex_handle(triangles.next_halfedge_handle(h));
      const VH d = triangles.to_vertex_handle(triangles.next_halfedge_handle(o));
      quads.addFace(std::array<int, 4>{x.idx(), d.idx(), y.idx(), z.idx()});
    }
  }
  return quads;
}

long long pairTriangles(const TriMesh& triangles, std::vector<int>& partner) {
  // Candidates: two unpaired triangles sharing an edge a -> b (in f; b -> a in g), as the quad
  // (a, d, b, c) with c and d their third corners; best (smallest worst corner deviation from
  // 90°) first.
  struct Candidate {
    double worst;
    int first, second;
  };
  std::vector<Candidate> candidates;
  for (const auto e : triangles.edges()) {
    if (triangles.is_boundary(e)) continue;
    const auto h = triangles.halfedge_handle(e, 0), o = triangles.halfedge_handle(e, 1);
    const int f = triangles.face_handle(h).idx(), g = triangles.face_handle(o).idx();
    if (partner[f] != kUnpaired || partner[g] != kUnpaired) continue;
    const auto at = [&](OpenMesh::HalfedgeHandle k) {
      return toEigen(triangles.point(triangles.to_vertex_handle(k)));
    };
    const std::array<Eigen::Vector3d, 4> quad{at(o), at(triangles.next_halfedge_handle(o)), at(h),
                                              at(triangles.next_halfedge_handle(h))};
    const double worst = worstCornerDeviation(quad);
    if (worst <= kQuadCornerWindow) candidates.push_back({worst, std::min(f, g), std::max(f, g)});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.worst, x.first, x.second) < std::tie(y.worst, y.first, y.second);
  });
  long long pairs = 0;
  for (const auto& c : candidates) {
    if (partner[c.first] != kUnpaired || partner[c.second] != kUnpaired) continue;
    partner[c.first] = c.second;
    partner[c.second] = c.first;
    ++pairs;
  }
  return pairs;
}

long long restoreQuadCorners(PolygonSoup& quads, TriMesh& triangles,
                             const std::vector<Eigen::Vector3d>& unfitted) {
  const PolygonAdjacency adjacency(quads);
  long long moves = 0;
  for (int pass = 0; pass < kRestorePasses; ++pass) {
    for (std::size_t i = 0; i < quads.vertexCount(); ++i) {
      const int v = static_cast<int>(i);
      const Eigen::Vector3d current = quads.positions[v];
      const double before = worstCorner(quads, adjacency, v, current);
      if (before <= kQuadCornerWindow || current == unfitted[v]) continue;
      double best = before;
      Eigen::Vector3d bestPosition = current;
      for (const double t : kRestoreFractions) {
        const Eigen::Vector3d p = current + t * (unfitted[v] - current);
        const double after = worstCorner(quads, adjacency, v, p);
        if (after < best) best = after, bestPosition = p;
        if (best <= kQuadCornerWindow) break;
      }
      if (bestPosition == current) continue;
      moveVertex(quads, triangles, v, bestPosition);
      ++moves;
    }
  }
  return moves;
}

long long centreIrregularVertices(PolygonSoup& quads, TriMesh& triangles,
                                  const ClosestPointQuery& input, const std::vector<char>& copied) {
  const PolygonAdjacency adjacency(quads);
  // Largest distance to the input of v's triangles' centroids and v's edge midpoints (the parts
  // of the remesh a move of v moves most), with v at p.
  const auto deviation = [&](int v, const Eigen::Vector3d& p) {
    const VH vh(v);
    double largest = 0.0;
    for (const auto f : triangles.vf_range(vh)) {
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (const auto w : triangles.fv_range(f))
        centroid += w == vh ? p : toEigen(triangles.point(w));
      largest = std::max(largest, input.closest(centroid / 3.0).distance);
    }
    for (const auto w : triangles.vv_range(vh))
      largest = std::max(largest, input.closest(0.5 * (p + toEigen(triangles.point(w)))).distance);
    return largest;
  };
  long long moves = 0;
  for (std::size_t i = 0; i < quads.vertexCount(); ++i) {
    const int v = static_cast<int>(i);
    const auto& around = adjacency.neighbours[v];
    if (adjacency.onBoundary[v] || copied[i] || around.size() == 4 || around.size() < 3) continue;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    double length = 0.0;
    for (const int w : around) {
      centroid += quads.positions[w];
      length += (quads.positions[w] - quads.positions[v]).norm();
    }
    centroid /= static_cast<double>(around.size());
    length /= static_cast<double>(around.size());
    const Eigen::Vector3d current = quads.positions[v];
    const Eigen::Vector3d p = input.closest(centroid).point;
    // Kept when the corners improve, the projection stays near the centroid (no jump to another
    // sheet of a thin part) and the remesh around v comes no farther from the input.
    if ((p - centroid).norm() > kCentreReach * length ||
        !(worstCorner(quads, adjacency, v, p) < worstCorner(quads, adjacency, v, current)) ||
        deviation(v, p) > deviation(v, current) + kCentreDeviation * length)
      continue;
    moveVertex(quads, triangles, v, p);
    ++moves;
  }
  return moves;
}

SliverRepairs repairSliversBesideSquares(TriMesh& triangles, std::vector<int>& partner,
                                         double sliverDegrees, double obtuseDegrees,
                                         double straightWithin) {
  // The repairs renumber the faces: each face carries its square (its lower face index) or its
  // partner code through them.
  OpenMesh::FPropHandleT<bool> fixed;  // halves of squares and copied triangles
  OpenMesh::FPropHandleT<int> square;
  triangles.add_property(fixed);
  triangles.add_property(square);
  for (const auto f : triangles.faces()) {
    const int other = partner[f.idx()];
    triangles.property(fixed, f) = other >= 0 || other == kKeptAsIs;
    triangles.property(square, f) = other >= 0 ? std::min(f.idx(), other) : other;
  }
  const SliverRepairs done =
      repairBoundarySlivers(triangles, sliverDegrees, obtuseDegrees, straightWithin, fixed);
  std::vector<int> firstHalf(partner.size(), -1);  // per square: its first face seen
  partner.assign(triangles.n_faces(), kUnpaired);
  for (const auto f : triangles.faces()) {
    const int id = triangles.property(square, f);
    if (id < 0) {
      partner[f.idx()] = id;
    } else if (firstHalf[id] < 0) {
      firstHalf[id] = f.idx();
    } else {
      partner[f.idx()] = firstHalf[id];
      partner[firstHalf[id]] = f.idx();
    }
  }
  triangles.remove_property(fixed);
  triangles.remove_property(square);
  return done;
}

}  // namespace hexcover::extract_detail
