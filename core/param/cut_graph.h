#pragma once
// Combing of an N-RoSy field and the cut graph of the HexCover parameterization (paper sec. 4.3).
//
// A breadth-first dual spanning tree of the faces (one per connected component, rooted at the
// component's lowest face index, neighbours visited in halfedge order) combs the field: each face
// gets a rotation k_f such that the combed representatives R^{k_f}·faceDirection[f] match with
// rotation 0 across every tree edge. The cut is every interior edge off the tree, pruned: a cut
// edge ending at an interior vertex that is a dangling tip (one cut edge) with trivial holonomy is
// removed, repeatedly. What remains cuts each component into one topological disk; it contains
// every vertex of non-trivial holonomy (every singularity of index ≢ 0 mod N) and, where the
// component has several boundary loops or genus, reaches every boundary loop.

#include <vector>

#include "core/field/rosy_field.h"
#include "core/mesh/mesh.h"

namespace hexcover {

struct CutGraph {
  int n = 6;
  /// #F: k_f in {0..N-1}; the combed representative of face f is faceDirection[f] rotated by
  /// 2π k_f / N counter-clockwise about the face normal.
  std::vector<int> faceRotation;
  /// #E: matching in the combed frames, (r_e + k_f0 − k_f1) mod N; 0 off the cut and on boundary.
  std::vector<int> combedMatching;
  /// #E: true for the edges of the cut graph.
  std::vector<bool> cutEdge;
  /// #V: rotation of the field's holonomy around the vertex, in {0..N-1} (the index I mod N);
  /// 0 for boundary and isolated vertices.
  std::vector<int> vertexHolonomy;
  /// #F: connected component of each face (components numbered by lowest face index).
  std::vector<int> faceComponent;
  int componentCount = 0;
  int cutEdgeCount = 0;
  double cutLength = 0.0;  ///< total surface length of the cut edges
};

/// Combs `field` and builds the cut graph of `mesh` (see above). Deterministic: ties are broken
/// by element index. Throws Error(InvalidOption) when the field does not fit the mesh or has
/// N ∉ {4, 6}.
CutGraph computeCutGraph(const TriMesh& mesh, const RosyField& field);

}  // namespace hexcover
