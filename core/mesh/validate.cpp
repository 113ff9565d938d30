#include "core/mesh/validate.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <span>

#include "core/mesh/soup_connectivity.h"

namespace hexcover {
namespace {

using detail::EdgeTable;
using detail::Triangle;
using detail::UnionFind;

// A face is degenerate when it has fewer than 3 corners, an index out of range, a repeated
// vertex, or (numerically) zero area: |Newell normal| ≤ 1e-12 · (longest edge)².
bool isDegenerateFace(const PolygonSoup& soup, std::size_t f) {
  const std::size_t n = soup.faceSize(f);
  if (n < 3) return true;
  const std::span<const std::uint32_t> corners(soup.cornerVertices.data() + soup.faceStarts[f], n);
  for (const auto v : corners)
    if (v >= soup.vertexCount()) return true;
  if (n == 3) {
    if (corners[0] == corners[1] || corners[1] == corners[2] || corners[0] == corners[2])
      return true;
  } else {
    std::vector<std::uint32_t> sorted(corners.begin(), corners.end());
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return true;
  }
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double longest = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = soup.positions[corners[i]];
    const Eigen::Vector3d& q = soup.positions[corners[(i + 1) % n]];
    normal += p.cross(q);
    longest = std::max(longest, (q - p).squaredNorm());
  }
  return !(normal.norm() > 1e-12 * longest);
}

// Faces whose sorted vertex lists equal an earlier face's: faces are grouped by a hash of their
// sorted corners, then compared within equal hashes.
std::size_t countDuplicateFaces(const PolygonSoup& soup) {
  std::vector<std::uint32_t> sortedCorners = soup.cornerVertices;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> hashed(soup.faceCount());
  for (std::uint32_t f = 0; f < soup.faceCount(); ++f) {
    const auto first = sortedCorners.begin() + soup.faceStarts[f];
    const auto last = sortedCorners.begin() + soup.faceStarts[f + 1];
    std::sort(first, last);
    std::uint64_t hash = 14695981039346656037ull;
    for (auto it = first; it != last; ++it) hash = (hash ^ *it) * 1099511628211ull;
    hashed[f] = {hash, f};
  }
  std::sort(hashed.begin(), hashed.end());
  const auto face = [&](std::uint32_t f) {
    return std::span<const std::uint32_t>(sortedCorners.data() + soup.faceStarts[f],
                                          soup.faceSize(f));
  };
  std::size_t duplicates = 0;
  for (std::size_t i = 0; i < hashed.size();) {
    std::size_t j = i + 1;
    while (j < hashed.size() && hashed[j].first == hashed[i].first) ++j;
    // Within a run of equal hashes, order the faces and count those equal to their predecessor.
    std::sort(hashed.begin() + static_cast<std::ptrdiff_t>(i),
              hashed.begin() + static_cast<std::ptrdiff_t>(j), [&](const auto& a, const auto& b) {
                const auto fa = face(a.second), fb = face(b.second);
                return std::lexicographical_compare(fa.begin(), fa.end(), fb.begin(), fb.end());
              });
    for (std::size_t a = i + 1; a < j; ++a) {
      const auto fa = face(hashed[a - 1].second), fb = face(hashed[a].second);
      duplicates += std::equal(fa.begin(), fa.end(), fb.begin(), fb.end());
    }
    i = j;
  }
  return duplicates;
}

// Finite vertices at exactly the position of another vertex (all but the first of each group).
std::size_t countDuplicateVertices(const std::vector<Eigen::Vector3d>& positions) {
  std::vector<std::array<double, 3>> keys;
  keys.reserve(positions.size());
  for (const auto& p : positions)
    if (p.allFinite()) keys.push_back({p.x(), p.y(), p.z()});
  std::sort(keys.begin(), keys.end());
  std::size_t duplicates = 0;
  for (std::size_t i = 1; i < keys.size(); ++i) duplicates += keys[i] == keys[i - 1];
  return duplicates;
}

}  // namespace

MeshStatistics measureMesh(const PolygonSoup& soup) {
  detail::checkSoupStructure(soup, /*checkIndices=*/false);
  MeshStatistics stats;
  stats.vertices = soup.vertexCount();
  stats.faces = soup.faceCount();
  std::vector<bool> referenced(soup.vertexCount(), false);
  for (std::size_t f = 0; f < soup.faceCount(); ++f) {
    const std::size_t n = soup.faceSize(f);
    if (n > 3) ++stats.nonTriangleFaces;
    stats.triangles += n >= 3 ? n - 2 : 1;
    if (isDegenerateFace(soup, f)) ++stats.degenerateFaces;
    for (std::size_t c = soup.faceStarts[f]; c < soup.faceStarts[f + 1]; ++c)
      if (soup.cornerVertices[c] < soup.vertexCount()) referenced[soup.cornerVertices[c]] = true;
  }
  for (std::size_t v = 0; v < soup.vertexCount(); ++v) {
    if (!referenced[v]) ++stats.unreferencedVertices;
    if (!soup.positions[v].allFinite()) ++stats.nonFiniteCoordinates;
  }
  stats.duplicateFaces = countDuplicateFaces(soup);
  stats.duplicateVertices = countDuplicateVertices(soup.positions);

  // Topology on the fan-triangulated faces (triangles with a repeated vertex left out).
  const std::vector<Triangle> tris = detail::fanTriangulate(soup);
  const EdgeTable edges = detail::buildEdgeTable(tris);

  UnionFind components(soup.vertexCount());
  for (const auto& t : tris) {
    components.unite(t[0], t[1]);
    components.unite(t[1], t[2]);
  }
  // Fans around vertices are joined across every edge, whatever its valence: a vertex is
  // non-manifold when its triangles still form several fans (two cones touching at a tip).
  std::vector<std::array<std::uint32_t, 2>> allPairs;
  std::vector<bool> onNonManifoldEdge(soup.vertexCount(), false);
  UnionFind boundary(soup.vertexCount());
  std::vector<bool> onBoundary(soup.vertexCount(), false);
  for (std::size_t e = 0; e < edges.edgeCount(); ++e) {
    const std::uint32_t* hs = edges.halfedges.data() + edges.edgeStarts[e];
    const std::size_t k = edges.valence(e);
    for (std::size_t i = 1; i < k; ++i) allPairs.push_back({hs[0], hs[i]});
    const std::uint32_t a = detail::halfedgeTail(tris, hs[0]);
    const std::uint32_t b = detail::halfedgeHead(tris, hs[0]);
    if (k > 2) {
      ++stats.nonManifoldEdges;
      onNonManifoldEdge[a] = onNonManifoldEdge[b] = true;
    } else if (k == 2 && detail::halfedgeTail(tris, hs[1]) == a) {
      ++stats.inconsistentlyOrientedEdges;
    } else if (k == 1) {
      boundary.unite(a, b);
      onBoundary[a] = onBoundary[b] = true;
    }
  }
  UnionFind fans = detail::cornerFans(tris, allPairs);
  std::vector<std::uint32_t> firstFan(soup.vertexCount(), UINT32_MAX);
  std::vector<bool> nonManifoldVertex(soup.vertexCount(), false);
  for (std::uint32_t c = 0; c < 3 * tris.size(); ++c) {
    const std::uint32_t v = tris[c / 3][c % 3];
    const std::uint32_t fan = fans.find(c);
    if (firstFan[v] == UINT32_MAX)
      firstFan[v] = fan;
    else if (firstFan[v] != fan)
      nonManifoldVertex[v] = true;
  }
  for (std::size_t v = 0; v < soup.vertexCount(); ++v)
    stats.nonManifoldVertices += nonManifoldVertex[v];

  // Orientation: a patch where propagation conflicts makes its component non-orientable.
  std::vector<bool> componentNonOrientable(soup.vertexCount(), false);
  const detail::Orientation orientation = detail::propagateOrientation(tris, edges);
  for (const auto t : orientation.conflict)
    if (t != UINT32_MAX) componentNonOrientable[components.find(tris[t][0])] = true;

  // Per-component counts. Component ids are the union-find roots (lowest vertex index).
  std::vector<std::uint32_t> componentIndex(soup.vertexCount(), UINT32_MAX);
  std::vector<ComponentTopology>& comps = stats.componentTopology;
  const auto componentOf = [&](std::uint32_t v) -> ComponentTopology& {
    const std::uint32_t root = components.find(v);
    if (componentIndex[root] == UINT32_MAX) {
      componentIndex[root] = static_cast<std::uint32_t>(comps.size());
      comps.emplace_back();
      comps.back().orientable = !componentNonOrientable[root];
    }
    return comps[componentIndex[root]];
  };
  for (const auto& t : tris) ++componentOf(t[0]).faces;
  for (std::size_t e = 0; e < edges.edgeCount(); ++e) {
    const std::uint32_t a = detail::halfedgeTail(tris, edges.halfedges[edges.edgeStarts[e]]);
    ComponentTopology& comp = componentOf(a);
    ++comp.edges;
    if (edges.valence(e) > 2) comp.manifold = false;
  }
  std::vector<bool> boundaryRootSeen(soup.vertexCount(), false);
  for (std::uint32_t v = 0; v < soup.vertexCount(); ++v) {
    if (firstFan[v] == UINT32_MAX) continue;  // unreferenced or only in skipped faces
    ComponentTopology& comp = componentOf(v);
    ++comp.vertices;
    if (nonManifoldVertex[v]) comp.manifold = false;
    if (onBoundary[v] && !boundaryRootSeen[boundary.find(v)]) {
      boundaryRootSeen[boundary.find(v)] = true;
      ++comp.boundaryLoops;
    }
  }
  for (auto& comp : comps) {
    comp.eulerCharacteristic = static_cast<long long>(comp.vertices) -
                               static_cast<long long>(comp.edges) +
                               static_cast<long long>(comp.faces);
    const long long twiceGenus =
        2 - comp.eulerCharacteristic - static_cast<long long>(comp.boundaryLoops);
    comp.genus = comp.manifold && comp.orientable && twiceGenus >= 0 && twiceGenus % 2 == 0
                     ? static_cast<int>(twiceGenus / 2)
                     : -1;
    stats.boundaryLoops += comp.boundaryLoops;
    stats.eulerCharacteristic += comp.eulerCharacteristic;
    stats.nonOrientableComponents += !comp.orientable;
  }
  std::stable_sort(comps.begin(), comps.end(),
                   [](const auto& a, const auto& b) { return a.faces > b.faces; });
  stats.components = comps.size();
  return stats;
}

MeshReport validateMesh(const PolygonSoup& soup) {
  MeshReport report;
  report.input = measureMesh(soup);
  return report;
}

}  // namespace hexcover
