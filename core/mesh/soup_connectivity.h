#pragma once
// Internal to core/mesh: connectivity of a triangle soup given as index triples, shared by
// validation and repair. Not a public header of the stage.

#include <array>
#include <cstdint>
#include <numeric>
#include <vector>

#include "core/mesh/mesh.h"

namespace hexcover::detail {

/// Throws Error(InvalidMesh) unless faceStarts starts at 0, never decreases and ends at the corner
/// count, and cornerTexcoords is empty or has one entry per corner. With `checkIndices`, also
/// unless every corner refers to an existing vertex (naming the first face that does not).
void checkSoupStructure(const PolygonSoup& soup, bool checkIndices);

/// Three vertex indices, counter-clockwise.
using Triangle = std::array<std::uint32_t, 3>;

/// Disjoint sets over 0..n-1 with path halving and union by index (the smaller root wins, so
/// roots are the lowest element of each set and results do not depend on the merge order).
class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a < b)
      parent_[b] = a;
    else if (b < a)
      parent_[a] = b;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

/// The undirected edges of a triangle soup. Half-edge h = 3t + i runs from corner i of triangle t
/// to corner (i+1) mod 3. Half-edges are grouped by undirected edge; within an edge they are in
/// increasing order (so by triangle index).
struct EdgeTable {
  std::vector<std::uint32_t> halfedges;  ///< #half-edges, grouped by edge
  std::vector<std::uint32_t>
      edgeStarts;  ///< #edges+1: edge e owns halfedges[edgeStarts[e], edgeStarts[e+1])

  std::size_t edgeCount() const { return edgeStarts.size() - 1; }
  std::size_t valence(std::size_t e) const { return edgeStarts[e + 1] - edgeStarts[e]; }
};

/// Tail and head vertex of half-edge h.
inline std::uint32_t halfedgeTail(const std::vector<Triangle>& tris, std::uint32_t h) {
  return tris[h / 3][h % 3];
}
inline std::uint32_t halfedgeHead(const std::vector<Triangle>& tris, std::uint32_t h) {
  return tris[h / 3][(h % 3 + 1) % 3];
}

/// Groups the 3·#triangles half-edges by undirected edge. Triangles must not repeat a vertex.
EdgeTable buildEdgeTable(const std::vector<Triangle>& triangles);

/// Fan triangulation (v0, vi, vi+1) of every face of the soup with at least 3 corners whose
/// indices are all in range and distinct; `origin` (if given) receives the face of each triangle.
std::vector<Triangle> fanTriangulate(const PolygonSoup& soup,
                                     std::vector<std::uint32_t>* origin = nullptr);

/// Corner-fan union: corners 3t+i of the triangles joined across every edge whose `join` entry is
/// true, at both end vertices. Each resulting set of corners of one vertex is a fan of triangles.
/// `joinPairs` lists, for each edge to join, the two half-edges whose triangles are glued.
UnionFind cornerFans(const std::vector<Triangle>& triangles,
                     const std::vector<std::array<std::uint32_t, 2>>& joinPairs);

/// Consistent orientation by breadth-first search over edges with exactly two triangles.
/// sign[t] = ±1 says whether triangle t keeps (+1) or reverses (−1) its corner order; each
/// search tree is one edge-connected patch (patch[t]). conflict[p] is a triangle of patch p
/// where two triangles demanded opposite signs (the patch is non-orientable), else UINT32_MAX.
struct Orientation {
  std::vector<std::int8_t> sign;        ///< #triangles
  std::vector<std::uint32_t> patch;     ///< #triangles
  std::vector<std::uint32_t> conflict;  ///< #patches
};
Orientation propagateOrientation(const std::vector<Triangle>& triangles, const EdgeTable& edges);

}  // namespace hexcover::detail
