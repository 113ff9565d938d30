#include "core/mesh/soup_connectivity.h"

#include <algorithm>
#include <functional>
#include <string>
#include <utility>

#include "core/common/error.h"

namespace hexcover::detail {

void checkSoupStructure(const PolygonSoup& soup, bool checkIndices) {
  const auto& starts = soup.faceStarts;
  if (starts.empty() || starts.front() != 0 || starts.back() != soup.cornerVertices.size() ||
      std::adjacent_find(starts.begin(), starts.end(), std::greater<>()) != starts.end())
    throw Error(ErrorCode::InvalidMesh,
                "malformed polygon soup: faceStarts must rise from 0 to the corner count");
  if (!soup.cornerTexcoords.empty() && soup.cornerTexcoords.size() != soup.cornerVertices.size())
    throw Error(ErrorCode::InvalidMesh,
                "malformed polygon soup: cornerTexcoords must be empty or one per corner");
  if (!checkIndices) return;
  for (std::size_t f = 0; f < soup.faceCount(); ++f)
    for (std::size_t c = starts[f]; c < starts[f + 1]; ++c)
      if (soup.cornerVertices[c] >= soup.vertexCount())
        throw Error(ErrorCode::InvalidMesh, "face " + std::to_string(f) + " refers to vertex " +
                                                std::to_string(soup.cornerVertices[c]) +
                                                ", but the mesh has only " +
                                                std::to_string(soup.vertexCount()) + " vertices");
}

EdgeTable buildEdgeTable(const std::vector<Triangle>& triangles) {
  // Bucket the half-edges by their lower vertex (counting sort), then order each small bucket by
  // (upper vertex, half-edge): O(#half-edges) instead of a global sort.
  const std::size_t halfedgeCount = 3 * triangles.size();
  std::uint32_t vertexCount = 0;
  for (const auto& t : triangles)
    vertexCount = std::max({vertexCount, t[0] + 1, t[1] + 1, t[2] + 1});
  std::vector<std::uint32_t> bucketStart(vertexCount + 1, 0);
  const auto lower = [&](std::uint32_t h) {
    return std::min(halfedgeTail(triangles, h), halfedgeHead(triangles, h));
  };
  const auto upper = [&](std::uint32_t h) {
    return std::max(halfedgeTail(triangles, h), halfedgeHead(triangles, h));
  };
  for (std::uint32_t h = 0; h < halfedgeCount; ++h) ++bucketStart[lower(h) + 1];
  std::partial_sum(bucketStart.begin(), bucketStart.end(), bucketStart.begin());
  EdgeTable table;
  table.halfedges.resize(halfedgeCount);
  {
    std::vector<std::uint32_t> fill(bucketStart.begin(), bucketStart.end() - 1);
    for (std::uint32_t h = 0; h < halfedgeCount; ++h) table.halfedges[fill[lower(h)]++] = h;
  }
  table.edgeStarts.reserve(halfedgeCount / 2 + 2);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> bucket;
  for (std::uint32_t v = 0; v < vertexCount; ++v) {
    const auto first = table.halfedges.begin() + bucketStart[v];
    const auto last = table.halfedges.begin() + bucketStart[v + 1];
    bucket.clear();
    for (auto it = first; it != last; ++it) bucket.emplace_back(upper(*it), *it);
    std::sort(bucket.begin(), bucket.end());
    for (std::size_t i = 0; i < bucket.size(); ++i) {
      if (i == 0 || bucket[i].first != bucket[i - 1].first)
        table.edgeStarts.push_back(static_cast<std::uint32_t>(bucketStart[v] + i));
      first[static_cast<std::ptrdiff_t>(i)] = bucket[i].second;
    }
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
      if (v == tail)
        fans.unite(h, 3 * tg + i);
      else if (v == head)
        fans.unite(3 * (h / 3) + (h % 3 + 1) % 3, 3 * tg + i);
    }
  }
  return fans;
}

Orientation propagateOrientation(const std::vector<Triangle>& triangles, const EdgeTable& edges) {
  // The opposite half-edge across every two-triangle edge (UINT32_MAX elsewhere).
  std::vector<std::uint32_t> opposite(3 * triangles.size(), UINT32_MAX);
  for (std::size_t e = 0; e < edges.edgeCount(); ++e) {
    if (edges.valence(e) != 2) continue;
    const std::uint32_t* hs = edges.halfedges.data() + edges.edgeStarts[e];
    opposite[hs[0]] = hs[1];
    opposite[hs[1]] = hs[0];
  }
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
      for (std::uint32_t h = 3 * t; h < 3 * t + 3; ++h) {
        const std::uint32_t g = opposite[h];
        if (g == UINT32_MAX) continue;
        // Consistent neighbours traverse the shared edge in opposite directions.
        const bool sameDirection = halfedgeTail(triangles, h) == halfedgeTail(triangles, g);
        const auto want =
            static_cast<std::int8_t>(sameDirection ? -result.sign[t] : result.sign[t]);
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
