#include "core/field/clustering.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <queue>
#include <set>
#include <tuple>
#include <utility>

#include "core/common/concurrency.h"
#include "core/common/median.h"

namespace hexcover::field {
namespace {

using QueueEntry = std::pair<double, int>;  // (distance, vertex): ties by vertex index
using MinQueue = std::priority_queue<QueueEntry, std::vector<QueueEntry>, std::greater<>>;

/// Single-source Dijkstra stopped at a radius, reusing its arrays between runs.
class GeodesicBall {
 public:
  explicit GeodesicBall(const EdgeGraph& graph)
      : graph_(graph),
        distance_(graph.vertices(), std::numeric_limits<double>::infinity()),
        previous_(graph.vertices(), -1) {}

  /// Vertices closer than `radius` to `source`, in the order they were settled; with `stop` ≥ 0,
  /// only up to vertex `stop` (whose distance and path are then final).
  const std::vector<int>& grow(int source, double radius, int stop = -1) {
    for (const int v : touched_) {
      distance_[v] = std::numeric_limits<double>::infinity();
      previous_[v] = -1;
    }
    touched_.clear();
    settled_.clear();
    heap_.clear();  // a binary min-heap (std::greater) that keeps its memory between runs
    const auto push = [this](double d, int v) {
      heap_.emplace_back(d, v);
      std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
    };
    distance_[source] = 0.0;
    touched_.push_back(source);
    push(0.0, source);
    while (!heap_.empty()) {
      std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
      const auto [d, v] = heap_.back();
      heap_.pop_back();
      if (d > distance_[v]) continue;
      settled_.push_back(v);
      if (v == stop) break;
      for (int k = graph_.offset[v]; k < graph_.offset[v + 1]; ++k) {
        const int w = graph_.target[k];
        const double dw = d + graph_.length[k];
        if (dw < distance_[w] && dw < radius) {
          if (distance_[w] == std::numeric_limits<double>::infinity()) touched_.push_back(w);
          distance_[w] = dw;
          previous_[w] = v;
          push(dw, w);
        }
      }
    }
    return settled_;
  }

  double distance(int v) const { return distance_[v]; }

  /// The path from the last source to v (both included), v reached.
  std::vector<int> pathTo(int v) const {
    std::vector<int> path;
    for (int w = v; w >= 0; w = previous_[w]) path.push_back(w);
    std::reverse(path.begin(), path.end());
    return path;
  }

 private:
  const EdgeGraph& graph_;
  std::vector<double> distance_;
  std::vector<int> previous_;
  std::vector<int> settled_, touched_;
  std::vector<QueueEntry> heap_;
};

}  // namespace

EdgeGraph::EdgeGraph(const TriMesh& mesh) : offset(mesh.n_vertices() + 1, 0) {
  target.reserve(mesh.n_halfedges());
  length.reserve(mesh.n_halfedges());
  for (const auto vh : mesh.vertices()) {
    for (const auto heh : mesh.voh_range(vh)) {
      target.push_back(heh.to().idx());
      length.push_back(mesh.calc_edge_length(heh));
    }
    offset[vh.idx() + 1] = static_cast<int>(target.size());
  }
}

std::vector<double> edgeGraphDistances(const EdgeGraph& graph, const std::vector<int>& sources,
                                       double limit) {
  std::vector<double> distance(graph.vertices(), std::numeric_limits<double>::infinity());
  MinQueue queue;
  for (const int s : sources) {
    distance[s] = 0.0;
    queue.emplace(0.0, s);
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    for (int k = graph.offset[v]; k < graph.offset[v + 1]; ++k) {
      const int w = graph.target[k];
      const double dw = d + graph.length[k];
      if (dw < distance[w] && dw < limit) {
        distance[w] = dw;
        queue.emplace(dw, w);
      }
    }
  }
  return distance;
}

ClusteringResult clusterSingularities(const TriMesh& mesh, const EdgeGraph& graph,
                                      const std::vector<ClusterNode>& initial,
                                      const std::vector<double>& gaussDensity, double dSing,
                                      int maxIndex, const std::vector<bool>& settled, int threads) {
  GeodesicBall ball(graph);
  std::vector<ClusterNode> nodes = initial;
  std::vector<bool> alive(nodes.size(), true);
  std::vector<std::vector<int>> nodesAt(mesh.n_vertices());
  for (std::size_t i = 0; i < nodes.size(); ++i)
    nodesAt[nodes[i].vertex].push_back(static_cast<int>(i));

  // Candidate edges of the singularity graph shorter than d_sing: (length, a, b) with a < b.
  using Candidate = std::tuple<double, int, int>;
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> candidates;
  const auto neighbours = [&](GeodesicBall& from, int node, auto&& add) {
    for (const int v : from.grow(nodes[node].vertex, dSing)) {
      if (!(from.distance(v) < dSing)) continue;
      for (const int other : nodesAt[v])
        if (other != node && alive[other])
          add(Candidate{from.distance(v), std::min(node, other), std::max(node, other)});
    }
  };
  const auto addNeighbours = [&](int node) {
    neighbours(ball, node, [&](const Candidate& c) { candidates.push(c); });
  };
  // The first searches (from every node not settled) are independent: on up to `threads`
  // threads with a ball each. The queue orders candidates totally, whatever the order of pushes.
  std::vector<int> sources;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (settled.empty() || !settled[i]) sources.push_back(static_cast<int>(i));
  const std::size_t workers = std::clamp<std::size_t>(static_cast<std::size_t>(threads), 1,
                                                      std::max<std::size_t>(1, sources.size()));
  std::vector<std::vector<Candidate>> found(workers);
  parallelFor(
      workers, static_cast<int>(workers),
      [&](std::size_t w) {
        GeodesicBall own(graph);
        for (std::size_t k = sources.size() * w / workers; k < sources.size() * (w + 1) / workers;
             ++k)
          neighbours(own, sources[k], [&](const Candidate& c) { found[w].push_back(c); });
      },
      1);
  for (const auto& list : found)
    for (const Candidate& c : list) candidates.push(c);

  ClusteringResult result;
  const auto remove = [&](int node) {
    alive[node] = false;
    auto& at = nodesAt[nodes[node].vertex];
    at.erase(std::find(at.begin(), at.end(), node));
  };
  std::set<std::pair<int, int>> forbidden;  // each pair is found from both of its nodes
  while (!candidates.empty()) {
    const auto [distance, a, b] = candidates.top();
    candidates.pop();
    if (!alive[a] || !alive[b]) continue;
    if (!mayMerge(nodes[a], nodes[b], maxIndex)) {
      forbidden.emplace(a, b);
      continue;
    }
    const int sum = nodes[a].index + nodes[b].index;
    const int va = nodes[a].vertex, vb = nodes[b].vertex;
    result.collapsedVertices.push_back(va);
    result.collapsedVertices.push_back(vb);
    ++result.collapses;
    remove(a);
    remove(b);
    if (sum == 0) continue;  // cancellation

    // The merged node: on the shortest path a → b at fraction |K_b| / (|K_a| + |K_b|).
    ball.grow(va, dSing, vb);  // reaches vb: the pair is closer than d_sing
    const std::vector<int> path = ball.pathTo(vb);
    const double ka = std::abs(gaussDensity[va]), kb = std::abs(gaussDensity[vb]);
    const double fraction = ka + kb > 0.0 ? kb / (ka + kb) : 0.5;
    const double target = fraction * ball.distance(vb);
    int best = -1;
    double bestGap = std::numeric_limits<double>::infinity();
    for (const int v : path) {
      if (mesh.is_boundary(mesh.vertex_handle(v))) continue;
      const double gap = std::abs(ball.distance(v) - target);
      if (gap < bestGap) {
        bestGap = gap;
        best = v;
      }
    }
    if (best < 0) best = ka >= kb ? va : vb;
    const int merged = static_cast<int>(nodes.size());
    nodes.push_back({best, sum});
    alive.push_back(true);
    nodesAt[best].push_back(merged);
    addNeighbours(merged);
  }

  for (const auto& [a, b] : forbidden)
    if (alive[a] && alive[b]) ++result.forbiddenPairs;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (alive[i]) result.nodes.push_back(nodes[i]);
  std::sort(result.nodes.begin(), result.nodes.end(),
            [](const ClusterNode& x, const ClusterNode& y) { return x.vertex < y.vertex; });
  std::sort(result.collapsedVertices.begin(), result.collapsedVertices.end());
  result.collapsedVertices.erase(
      std::unique(result.collapsedVertices.begin(), result.collapsedVertices.end()),
      result.collapsedVertices.end());
  return result;
}

namespace {

/// Like-signed nodes closer than this fraction of d_sing (half a lattice edge at the pipeline's
/// d_sing = 6h) round onto one lattice point: they are one node of their summed index.
constexpr double kCoincidentFraction = 1.0 / 12.0;
/// ... when that index is one that no single vertex of the lattice realizes: two +1/6 make a
/// vertex of valence 4 (the extraction merges their lattice point's copies), three or more do not.
constexpr int kCoincidentMinIndex = 3;
/// ... where the mesh's edges around them are on average shorter than this fraction of its
/// median edge (a graded sphere's dense pole: under a tenth).
constexpr double kCoincidentFinerThan = 0.25;

/// The median length of the mesh's edges (0 without edges).
double medianEdgeLength(const TriMesh& mesh) {
  std::vector<double> lengths;
  lengths.reserve(mesh.n_edges());
  for (const auto e : mesh.edges()) lengths.push_back(mesh.calc_edge_length(e));
  return median(std::move(lengths));
}

/// `nodes` with every group of like-signed nodes that are transitively closer than `radius`
/// (graph distance) and whose summed index reaches `minIndex` in absolute value replaced by one
/// node of that index on the member nearest the others (least Σ squared distances; ties: the
/// lower vertex). A mesh much finer in one place than in another resolves the zeros of the
/// smoothest field there as separate nodes a fraction of an edge apart (six +1/6 at the dense
/// pole of a graded sphere), where a uniform mesh has one node of high order. A group stays
/// apart where the edges around its nodes average at least kCoincidentFinerThan of the mesh's
/// median edge, and when the angle defects within `reach` of its first node carry at least half
/// of its index (N Σ K_v / 2π). The replaced nodes' vertices are appended to `replaced`.
std::vector<ClusterNode> mergeCoincidentNodes(const TriMesh& mesh, GeodesicBall& ball,
                                              const std::vector<ClusterNode>& nodes,
                                              const std::vector<double>& angleDefect, int n,
                                              double radius, double reach, int minIndex,
                                              std::vector<int>& replaced) {
  const auto position = [&](int k) {
    return toEigen(mesh.point(OpenMesh::VertexHandle(nodes[k].vertex)));
  };
  std::vector<int> nodeAt(mesh.n_vertices(), -1);
  for (std::size_t k = 0; k < nodes.size(); ++k) nodeAt[nodes[k].vertex] = static_cast<int>(k);
  std::vector<char> grouped(nodes.size(), 0), mergedAway(nodes.size(), 0);
  std::vector<ClusterNode> result;
  std::optional<double> typicalEdgeLength;  // the median edge, measured when a group needs it
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    if (grouped[k] || nodes[k].index == 0) continue;
    // Breadth-first over like-signed nodes within `radius` of a member.
    std::vector<int> members{static_cast<int>(k)};
    grouped[k] = 1;
    for (std::size_t m = 0; m < members.size(); ++m)
      for (const int w : ball.grow(nodes[members[m]].vertex, radius))
        if (const int j = nodeAt[w]; j >= 0 && !grouped[j] && nodes[j].index != 0 &&
                                     (nodes[j].index > 0) == (nodes[k].index > 0)) {
          grouped[j] = 1;
          members.push_back(j);
        }
    int index = 0;
    for (const int j : members) index += nodes[j].index;
    if (members.size() < 2 || std::abs(index) < minIndex) continue;
    // Only where the mesh is much finer than it typically is: on a mesh about as fine
    // everywhere, nodes this close are features of the surface that a coarse lattice meets
    // (feline at K = V/64: three −1/6 4 input edges apart; merged and split, the parameterization
    // folded and the input came back unchanged).
    double lengthSum = 0.0, edges = 0.0;
    for (const int j : members)
      for (const auto h : mesh.voh_range(OpenMesh::VertexHandle(nodes[j].vertex))) {
        lengthSum += mesh.calc_edge_length(h);
        edges += 1.0;
      }
    if (!typicalEdgeLength) typicalEdgeLength = medianEdgeLength(mesh);
    if (!(lengthSum < kCoincidentFinerThan * *typicalEdgeLength * edges)) continue;
    // Where the Gauss curvature within `reach` carries half of the index or more (the tip of an
    // elongated ellipsoid), the zeros sit where the surface turns: they stay.
    double curvature = 0.0;
    for (const int w : ball.grow(nodes[k].vertex, reach)) curvature += angleDefect[w];
    if (2.0 * std::abs(n * curvature / (2.0 * M_PI)) >= std::abs(index) &&
        (curvature > 0.0) == (index > 0))
      continue;
    // (Σ squared distances to the others, vertex) of each member; the least is the centre.
    std::vector<std::pair<double, int>> spread;
    for (const int a : members) {
      double sum = 0.0;
      for (const int j : members) sum += (position(a) - position(j)).squaredNorm();
      spread.emplace_back(sum, nodes[a].vertex);
    }
    result.push_back({std::min_element(spread.begin(), spread.end())->second, index});
    for (const int j : members) {
      mergedAway[j] = 1;
      replaced.push_back(nodes[j].vertex);
    }
  }
  for (std::size_t k = 0; k < nodes.size(); ++k)
    if (!mergedAway[k]) result.push_back(nodes[k]);
  return result;
}

}  // namespace

ClusteringResult splitHighOrderNodes(const TriMesh& mesh, const EdgeGraph& graph,
                                     const std::vector<ClusterNode>& nodes,
                                     const std::vector<double>& angleDefect,
                                     const std::vector<bool>& blocked, int n, int maxIndex,
                                     double dSing) {
  ClusteringResult result;
  const auto position = [&](int v) { return toEigen(mesh.point(OpenMesh::VertexHandle(v))); };
  GeodesicBall ball(graph);
  const std::vector<ClusterNode> merged =
      mergeCoincidentNodes(mesh, ball, nodes, angleDefect, n, kCoincidentFraction * dSing,
                           0.5 * dSing, kCoincidentMinIndex, result.collapsedVertices);
  std::vector<char> taken(graph.vertices(), 0);
  for (const auto& node : merged) taken[node.vertex] = 1;
  for (const auto& node : merged) {
    if (maxIndex <= 0 || std::abs(node.index) <= maxIndex) {
      result.nodes.push_back(node);
      continue;
    }
    const int v = node.vertex, sign = node.index > 0 ? 1 : -1;
    // The part of I that v's angle defect carries: round(N K_v / 2π) if of I's sign, ≤ |I|; the
    // rest, `count` nodes of index `sign`, goes around v.
    const long carried = std::lround(n * angleDefect[v] / (2.0 * M_PI)) * sign;
    const int keep = sign * static_cast<int>(std::clamp<long>(carried, 0, std::abs(node.index)));
    const int count = std::abs(node.index - keep);
    if (count == 0) {
      result.nodes.push_back(node);
      continue;
    }
    // ρ: half the distance to the nearest obstacle (the ball settles vertices by distance).
    const std::vector<int>& reached = ball.grow(v, dSing);
    double obstacle = dSing;
    for (const int w : reached)
      if (w != v && (blocked[w] || taken[w])) {
        obstacle = ball.distance(w);
        break;
      }
    const double rho = 0.5 * obstacle;
    std::vector<int> ring;
    for (const int w : reached)
      if (!blocked[w] && !taken[w] && std::abs(ball.distance(w) - rho) <= 0.5 * rho)
        ring.push_back(w);
    if (static_cast<int>(ring.size()) < count) {
      result.nodes.push_back(node);
      continue;
    }
    // Farthest-point sampling from the ring vertex nearest the radius ρ.
    std::vector<int> picked{*std::min_element(ring.begin(), ring.end(), [&](int a, int b) {
      return std::abs(ball.distance(a) - rho) < std::abs(ball.distance(b) - rho);
    })};
    std::vector<double> gap(ring.size(), std::numeric_limits<double>::infinity());
    while (static_cast<int>(picked.size()) < count) {
      std::size_t farthest = 0;
      for (std::size_t k = 0; k < ring.size(); ++k) {
        gap[k] = std::min(gap[k], (position(ring[k]) - position(picked.back())).norm());
        if (gap[k] > gap[farthest]) farthest = k;
      }
      picked.push_back(ring[farthest]);
    }
    if (keep != 0) result.nodes.push_back({v, keep});
    result.collapsedVertices.push_back(v);
    for (const int w : picked) {
      result.nodes.push_back({w, sign});
      result.collapsedVertices.push_back(w);
      taken[w] = 1;
    }
    ++result.collapses;
  }
  std::sort(result.nodes.begin(), result.nodes.end(),
            [](const ClusterNode& a, const ClusterNode& b) { return a.vertex < b.vertex; });
  std::sort(result.collapsedVertices.begin(), result.collapsedVertices.end());
  return result;
}

}  // namespace hexcover::field
