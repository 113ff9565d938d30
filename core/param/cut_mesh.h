#pragma once
// Internal to core/param: the cut mesh and the unknowns of the HexCover solve (hexcover.h).
//
// Cutting the mesh along the cut graph splits each vertex's corners into wedges. A wedge's
// lattice coordinates are an integer-matrix image of its vertex's master coordinates and of
// integer 2-vectors ("pairs": the translation of each cut edge, then the lattice position of each
// singular vertex), composed from the transitions of eq. (2) across the cut edges around the
// vertex; the closure around each vertex gives integer equations among the pairs, which
// integer_elimination.h eliminates exactly.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/param/cut_graph.h"
#include "core/param/integer_elimination.h"

namespace hexcover::param_detail {

/// sign · R^rotation · y_pair, a term of a corner's coordinates.
struct TranslationTerm {
  int pair = -1;
  int rotation = 0;  ///< in [0, n)
  int sign = 1;
};

/// z_wedge = R^rotation · z_master + Σ terms.
struct WedgeTransform {
  int rotation = 0;  ///< in [0, n)
  std::vector<TranslationTerm> terms;
};

/// The cut mesh: corners grouped into wedges, each wedge's coordinates as a transform of its
/// vertex's master coordinates and the pairs, and the closure constraints among the pairs.
struct CutMesh {
  std::vector<int> halfedgeWedge;              ///< #H, -1 on boundary halfedges
  std::vector<std::array<int, 3>> faceWedges;  ///< #F, the wedges of its halfedges, in order
  std::vector<int> wedgeVertex;
  std::vector<WedgeTransform> wedgeTransform;
  std::vector<int> edgePair;    ///< #E, pair of the cut edge's translation or -1
  std::vector<int> vertexPair;  ///< #V, pair of the singular vertex's position or -1
  std::vector<bool> realGauge;  ///< #V, master coordinates fixed at 0 (one per component)
  int pairCount = 0;
  std::vector<IntegerCombination> rows;  ///< over scalars 2·pair + {0, 1}
};

/// The wedges of `mesh` cut along `cut`, their transforms, the closure rows and one gauge per
/// component: a singular vertex at the origin (preferring holonomy ±1, whose fixed point is a
/// lattice point for any integer translations), else one vertex's master coordinates at 0.
CutMesh buildCutMesh(const TriMesh& mesh, const CutGraph& cut);

/// Column layout of the solve: the Cartesian master coordinates (u, v) of every free vertex, then
/// the free integer scalars (lattice units). Each wedge's Cartesian coordinates p_w = M z_w are
/// two sparse rows over these columns: p_w = Rc^ρ p_master + M Σ S_k y_k with Rc the Cartesian
/// rotation. Cartesian masters keep u and v uncoupled away from the cut (the Dirichlet energy is
/// the same Laplacian for both), which keeps the Cholesky factor about 5 times sparser than
/// lattice-coordinate masters coupled by the Gram matrix.
struct Unknowns {
  int realCount = 0;
  int integerCount = 0;
  int scalarCount = 0;            ///< integer scalars 2·pair + j (more free ones may be appended)
  std::vector<int> vertexColumn;  ///< #V, first of two real columns or -1
  IntegerElimination elimination;
  std::vector<int> freeColumn;  ///< #elimination variables, column of a free one or -1
  using Row = std::vector<std::pair<int, double>>;
  std::vector<std::array<Row, 2>> wedgeRows;

  int columns() const { return realCount + integerCount; }
};

/// The unknowns of the cut mesh for the lattice of order n, with the closure rows eliminated.
Unknowns buildUnknowns(const TriMesh& mesh, const CutMesh& cm, int n);

/// Groups of integer unknowns (counted from 0) that no face couples: those of each connected
/// component of the cut graph (a pair's cut edge or singular vertex lies in one), ascending within
/// a group; one group of all when an unknown spans two components. With several components the
/// Schur complement is block diagonal and each block is solved on its own: 400 small spheres have
/// 6400 integer unknowns, whose dense S would take O(k³) per solve.
std::vector<std::vector<int>> integerGroups(const TriMesh& mesh, const CutGraph& cut,
                                            const CutMesh& cm, const Unknowns& u);

/// Cartesian coordinates of a wedge in the solution x.
Eigen::Vector2d wedgePosition(const Unknowns& u, int wedge, const Eigen::VectorXd& x);

/// Per elimination variable: its free unknown in x rounded to an integer (0 for the others, which
/// no expression uses). `Solution` is read unknown by unknown (x[column]).
template <typename Solution>
std::vector<std::int64_t> roundedFreeUnknowns(const Unknowns& u, const Solution& x) {
  std::vector<std::int64_t> rounded(u.freeColumn.size(), 0);
  for (std::size_t variable = 0; variable < rounded.size(); ++variable)
    if (u.freeColumn[variable] >= 0) rounded[variable] = std::llround(x[u.freeColumn[variable]]);
  return rounded;
}

/// Value of integer scalar `scalar` (2·pair + j) from the rounded free unknowns.
std::int64_t integerValue(const Unknowns& u, const std::vector<std::int64_t>& rounded, int scalar);

}  // namespace hexcover::param_detail
