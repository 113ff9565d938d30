#pragma once
// Internal to core/param: energy (4) of the paper as a sparse least-squares problem over the
// unknowns of cut_mesh.h, with the rows that put creases on lattice lines.
//
// Rows (∂u/∂x, ∂u/∂y, ∂v/∂x, ∂v/∂y) per face in the combed frame over the columns of Unknowns,
// with targets (σ_f, 0, 0, σ_f), σ_f = s_f / h; then two rows
// √λ·(∂v/∂x + ∂u/∂y, ∂v/∂y − ∂u/∂x) = √λ·(∇v − J∇u) with target 0: the anti-conformal part of
// the Jacobian. Energy (4) is |conformal part − σ·I|² + |anti-conformal part|²; the extra rows
// weigh anisotropy (1 + 2λ) times more than a change of scale or rotation, so what the integer
// constraints force on the map is taken up by angle-preserving changes where possible.
//
// Creases (the field's sharp edges). A crease edge u→w seen from one of its faces f, whose field
// follows the edge, runs along a lattice direction in f's chart; the lattice coordinate across
// it, ℓ·p (b along e1, a along e2, a + b along e2 − e1; p Cartesian), is then constant along
// the edge, and when it is an integer a lattice line (a row of remesh edges) lies on the crease
// (for N = 4 the directions are e1 and e2, and ℓ is b or a).
// Three rows per crease edge and face: ℓ·(p_w − p_u) = 0 (alignment) from the start; after the
// rounding, ℓ·p_u = t and ℓ·p_w = t with t the integer nearest to the edge's mean coordinate.
// Each edge takes its own nearest line: a crease that the lattice cannot follow exactly (a
// curved one, or one where the field turns) moves to the next line where it must, instead of
// straining the whole map.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "core/field/rosy_field.h"
#include "core/mesh/mesh.h"
#include "core/param/cut_graph.h"
#include "core/param/cut_mesh.h"

namespace hexcover::param_detail {

/// Per-face geometry in the combed frame: gradients of the three corner hat functions.
struct FaceGeometry {
  std::vector<double> area;                           ///< #F
  std::vector<std::array<Eigen::Vector2d, 3>> grad;   ///< #F × corner (halfedge order)
  std::vector<std::array<Eigen::Vector2d, 3>> local;  ///< #F × corner positions in the frame
};

FaceGeometry computeFaceGeometry(const TriMesh& mesh, const RosyField& field, const CutGraph& cut);

constexpr int kRowsPerFace = 6;
constexpr int kEnergyRows = 4;  ///< the first rows of a face: those of energy (4)
constexpr int kRowsPerCrease = 3;

struct LeastSquares {
  Eigen::SparseMatrix<double> gradient;  ///< 6F (+ crease rows) × columns
  Eigen::VectorXd target;                ///< 6F (+ crease rows)
  Eigen::VectorXd faceArea;              ///< F (0 for degenerate faces, which are left out)
  Eigen::VectorXd rowWeight;             ///< per crease row (after the 6F face rows)
};

/// A crease edge seen from one of its faces.
struct CreaseEdge {
  int wedgeFrom = -1, wedgeTo = -1;
  int face = -1;           ///< the face it is seen from
  double length = 0.0;     ///< on the surface
  Eigen::Vector2d across;  ///< ℓ
  double weight = 0.0;     ///< of its rows: the crease weight times its length in lattice units
};

/// The crease edges of the field's sharp edges, each seen from both of its faces (weights 0 until
/// setLatticeScale); none when `weight` ≤ 0.
std::vector<CreaseEdge> findCreases(const TriMesh& mesh, const CutMesh& cm,
                                    const FaceGeometry& geometry, const RosyField& field,
                                    double weight);

/// The rows of energy (4) and the anisotropy of every face, then the crease rows; the targets
/// and the crease weights, which depend on the lattice scale, are 0 until setLatticeScale. The
/// matrix does not depend on the scale.
LeastSquares buildLeastSquares(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u,
                               const FaceGeometry& geometry, double conformalWeight,
                               const std::vector<CreaseEdge>& creases);

/// The targets (σ_f, 0, 0, σ_f) of energy (4), σ_f = faceScale[f] (lattice units per surface
/// length), and the crease weights (their lengths in lattice units).
void setLatticeScale(const std::vector<double>& faceScale, double creaseWeight,
                     std::vector<CreaseEdge>& creases, LeastSquares& ls);

/// Puts every crease edge on its nearest lattice line in x: targets and weights of its line rows.
void setCreaseTargets(const Unknowns& u, const std::vector<CreaseEdge>& creases,
                      const Eigen::VectorXd& x, LeastSquares& ls);

}  // namespace hexcover::param_detail
