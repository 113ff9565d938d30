#include "core/param/cut_graph.h"

#include <deque>
#include <string>

#include "core/common/error.h"
#include "core/param/lattice.h"

namespace hexcover {
namespace {

int mod(int a, int n) { return ((a % n) + n) % n; }

}  // namespace

CutGraph computeCutGraph(const TriMesh& mesh, const RosyField& field) {
  const int n = field.n;
  const int nF = static_cast<int>(mesh.n_faces());
  const int nE = static_cast<int>(mesh.n_edges());
  const int nV = static_cast<int>(mesh.n_vertices());
  if (!isLatticeOrder(n))
    throw Error(ErrorCode::InvalidOption,
                "the parameterization needs a 4- or 6-RoSy field, got N = " + std::to_string(n));
  if (static_cast<int>(field.faceDirection.size()) != nF ||
      static_cast<int>(field.edgeMatching.size()) != nE)
    throw Error(ErrorCode::InvalidOption,
                "the field does not belong to this mesh (" + std::to_string(field.faceDirection.size()) +
                    " face directions for " + std::to_string(nF) + " faces)");

  CutGraph cut;
  cut.n = n;
  cut.faceRotation.assign(nF, 0);
  cut.combedMatching.assign(nE, 0);
  cut.cutEdge.assign(nE, false);
  cut.vertexHolonomy.assign(nV, 0);
  cut.faceComponent.assign(nF, -1);

  // Breadth-first dual spanning tree per component; combing k_f1 = k_f0 + r_e across tree edges.
  std::vector<bool> treeEdge(nE, false);
  std::deque<int> queue;
  for (int root = 0; root < nF; ++root) {
    if (cut.faceComponent[root] >= 0) continue;
    const int component = cut.componentCount++;
    cut.faceComponent[root] = component;
    queue.push_back(root);
    while (!queue.empty()) {
      const auto fh = mesh.face_handle(queue.front());
      queue.pop_front();
      for (const auto h : mesh.fh_range(fh)) {
        const auto opposite = mesh.opposite_halfedge_handle(h);
        if (mesh.is_boundary(opposite)) continue;
        const int g = mesh.face_handle(opposite).idx();
        if (cut.faceComponent[g] >= 0) continue;
        const auto eh = mesh.edge_handle(h);
        const int r = field.edgeMatching[eh.idx()];
        const bool fromF0 = mesh.halfedge_handle(eh, 0) == h;
        cut.faceRotation[g] = mod(cut.faceRotation[fh.idx()] + (fromF0 ? r : -r), n);
        cut.faceComponent[g] = component;
        treeEdge[eh.idx()] = true;
        queue.push_back(g);
      }
    }
  }

  std::vector<int> cutDegree(nV, 0);
  for (const auto eh : mesh.edges()) {
    if (mesh.is_boundary(eh)) continue;
    const int f0 = mesh.face_handle(mesh.halfedge_handle(eh, 0)).idx();
    const int f1 = mesh.face_handle(mesh.halfedge_handle(eh, 1)).idx();
    const int e = eh.idx();
    cut.combedMatching[e] =
        mod(field.edgeMatching[e] + cut.faceRotation[f0] - cut.faceRotation[f1], n);
    if (treeEdge[e]) continue;
    cut.cutEdge[e] = true;
    ++cutDegree[mesh.from_vertex_handle(mesh.halfedge_handle(eh, 0)).idx()];
    ++cutDegree[mesh.to_vertex_handle(mesh.halfedge_handle(eh, 0)).idx()];
  }

  // Holonomy I mod N: Σ ±r_e over the counter-clockwise loop of faces around the vertex, +r_e when
  // the loop crosses e from f0 to f1, i.e. when v = to_vertex(halfedge(e, 0)).
  for (const auto vh : mesh.vertices()) {
    if (mesh.is_boundary(vh) || mesh.is_isolated(vh)) continue;
    int sum = 0;
    for (const auto h : mesh.vih_range(vh)) {
      const auto eh = mesh.edge_handle(h);
      sum += mesh.halfedge_handle(eh, 0) == h ? field.edgeMatching[eh.idx()]
                                              : -field.edgeMatching[eh.idx()];
    }
    cut.vertexHolonomy[vh.idx()] = mod(sum, n);
  }

  // Prune dangling branches: a cut edge whose tip is an interior vertex of trivial holonomy.
  const auto prunable = [&](int v) {
    const auto vh = mesh.vertex_handle(v);
    return cutDegree[v] == 1 && !mesh.is_boundary(vh) && cut.vertexHolonomy[v] == 0;
  };
  std::deque<int> tips;
  for (int v = 0; v < nV; ++v)
    if (prunable(v)) tips.push_back(v);
  while (!tips.empty()) {
    const int v = tips.front();
    tips.pop_front();
    if (!prunable(v)) continue;
    for (const auto h : mesh.voh_range(mesh.vertex_handle(v))) {
      const int e = mesh.edge_handle(h).idx();
      if (!cut.cutEdge[e]) continue;
      cut.cutEdge[e] = false;
      --cutDegree[v];
      const int other = mesh.to_vertex_handle(h).idx();
      --cutDegree[other];
      if (prunable(other)) tips.push_back(other);
      break;
    }
  }

  for (const auto eh : mesh.edges()) {
    if (!cut.cutEdge[eh.idx()]) continue;
    ++cut.cutEdgeCount;
    cut.cutLength += mesh.calc_edge_length(eh);
  }
  return cut;
}

}  // namespace hexcover
