#pragma once
// Internal to core/field: singularity clustering (paper section 3.3) and the geodesic distances
// it needs. Distances are shortest paths along mesh edges (Dijkstra), an upper bound of the
// geodesic distance that is within a few percent of it on well-shaped meshes.

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <vector>

#include "core/mesh/mesh.h"

namespace hexcover::field {

/// The mesh's vertex graph in compressed rows, built once per run: the neighbours of v (in the
/// order of its outgoing halfedges) are target[offset[v] .. offset[v + 1]), at distance
/// length[...].
struct EdgeGraph {
  std::vector<int> offset, target;
  std::vector<double> length;

  explicit EdgeGraph(const TriMesh& mesh);
  int vertices() const { return static_cast<int>(offset.size()) - 1; }
};

/// Multi-source Dijkstra along edges from `sources` (vertex indices), stopped at `limit`:
/// #V distances, +∞ for vertices at `limit` or farther.
std::vector<double> edgeGraphDistances(const EdgeGraph& graph, const std::vector<int>& sources,
                                       double limit = std::numeric_limits<double>::infinity());

struct ClusterNode {
  int vertex = -1;
  int index = 0;  ///< I (index I/N)
};

/// The merge rule of clusterSingularities: the merged index |I_a + I_b| may exceed maxIndex only
/// when it lowers the larger |I| of the pair (a +4/N needle absorbing a −1/N); maxIndex 0 allows
/// every merge.
inline bool mayMerge(const ClusterNode& a, const ClusterNode& b, int maxIndex) {
  return maxIndex == 0 ||
         std::abs(a.index + b.index) <= std::max({maxIndex, std::abs(a.index), std::abs(b.index)});
}

struct ClusteringResult {
  std::vector<ClusterNode> nodes;  ///< the remaining singularity constraints, I ≠ 0, by vertex
  std::vector<int> collapsedVertices;  ///< V_collapse: both ends of every collapsed edge, sorted
  int collapses = 0;                   ///< merges and cancellations performed
  int forbiddenPairs = 0;  ///< remaining pairs closer than d_sing whose merge the rule forbids
};

/// Collapses the singularity graph (section 3.3). The graph is the dual of the geodesic Voronoi
/// diagram of the singularities; only its edges shorter than d_sing are ever collapsed, and
/// those are found as the pairs within distance d_sing by Dijkstra from every node stopped at
/// d_sing (which also includes close pairs that are not Voronoi neighbours, so that at the end no
/// two nodes are closer than d_sing). Edges are collapsed by increasing length (ties: lower node
/// ids first): the merged node has index I_a + I_b and sits on the shortest path from a to b at
/// arc-length fraction |K_b| / (|K_a| + |K_b|) (½ when both are 0), i.e. closer to the larger
/// |K|; a zero sum cancels both. Collapses that mayMerge refuses are skipped. Nodes are
/// never placed on boundary vertices (the nearest interior vertex of the path is used).
/// `nodes` must be interior vertices; `gaussDensity` is #V |K|/area or any per-vertex weight.
/// `settled` (empty or one flag per node): nodes known to have no collapsible partner among the
/// other settled nodes (they were left apart by an earlier clustering); the search for close
/// pairs then starts only from the others. `threads`: the first searches for close pairs run on up
/// to this many threads (the result is the same for any count).
ClusteringResult clusterSingularities(const TriMesh& mesh, const EdgeGraph& graph,
                                      const std::vector<ClusterNode>& nodes,
                                      const std::vector<double>& gaussDensity, double dSing,
                                      int maxIndex, const std::vector<bool>& settled = {},
                                      int threads = 1);

/// Splits the nodes whose index the lattice cannot take (paper section 3.3 read backwards: a
/// singularity of index I/N is I first-order ones merged). The smoothest field concentrates
/// symmetric curvature in one zero of high order: on a flat disk whose rim it follows (the cap of
/// a cylinder, a washer) a single +N/N at the centre, which no triangle fan can realize. A node
/// with |I| > maxIndex (maxIndex ≥ 1) keeps the part that its vertex's angle defect K_v carries,
/// I_keep = round(N K_v / 2π) when its sign is I's, at most |I| (a cone apex of 199° keeps 3/6, a
/// cube corner 2/6), and the rest becomes |I − I_keep| nodes of index ±1 on vertices at graph
/// distance ρ ± ρ/2 from it, spread by farthest-point sampling, where ρ is half the distance to
/// the nearest obstacle (a vertex of `blocked`, e.g. boundary and crease vertices, or another
/// node) and at most dSing / 2. A node whose ring has too few free vertices stays whole (the
/// remesh pipeline then refines the input and computes the field again). Like-signed nodes closer
/// than dSing / 12 whose index sum is 3 or more count as one node first where the mesh's edges
/// around them average under a quarter of its median edge (a mesh much finer in one place
/// resolves a high-order zero there as first-order ones a fraction of an edge apart; on a mesh
/// about as fine everywhere, nodes that close are the surface's features met by a coarse
/// lattice), unless the angle defects within dSing / 2 carry half of that sum (an ellipsoid's
/// tip).
/// Returns every node (sorted by vertex) and, in collapsedVertices, the split nodes' vertices and
/// their rings (the region to re-solve); collapses counts the nodes split.
ClusteringResult splitHighOrderNodes(const TriMesh& mesh, const EdgeGraph& graph,
                                     const std::vector<ClusterNode>& nodes,
                                     const std::vector<double>& angleDefect,
                                     const std::vector<bool>& blocked, int n, int maxIndex,
                                     double dSing);

}  // namespace hexcover::field
