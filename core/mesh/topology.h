#pragma once
// Topological invariants of a triangle mesh: connected components, boundary loops, Euler
// characteristic and genus, per component and in total.
//
// Conventions. Only vertices referenced by a face count (isolated vertices are reported apart,
// they are not components of the surface). Components are the classes of faces connected through
// shared vertices. χ = V − E + F per component; for a connected orientable surface with b
// boundary loops χ = 2 − 2g − b, so g = (2 − χ − b) / 2. OpenMesh stores every face with a
// consistent orientation, so the only obstruction to a genus is a non-manifold vertex.

#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/report.h"  // ComponentTopology

namespace hexcover {

/// Invariants of the whole mesh; totals are sums over the components.
struct MeshTopology {
  int components = 0;
  int boundaryLoops = 0;
  int eulerCharacteristic = 0;
  int isolatedVertices = 0;  ///< vertices that belong to no face (not counted in χ)
  /// Ordered by each component's lowest face index; `orientable` is always true (OpenMesh stores
  /// consistently oriented faces), genus is −1 for a component with a non-manifold vertex.
  std::vector<ComponentTopology> perComponent;
  bool manifold = true;  ///< every vertex has a single fan of faces (OpenMesh edges always are)

  /// Sum of the component genera; −1 if any component's genus is undefined.
  int genus() const;
  /// Same number of components, and per component the same χ, boundary loops and genus, compared
  /// as multisets (component order does not matter).
  bool sameAs(const MeshTopology& other) const;
};

/// Components, boundary loops, χ and genus of `mesh`. Deleted elements (not yet garbage
/// collected) are ignored. O(V + E + F).
MeshTopology computeTopology(const TriMesh& mesh);

}  // namespace hexcover
