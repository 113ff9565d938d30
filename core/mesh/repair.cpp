#include "core/mesh/repair.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "core/common/concurrency.h"
#include "core/common/error.h"
#include "core/mesh/soup_connectivity.h"
#include "core/mesh/validate.h"

namespace hexcover {
namespace {

using detail::EdgeTable;
using detail::Triangle;

constexpr std::uint32_t kNone = UINT32_MAX;
/// Polygons with more corners are fan-triangulated: ear clipping costs O(n³) on adversarial
/// outlines, and at 16 corners a file at the face limit still triangulates in about a second.
constexpr std::size_t kMaxEarClippingCorners = 16;
/// Bounding-box diagonals the pipeline supports: areas and squared lengths of meshes much smaller
/// (or larger) underflow (or overflow) in double precision; remeshes work to beyond 1e±60.
constexpr double kMinDiagonal = 1e-50;
constexpr double kMaxDiagonal = 1e50;

std::string formatPoint(const Eigen::Vector3d& p) {
  std::ostringstream out;
  out << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return out.str();
}

void validateOptions(const RepairOptions& options) {
  if (!(options.weldTolerance >= 0.0 && options.weldTolerance <= 0.1))
    throw Error(ErrorCode::InvalidOption,
                "weld tolerance must be in [0, 0.1] (a fraction of the "
                "bounding-box diagonal), got " +
                    std::to_string(options.weldTolerance));
  if (options.maxFaces == 0)
    throw Error(ErrorCode::InvalidOption, "the face limit must be positive");
  if (options.threads < 1)
    throw Error(ErrorCode::InvalidOption,
                "repair threads must be at least 1, got " + std::to_string(options.threads));
}

// Refuses what no repair can fix, naming the first offending element.
void refuseUnrepairable(const PolygonSoup& soup, const RepairOptions& options) {
  detail::checkSoupStructure(soup, /*checkIndices=*/false);
  if (soup.faceCount() == 0)
    throw Error(ErrorCode::InvalidMesh,
                "empty mesh: no faces (" + std::to_string(soup.vertexCount()) + " vertices)");
  std::size_t triangles = 0;
  for (std::size_t f = 0; f < soup.faceCount(); ++f)
    triangles += std::max<std::size_t>(soup.faceSize(f), 3) - 2;
  if (triangles > options.maxFaces)
    throw Error(ErrorCode::LimitExceeded, "the mesh has " + std::to_string(triangles) +
                                              " triangles, over the limit of " +
                                              std::to_string(options.maxFaces));
  detail::checkSoupStructure(soup, /*checkIndices=*/true);
  for (std::size_t v = 0; v < soup.vertexCount(); ++v)
    if (!soup.positions[v].allFinite())
      throw Error(ErrorCode::InvalidMesh, "vertex " + std::to_string(v) +
                                              " has a NaN or infinite coordinate " +
                                              formatPoint(soup.positions[v]));
}

// Refuses a mesh whose bounding box (corners low, high) is outside the supported sizes. A zero
// diagonal is left to the degenerate-face check.
void refuseExtremeSize(const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  const double diagonal = 2.0 * (0.5 * high - 0.5 * low).norm();  // halves: no overflow
  if (diagonal > 0.0 && !(diagonal >= kMinDiagonal && diagonal <= kMaxDiagonal)) {
    std::ostringstream message;
    message << "the mesh's bounding-box diagonal is " << diagonal << ", outside the supported "
            << "range " << kMinDiagonal << " to " << kMaxDiagonal
            << ": scale its coordinates (a remesh does not depend on the unit)";
    throw Error(ErrorCode::InvalidMesh, message.str());
  }
}

// Ear clipping of face f in the plane of its Newell normal; falls back to a fan for large or
// numerically degenerate polygons and when no ear is found (self-intersecting outlines).
void triangulateFace(const PolygonSoup& soup, std::size_t f, std::vector<Triangle>& out) {
  const std::uint32_t* corners = soup.cornerVertices.data() + soup.faceStarts[f];
  const std::size_t n = soup.faceSize(f);
  const auto fan = [&](const std::vector<std::uint32_t>& ring) {
    for (std::size_t i = 1; i + 1 < ring.size(); ++i)
      out.push_back({ring[0], ring[i], ring[i + 1]});
  };
  std::vector<std::uint32_t> ring(corners, corners + n);
  if (n == 3 || n > kMaxEarClippingCorners) return fan(ring);
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i)
    normal += soup.positions[corners[i]].cross(soup.positions[corners[(i + 1) % n]]);
  if (!(normal.norm() > 0.0)) return fan(ring);
  normal.normalize();
  const Eigen::Vector3d u = normal.unitOrthogonal();
  const Eigen::Vector3d w = normal.cross(u);
  const auto at = [&](std::uint32_t v) {
    return Eigen::Vector2d(soup.positions[v].dot(u), soup.positions[v].dot(w));
  };
  const auto cross2 = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  while (ring.size() > 3) {
    const std::size_t m = ring.size();
    bool clipped = false;
    for (std::size_t i = 0; i < m && !clipped; ++i) {
      const Eigen::Vector2d a = at(ring[(i + m - 1) % m]), b = at(ring[i]),
                            c = at(ring[(i + 1) % m]);
      if (cross2(b - a, c - b) <= 0.0) continue;  // reflex or flat corner
      bool empty = true;
      for (std::size_t j = 0; j < m && empty; ++j) {
        if (j == i || j == (i + 1) % m || j == (i + m - 1) % m) continue;
        const Eigen::Vector2d p = at(ring[j]);
        empty = !(cross2(b - a, p - a) >= 0.0 && cross2(c - b, p - b) >= 0.0 &&
                  cross2(a - c, p - c) >= 0.0);
      }
      if (!empty) continue;
      out.push_back({ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) return fan(ring);
  }
  out.push_back({ring[0], ring[1], ring[2]});
}

// Representative of every vertex after welding referenced vertices closer than `tolerance`
// (exactly coincident ones when it is 0): the lowest index of each group of vertices linked by
// such distances. Unreferenced vertices map to themselves.
// `origin` is the lower corner of the bounding box and `diagonal` its length.
std::vector<std::uint32_t> weldVertices(const std::vector<Eigen::Vector3d>& positions,
                                        const std::vector<bool>& referenced,
                                        const Eigen::Vector3d& origin, double diagonal,
                                        double tolerance) {
  detail::UnionFind groups(positions.size());
  // Below ~1e-15 of the diagonal, distances are at the level of rounding: weld exact copies only
  // (this also keeps grid cell indices far from integer overflow).
  if (!(tolerance > 1e-15 * diagonal)) {
    std::vector<std::uint32_t> order;
    for (std::uint32_t v = 0; v < positions.size(); ++v)
      if (referenced[v]) order.push_back(v);
    const auto key = [&](std::uint32_t v) {
      return std::array<double, 3>{positions[v].x(), positions[v].y(), positions[v].z()};
    };
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return key(a) < key(b); });
    for (std::size_t i = 1; i < order.size(); ++i)
      if (key(order[i]) == key(order[i - 1])) groups.unite(order[i], order[i - 1]);
  } else {
    // Hash grid of cell size 2·tolerance: a point's partners within `tolerance` lie in the 2×2×2
    // cells on the sides of its own cell that it is closest to.
    using Cell = std::array<std::int64_t, 3>;
    struct CellHash {
      std::size_t operator()(const Cell& c) const {
        std::uint64_t h = 14695981039346656037ull;
        for (const auto x : c) h = (h ^ static_cast<std::uint64_t>(x)) * 1099511628211ull;
        return static_cast<std::size_t>(h ^ (h >> 32));
      }
    };
    const double cellSize = 2.0 * tolerance;
    std::unordered_map<Cell, std::uint32_t, CellHash> cellHead;  // last vertex put in a cell
    cellHead.reserve(positions.size());
    std::vector<std::uint32_t> next(positions.size(), kNone);  // chain of vertices per cell
    const double toleranceSquared = tolerance * tolerance;
    for (std::uint32_t v = 0; v < positions.size(); ++v) {
      if (!referenced[v]) continue;
      const Eigen::Vector3d scaled = (positions[v] - origin) / cellSize;
      const Cell cell{static_cast<std::int64_t>(std::floor(scaled.x())),
                      static_cast<std::int64_t>(std::floor(scaled.y())),
                      static_cast<std::int64_t>(std::floor(scaled.z()))};
      Cell side{};
      for (int i = 0; i < 3; ++i) side[i] = scaled[i] - static_cast<double>(cell[i]) < 0.5 ? -1 : 1;
      // A vertex that welds is not put in the grid (its partner stands for it there), so that
      // cells never hold more than a few mutually distant vertices: no quadratic chains.
      bool welded = false;
      for (int corner = 0; corner < 8; ++corner) {
        const Cell probe{cell[0] + ((corner & 1) ? side[0] : 0),
                         cell[1] + ((corner & 2) ? side[1] : 0),
                         cell[2] + ((corner & 4) ? side[2] : 0)};
        const auto it = cellHead.find(probe);
        if (it == cellHead.end()) continue;
        for (std::uint32_t w = it->second; w != kNone; w = next[w])
          if ((positions[w] - positions[v]).squaredNorm() <= toleranceSquared) {
            groups.unite(v, w);
            welded = true;
          }
      }
      if (welded) continue;
      auto [it, inserted] = cellHead.try_emplace(cell, v);
      if (!inserted) {
        next[v] = it->second;
        it->second = v;
      }
    }
  }
  std::vector<std::uint32_t> representative(positions.size());
  for (std::uint32_t v = 0; v < positions.size(); ++v) representative[v] = groups.find(v);
  return representative;
}

bool isZeroArea(const std::vector<Eigen::Vector3d>& positions, const Triangle& t) {
  const Eigen::Vector3d &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
  const double longest =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return !((b - a).cross(c - a).norm() > 1e-12 * longest);
}

// The triangles with their input face, filtered in place by `keep`.
template <typename Keep>
std::size_t filterTriangles(std::vector<Triangle>& tris, std::vector<std::uint32_t>& origin,
                            Keep keep) {
  std::size_t kept = 0;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    if (!keep(t)) continue;
    tris[kept] = tris[t];
    origin[kept] = origin[t];
    ++kept;
  }
  const std::size_t dropped = tris.size() - kept;
  tris.resize(kept);
  origin.resize(kept);
  return dropped;
}

// Splits non-manifold edges and vertices: vertices get one copy per fan of triangles, where fans
// are joined across two-triangle edges and, for an edge with more triangles, across consistently
// oriented pairs of them only (so each pair ends up on its own copy of the edge). Copies are
// appended to `positions`. Repeats while edges with more than two triangles remain (a few rounds
// at most; anything left is refused by add_face and counted). Returns the edge table of the
// final triangles.
EdgeTable splitNonManifold(std::vector<Triangle>& tris, std::vector<Eigen::Vector3d>& positions,
                           RepairCounts& counts) {
  constexpr int kMaxRounds = 4;
  for (int round = 0; round < kMaxRounds; ++round) {
    EdgeTable edges = detail::buildEdgeTable(tris);
    std::vector<std::array<std::uint32_t, 2>> pairs;
    pairs.reserve(edges.edgeCount());
    std::vector<bool> onSplitEdge(positions.size(), false);
    std::size_t splitEdges = 0;
    for (std::size_t e = 0; e < edges.edgeCount(); ++e) {
      const std::uint32_t* hs = edges.halfedges.data() + edges.edgeStarts[e];
      const std::size_t k = edges.valence(e);
      if (k == 2) pairs.push_back({hs[0], hs[1]});
      if (k <= 2) continue;
      ++splitEdges;
      const std::uint32_t tail = detail::halfedgeTail(tris, hs[0]);
      onSplitEdge[tail] = onSplitEdge[detail::halfedgeHead(tris, hs[0])] = true;
      // Glue the triangles in consistently oriented pairs (one traversing the edge each way),
      // in index order; the rest stay alone on their own copy of the edge.
      std::vector<std::uint32_t> forward, backward;
      for (std::size_t i = 0; i < k; ++i)
        (detail::halfedgeTail(tris, hs[i]) == tail ? forward : backward).push_back(hs[i]);
      for (std::size_t i = 0; i < std::min(forward.size(), backward.size()); ++i)
        pairs.push_back({forward[i], backward[i]});
    }
    detail::UnionFind fans = detail::cornerFans(tris, pairs);
    std::vector<std::uint32_t> firstFan(positions.size(), kNone);
    std::vector<std::uint32_t> vertexOfFan(3 * tris.size(), kNone);
    std::vector<bool> split(positions.size(), false);
    std::size_t added = 0;
    for (std::uint32_t c = 0; c < 3 * tris.size(); ++c) {
      std::uint32_t& v = tris[c / 3][c % 3];
      const std::uint32_t fan = fans.find(c);
      if (firstFan[v] == kNone) firstFan[v] = fan;
      if (firstFan[v] == fan) continue;
      if (vertexOfFan[fan] == kNone) {
        vertexOfFan[fan] = static_cast<std::uint32_t>(positions.size());
        positions.push_back(positions[v]);
        ++added;
        split[v] = true;
      }
      v = vertexOfFan[fan];
    }
    counts.splitNonManifoldEdges += splitEdges;
    counts.addedVertices += added;
    for (std::size_t v = 0; v < split.size(); ++v)
      counts.splitNonManifoldVertices += split[v] && !onSplitEdge[v];
    if (splitEdges == 0 && added == 0) return edges;  // nothing changed: the table still holds
    if (splitEdges == 0) break;                       // one round settles non-manifold vertices
  }
  return detail::buildEdgeTable(tris);
}

// Orients every edge-connected patch consistently and counts the flips: closed patches outward
// (positive signed volume) when `outward`, other patches toward the majority of their triangles.
// Refuses non-orientable patches.
void orientPatches(std::vector<Triangle>& tris, const EdgeTable& edges,
                   const std::vector<std::uint32_t>& origin,
                   const std::vector<Eigen::Vector3d>& positions, bool outward,
                   RepairCounts& counts) {
  detail::Orientation orientation = detail::propagateOrientation(tris, edges);
  const std::size_t patchCount = orientation.conflict.size();
  std::vector<std::size_t> size(patchCount, 0), reversed(patchCount, 0);
  std::vector<bool> open(patchCount, false);
  std::vector<double> volume(patchCount, 0.0);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const std::uint32_t p = orientation.patch[t];
    ++size[p];
    reversed[p] += orientation.sign[t] < 0;
    const Eigen::Vector3d &a = positions[tris[t][0]], &b = positions[tris[t][1]],
                          &c = positions[tris[t][2]];
    volume[p] += orientation.sign[t] * a.dot(b.cross(c));
  }
  for (std::size_t e = 0; e < edges.edgeCount(); ++e)
    if (edges.valence(e) == 1)
      open[orientation.patch[edges.halfedges[edges.edgeStarts[e]] / 3]] = true;
  for (std::size_t p = 0; p < patchCount; ++p) {
    const std::uint32_t t = orientation.conflict[p];
    if (t != kNone)
      throw Error(
          ErrorCode::InvalidMesh,
          "non-orientable component: the " + std::to_string(size[p]) +
              " triangles connected to input face " + std::to_string(origin[t]) +
              " cannot be oriented consistently (a Moebius-like strip); repair cannot fix this");
  }
  std::vector<bool> invert(patchCount, false);
  for (std::size_t p = 0; p < patchCount; ++p)
    invert[p] = open[p] || !outward ? 2 * reversed[p] > size[p] : volume[p] < 0.0;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const bool flip = (orientation.sign[t] < 0) != invert[orientation.patch[t]];
    if (!flip) continue;
    std::swap(tris[t][1], tris[t][2]);
    ++counts.flippedFaces;
  }
}

// With repair off, names every repair the mesh would need.
void refuseRepairs(const RepairCounts& counts) {
  std::string needed;
  const auto need = [&](std::size_t count, const char* what) {
    if (count == 0) return;
    needed += (needed.empty() ? "" : ", ") + std::to_string(count) + " " + what;
  };
  need(counts.weldedVertices, "vertices to weld");
  need(counts.droppedDegenerateFaces, "degenerate faces");
  need(counts.droppedDuplicateFaces, "duplicate faces");
  need(counts.droppedUnreferencedVertices, "unreferenced vertices");
  need(counts.splitNonManifoldEdges, "non-manifold edges");
  need(counts.splitNonManifoldVertices, "non-manifold vertices");
  need(counts.flippedFaces, "faces to flip for a consistent orientation");
  need(counts.facesRefusedByMesh, "faces the half-edge mesh refuses");
  if (!needed.empty())
    throw Error(ErrorCode::InvalidMesh, "repair is off but the mesh needs it: " + needed);
}

// Builds in the empty `mesh` the repaired triangles of `soup` (triangulated, welded, without
// degenerate and duplicate triangles, manifold, oriented), counting what was done in `counts`.
void buildRepairedTriangles(const PolygonSoup& soup, const RepairOptions& options,
                            RepairCounts& counts, TriMesh& mesh) {
  // Triangulate, keeping the input face of every triangle for messages.
  std::vector<Triangle> tris;
  std::vector<std::uint32_t> origin;
  // Σ (corners − 2) triangles when every face has 3 corners or more.
  tris.reserve(soup.cornerVertices.size() -
               std::min(soup.cornerVertices.size(), 2 * soup.faceCount()));
  for (std::size_t f = 0; f < soup.faceCount(); ++f) {
    const std::size_t n = soup.faceSize(f);
    if (n < 3) {
      ++counts.droppedDegenerateFaces;
      continue;
    }
    if (n > 3) ++counts.polygonsTriangulated;
    triangulateFace(soup, f, tris);
    origin.resize(tris.size(), static_cast<std::uint32_t>(f));
  }

  // Weld referenced vertices.
  std::vector<bool> referenced(soup.vertexCount(), false);
  for (const auto& t : tris)
    for (const auto v : t) referenced[v] = true;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t v = 0; v < soup.vertexCount(); ++v)
    if (referenced[v]) {
      lo = lo.cwiseMin(soup.positions[v]);
      hi = hi.cwiseMax(soup.positions[v]);
    }
  if (!tris.empty()) refuseExtremeSize(lo, hi);
  const double diagonal = tris.empty() ? 0.0 : (hi - lo).norm();
  const std::vector<std::uint32_t> representative =
      weldVertices(soup.positions, referenced, lo, diagonal, options.weldTolerance * diagonal);
  for (std::size_t v = 0; v < soup.vertexCount(); ++v)
    counts.weldedVertices += representative[v] != v;
  for (auto& t : tris)
    for (auto& v : t) v = representative[v];

  // Drop degenerate, then duplicate triangles (same vertex set as an earlier one).
  std::vector<Eigen::Vector3d> positions = soup.positions;
  counts.droppedDegenerateFaces += filterTriangles(tris, origin, [&](std::size_t t) {
    const Triangle& tri = tris[t];
    return tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2] && !isZeroArea(positions, tri);
  });
  {
    std::vector<std::pair<Triangle, std::uint32_t>> sorted(tris.size());
    for (std::uint32_t t = 0; t < tris.size(); ++t) {
      Triangle key = tris[t];
      std::sort(key.begin(), key.end());
      sorted[t] = {key, t};
    }
    std::sort(sorted.begin(), sorted.end());
    std::vector<bool> duplicate(tris.size(), false);
    for (std::size_t i = 1; i < sorted.size(); ++i)
      if (sorted[i].first == sorted[i - 1].first) duplicate[sorted[i].second] = true;
    counts.droppedDuplicateFaces +=
        filterTriangles(tris, origin, [&](std::size_t t) { return !duplicate[t]; });
  }

  // Split non-manifold edges and vertices, then orient.
  const EdgeTable edges = splitNonManifold(tris, positions, counts);
  orientPatches(tris, edges, origin, positions, /*outward=*/options.repair, counts);

  // Drop unreferenced vertices (input order kept, split copies after) and build the mesh.
  std::vector<std::uint32_t> newIndex(positions.size(), kNone);
  for (const auto& t : tris)
    for (const auto v : t) newIndex[v] = 0;
  std::uint32_t used = 0;
  for (auto& index : newIndex)
    if (index != kNone) index = used++;
  for (std::size_t v = 0; v < soup.vertexCount(); ++v)
    counts.droppedUnreferencedVertices += representative[v] == v && newIndex[v] == kNone;
  if (tris.empty())
    throw Error(ErrorCode::InvalidMesh, "empty mesh: all " + std::to_string(soup.faceCount()) +
                                            " faces are degenerate or duplicates");

  mesh.reserve(used, 3 * tris.size() / 2 + 3, tris.size());
  std::vector<TriMesh::VertexHandle> handles(used);
  for (std::size_t v = 0; v < positions.size(); ++v)
    if (newIndex[v] != kNone) handles[newIndex[v]] = mesh.add_vertex(toOpenMesh(positions[v]));
  for (const auto& t : tris) {
    const auto fh =
        mesh.add_face(handles[newIndex[t[0]]], handles[newIndex[t[1]]], handles[newIndex[t[2]]]);
    counts.facesRefusedByMesh += !fh.is_valid();
  }
  counts.droppedFaces =
      counts.droppedDegenerateFaces + counts.droppedDuplicateFaces + counts.facesRefusedByMesh;
}

}  // namespace

RepairedMesh repairMesh(const PolygonSoup& soup, const RepairOptions& options) {
  validateOptions(options);
  refuseUnrepairable(soup, options);
  RepairedMesh out;
  MeshReport& report = out.report;
  // The input is measured (report.input) on a second thread while it is repaired.
  runBoth(
      options.threads, [&] { buildRepairedTriangles(soup, options, report.repairs, out.mesh); },
      [&] { report.input = measureMesh(soup); });
  if (!options.repair) refuseRepairs(report.repairs);
  report.repaired = options.repair;
  report.result = measureMesh(toPolygonSoup(out.mesh));
  return out;
}

}  // namespace hexcover
