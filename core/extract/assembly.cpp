#include "core/extract/assembly.h"

#include <algorithm>
#include <iterator>

namespace hexcover::extract_detail {
namespace {

using VH = TriMesh::VertexHandle;

/// A triangle with a repeated corner (no area, no orientation).
bool hasRepeatedCorner(const Triangle& t) { return t[0] == t[1] || t[1] == t[2] || t[2] == t[0]; }

/// Vertices whose triangles do not form a single fan: their link (the edge opposite the vertex
/// in each triangle) is not one path or one cycle.
std::vector<int> nonManifoldVertices(const std::vector<Triangle>& triangles,
                                     std::size_t vertexCount) {
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

}  // namespace

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

std::vector<int> polygonValences(const Assembly& out) {
  std::vector<int> valence = vertexValences(out);
  if (out.squares.empty()) return valence;
  std::vector<Triangle> present;
  present.reserve(out.triangles.size());
  for (const auto& t : out.triangles) present.push_back(canonicalTriangle(t));
  std::sort(present.begin(), present.end());
  const auto has = [&](const Triangle& t) {
    return std::binary_search(present.begin(), present.end(), canonicalTriangle(t));
  };
  for (const auto& [c0, c1, c2, c3] : out.squares)
    if (has({c0, c1, c2}) && has({c0, c2, c3})) --valence[c0], --valence[c2];
  return valence;
}

std::vector<Eigen::Vector3d> vertexNormals(const Assembly& out) {
  std::vector<Eigen::Vector3d> normal(out.positions.size(), Eigen::Vector3d::Zero());
  for (const auto& t : out.triangles) {
    const Eigen::Vector3d n = (out.positions[t[1]] - out.positions[t[0]])
                                  .cross(out.positions[t[2]] - out.positions[t[0]]);
    for (const int v : t) normal[v] += n;
  }
  return normal;
}

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
    if (hasRepeatedCorner(t)) {
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

void removeVertices(Assembly& out, const std::vector<bool>& drop) {
  std::erase_if(out.triangles,
                [&](const Triangle& t) { return drop[t[0]] || drop[t[1]] || drop[t[2]]; });
}

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

long long keepLargestFans(std::vector<Triangle>& triangles, std::size_t vertexCount,
                          const std::vector<bool>& eligible) {
  constexpr int kMaxPasses = 4;
  long long dropped = 0;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    std::vector<int> pinched;
    for (const int v : nonManifoldVertices(triangles, vertexCount))
      if (eligible[v]) pinched.push_back(v);
    if (pinched.empty()) break;
    std::vector<std::vector<int>> around(vertexCount);
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (const int v : triangles[t]) around[v].push_back(static_cast<int>(t));
    std::vector<bool> drop(triangles.size(), false);
    for (const int v : pinched) {
      std::vector<int> fan;  // v's triangles still kept, in index order
      for (const int t : around[v])
        if (!drop[t]) fan.push_back(t);
      // Fans: triangles at v joined through the edges at v they share (union by relabelling).
      std::vector<int> label(fan.size());
      for (std::size_t i = 0; i < fan.size(); ++i) label[i] = static_cast<int>(i);
      const auto sharesEdgeAtV = [&](int a, int b) {
        for (const int x : triangles[a])
          if (x != v &&
              std::find(triangles[b].begin(), triangles[b].end(), x) != triangles[b].end())
            return true;
        return false;
      };
      for (bool changed = true; changed;) {
        changed = false;
        for (std::size_t i = 0; i < fan.size(); ++i)
          for (std::size_t j = i + 1; j < fan.size(); ++j)
            if (label[i] != label[j] && sharesEdgeAtV(fan[i], fan[j])) {
              label[i] = label[j] = std::min(label[i], label[j]);
              changed = true;
            }
      }
      std::vector<int> size(fan.size(), 0);
      for (const int l : label) ++size[l];
      // The largest fan stays; on a tie the one with the lowest triangle index.
      const int keep = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
      for (std::size_t i = 0; i < fan.size(); ++i)
        if (label[i] != keep) drop[fan[i]] = true, ++dropped;
    }
    std::vector<Triangle> kept;
    for (std::size_t t = 0; t < triangles.size(); ++t)
      if (!drop[t]) kept.push_back(triangles[t]);
    triangles = std::move(kept);
  }
  return dropped;
}

long long collapseLatticePointCopies(Assembly& out) {
  // Measured ratios of the copies' edge to the hole's sides: 0.04-0.18 (bunny_7k, camelhead,
  // feline and spot at V/4 and V/16).
  constexpr double kCopyEdgeRatio = 0.3;
  const DirectedEdges edges(out.triangles);
  // u's neighbours, sorted: the ends and apexes of its edges (a vertex on the soup's boundary
  // has one neighbour that only an apex names).
  const auto neighbours = [&](int u) {
    std::vector<int> list;
    for (int e = edges.begin(u); e < edges.end(u); ++e) {
      list.push_back(edges.to(e));
      list.push_back(edges.apex(e));
    }
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    return list;
  };
  // Interior: every edge at u has its reverse (u's triangles close up around it).
  const auto interior = [&](int u) {
    if (out.onBoundary[u] || edges.begin(u) == edges.end(u)) return false;
    for (int e = edges.begin(u); e < edges.end(u); ++e)
      if (edges.find(edges.to(e), u) < 0) return false;
    return true;
  };
  const auto irregularity = [](int a, int b, int c, int d) {
    return std::abs(a - 6) + std::abs(b - 6) + std::abs(c - 6) + std::abs(d - 6);
  };
  std::vector<int> mergedInto(out.positions.size(), -1);
  std::vector<char> touched(out.positions.size(), 0);
  long long collapses = 0;
  for (std::size_t t = 0; t < out.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = out.triangles[t][k], v = out.triangles[t][(k + 1) % 3];
      const int a = out.triangles[t][(k + 2) % 3];
      const int twin = edges.find(v, u);
      if (u > v || twin < 0) continue;
      const int b = edges.apex(twin);
      if (touched[u] || touched[v] || touched[a] || touched[b] || !interior(u) || !interior(v))
        continue;
      const auto& p = out.positions;
      const double others = 0.25 * ((p[u] - p[a]).norm() + (p[v] - p[a]).norm() +
                                    (p[u] - p[b]).norm() + (p[v] - p[b]).norm());
      if (!((p[u] - p[v]).norm() < kCopyEdgeRatio * others)) continue;
      const std::vector<int> nu = neighbours(u), nv = neighbours(v);
      const auto valence = [&](int w) { return static_cast<int>(neighbours(w).size()); };
      const int vu = static_cast<int>(nu.size()), vv = static_cast<int>(nv.size());
      const int va = valence(a), vb = valence(b);
      // (u, v) → one vertex of valence val(u) + val(v) − 4; a and b lose an edge each.
      if (irregularity(vu + vv - 4, 6, va - 1, vb - 1) >= irregularity(vu, vv, va, vb)) continue;
      std::vector<int> shared;
      std::set_intersection(nu.begin(), nu.end(), nv.begin(), nv.end(), std::back_inserter(shared));
      if (shared != std::vector<int>{std::min(a, b), std::max(a, b)}) continue;
      out.positions[u] = 0.5 * (p[u] + p[v]);
      mergedInto[v] = u;
      for (const int w : {u, v, a, b}) touched[w] = 1;
      ++collapses;
    }
  if (collapses == 0) return 0;
  for (auto& t : out.triangles)
    for (int& w : t)
      if (mergedInto[w] >= 0) w = mergedInto[w];
  std::erase_if(out.triangles, hasRepeatedCorner);
  return collapses;
}

void keepComponentsTooSmallForTheLattice(const TriMesh& mesh, const TriMesh& given,
                                         const std::vector<int>& faceComponent, int componentCount,
                                         const ExtractOptions& options, Assembly& out,
                                         ExtractionReport& report) {
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
  std::vector<int> copy(given.n_vertices(), -1);
  for (const auto f : given.faces()) {
    const int c = vertexComponent[f.halfedge().to().idx()];
    if (!keep[c]) continue;
    Triangle copied;
    int k = 0;
    for (const auto v : f.vertices()) {
      if (copy[v.idx()] < 0) copy[v.idx()] = out.addVertex(toEigen(given.point(v)), c);
      copied[k++] = copy[v.idx()];
    }
    out.triangles.push_back(copied);
  }
  for (int c = 0; c < componentCount; ++c) report.componentsKept += keep[c] ? 1 : 0;
  report.keptVertices = std::count_if(copy.begin(), copy.end(), [](int v) { return v >= 0; });
}

TriMesh buildMesh(const Assembly& out, ExtractionReport& report, std::vector<VH>& handle) {
  TriMesh result;
  handle.assign(out.positions.size(), VH());
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
      if (!result.add_face(handle[t[0]], handle[t[1]], handle[t[2]]).is_valid())
        refused.push_back(t);
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
        outputBoundary =
            outputBoundary || out.onBoundary[assemblyVertex[result.from_vertex_handle(g).idx()]];
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
    // The handles follow the vertices' new indices (a deleted vertex's handle becomes invalid).
    std::vector<VH*> handles;
    for (VH& h : handle)
      if (h.is_valid()) handles.push_back(&h);
    std::vector<OpenMesh::HalfedgeHandle*> noHalfedges;
    std::vector<OpenMesh::FaceHandle*> noFaces;
    result.garbage_collection(handles, noHalfedges, noFaces);
    result.release_vertex_status();
    result.release_edge_status();
    result.release_face_status();
  }
  return result;
}

}  // namespace hexcover::extract_detail
