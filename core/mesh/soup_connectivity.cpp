#include "core/mesh/soup_connectivity.h"

#include <algorithm>
#include <utility>

namespace hexcover::detail {

EdgeTable buildEdgeTable(const std::vector<Triangle>& triangles) {
  const std::size_t halfedgeCount = 3 * triangles.size();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(halfedgeCount);
  for (std::uint32_t h = 0; h < halfedgeCount; ++h) {
    const std::uint64_t a = halfedgeTail(triangles, h);
    const std::uint64_t b = halfedgeHead(triangles, h);
    keyed[h] = {std::min(a, b) << 32 | std::max(a, b), h};
  }
  std::sort(keyed.begin(), keyed.end());
  EdgeTable table;
  table.halfedges.resize(halfedgeCount);
  table.edgeStarts.clear();
  for (std::size_t i = 0; i < halfedgeCount; ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first)
      table.edgeStarts.push_back(static_cast<std::uint32_t>(i));
    table.halfedges[i] = keyed[i].second;
  }
  table.edgeStarts.push_back(static_cast<std::uint32_t>(halfedgeCount));
  return table;
}

std::vector<Triangle> fanTriangulate(const PolygonSoup& soup, std::vector<std::uint32_t>* origin) {
  std::vector<Triangle> triangles;
  triangles.reserve(soup.cornerVertices.size());
  if (origin) origin->clear();
  for (std::size_t f = 0; f < soup.faceCount(); ++f) {
    const std::uint32_t* corners = soup.cornerVertices.data() + soup.faceStarts[f];
    const std::size_t n = soup.faceSize(f);
    if (n < 3) continue;
    bool valid = true;
    for (std::size_t i = 0; i < n && valid; ++i) valid = corners[i] < soup.vertexCount();
    if (!valid) continue;
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const Triangle t{corners[0], corners[i], corners[i + 1]};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      triangles.push_back(t);
      if (origin) origin->push_back(static_cast<std::uint32_t>(f));
    }
  }
  return triangles;
}

UnionFind cornerFans(const std::vector<Triangle>& triangles,
                     const std::vector<std::array<std::uint32_t, 2>>& joinPairs) {
  UnionFind fans(3 * triangles.size());
  for (const auto& [h, g] : joinPairs) {
    // Half-edge h runs tail→head in its triangle; find the corner of each end vertex in g.
    const std::uint32_t tail = halfedgeTail(triangles, h);
    const std::uint32_t head = halfedgeHead(triangles, h);
    const std::uint32_t tg = g / 3;
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t v = triangles[tg][i];
      if (v == tail) fans.unite(h, 3 * tg + i);
      else if (v == head) fans.unite(3 * (h / 3) + (h % 3 + 1) % 3, 3 * tg + i);
    }
  }
  return fans;
}

Orientation propagateOrientation(const std::vector<Triangle>& triangles, const EdgeTable& edges) {
  // Adjacency of triangles across two-triangle edges, as (half-edge, opposite half-edge) pairs
  // sorted by the first half-edge, hence grouped by triangle.
  std::vector<std::array<std::uint32_t, 2>> pairs;
  pairs.reserve(2 * edges.edgeCount());
  for (std::size_t e = 0; e < edges.edgeCount(); ++e) {
    if (edges.valence(e) != 2) continue;
    const std::uint32_t* hs = edges.halfedges.data() + edges.edgeStarts[e];
    pairs.push_back({hs[0], hs[1]});
    pairs.push_back({hs[1], hs[0]});
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<std::uint32_t> start(triangles.size() + 1, 0);
  for (const auto& p : pairs) ++start[p[0] / 3 + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());

  Orientation result;
  result.sign.assign(triangles.size(), 0);
  result.patch.assign(triangles.size(), UINT32_MAX);
  std::vector<std::uint32_t> queue;
  for (std::uint32_t root = 0; root < triangles.size(); ++root) {
    if (result.sign[root] != 0) continue;
    const auto patch = static_cast<std::uint32_t>(result.conflict.size());
    result.conflict.push_back(UINT32_MAX);
    result.sign[root] = 1;
    result.patch[root] = patch;
    queue.assign(1, root);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t t = queue[q];
      for (std::uint32_t i = start[t]; i < start[t + 1]; ++i) {
        const auto [h, g] = pairs[i];
        // Consistent neighbours traverse the shared edge in opposite directions.
        const bool sameDirection = halfedgeTail(triangles, h) == halfedgeTail(triangles, g);
        const auto want = static_cast<std::int8_t>(sameDirection ? -result.sign[t] : result.sign[t]);
        const std::uint32_t u = g / 3;
        if (result.sign[u] == 0) {
          result.sign[u] = want;
          result.patch[u] = patch;
          queue.push_back(u);
        } else if (result.sign[u] != want && result.conflict[patch] == UINT32_MAX) {
          result.conflict[patch] = u;
        }
      }
    }
  }
  return result;
}

}  // namespace hexcover::detail
