#include "core/mesh/topology.h"

#include <algorithm>
#include <cassert>
#include <numeric>
#include <tuple>

namespace hexcover {
namespace {

/// Union–find over vertex indices with path halving.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

}  // namespace

int MeshTopology::genus() const {
  int total = 0;
  for (const auto& c : perComponent) {
    if (c.genus < 0) return -1;
    total += c.genus;
  }
  return total;
}

bool MeshTopology::sameAs(const MeshTopology& other) const {
  if (components != other.components) return false;
  const auto signature = [](const MeshTopology& t) {
    std::vector<std::tuple<long long, std::size_t, int>> s;
    for (const auto& c : t.perComponent)
      s.emplace_back(c.eulerCharacteristic, c.boundaryLoops, c.genus);
    std::sort(s.begin(), s.end());
    return s;
  };
  return signature(*this) == signature(other);
}

MeshTopology computeTopology(const TriMesh& mesh) {
  MeshTopology topology;
  DisjointSets sets(mesh.n_vertices());
  std::vector<char> referenced(mesh.n_vertices(), 0);
  for (const auto fh : mesh.faces()) {
    const auto heh = fh.halfedge();
    const int a = heh.from().idx(), b = heh.to().idx(), c = heh.next().to().idx();
    sets.unite(a, b);
    sets.unite(a, c);
    referenced[a] = referenced[b] = referenced[c] = 1;
  }

  // Component ids in order of each component's lowest face index.
  std::vector<int> componentOfRoot(mesh.n_vertices(), -1);
  const auto componentOf = [&](TriMesh::VertexHandle vh) {
    return componentOfRoot[sets.find(vh.idx())];
  };
  for (const auto fh : mesh.faces()) {
    int& id = componentOfRoot[sets.find(fh.halfedge().from().idx())];
    if (id < 0) {
      id = static_cast<int>(topology.perComponent.size());
      topology.perComponent.emplace_back();
    }
    ++topology.perComponent[id].faces;
  }
  topology.components = static_cast<int>(topology.perComponent.size());

  for (const auto vh : mesh.vertices()) {
    if (!referenced[vh.idx()]) {
      ++topology.isolatedVertices;
      continue;
    }
    auto& component = topology.perComponent[componentOf(vh)];
    ++component.vertices;
    if (!mesh.is_manifold(vh)) component.manifold = false;
  }
  for (const auto eh : mesh.edges()) {
    if (eh.h0().is_boundary() && eh.h1().is_boundary()) continue;  // dangling edge, no face
    ++topology.perComponent[componentOf(eh.v0())].edges;
  }

  // Boundary loops: cycles of boundary halfedges under next_halfedge.
  std::vector<char> visited(mesh.n_halfedges(), 0);
  for (const auto heh : mesh.halfedges()) {
    if (!heh.is_boundary() || visited[heh.idx()] || heh.opp().is_boundary()) continue;
    auto walk = heh;
    std::size_t steps = 0;
    do {
      visited[walk.idx()] = 1;
      walk = walk.next();
      ++steps;
    } while (walk != heh && steps <= mesh.n_halfedges());
    assert(walk == heh && "boundary halfedges must form cycles");
    ++topology.perComponent[componentOf(heh.from())].boundaryLoops;
  }

  for (auto& c : topology.perComponent) {
    c.eulerCharacteristic = static_cast<long long>(c.vertices) - static_cast<long long>(c.edges) +
                            static_cast<long long>(c.faces);
    const long long twiceGenus =
        2 - c.eulerCharacteristic - static_cast<long long>(c.boundaryLoops);
    c.genus = c.manifold && twiceGenus >= 0 && twiceGenus % 2 == 0
                  ? static_cast<int>(twiceGenus / 2)
                  : -1;
    topology.boundaryLoops += static_cast<int>(c.boundaryLoops);
    topology.eulerCharacteristic += static_cast<int>(c.eulerCharacteristic);
    topology.manifold = topology.manifold && c.manifold;
  }
  return topology;
}

}  // namespace hexcover
