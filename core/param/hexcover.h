#pragma once
// HexCover: seamless hexagonal (N = 6) or quadrilateral (N = 4) global parameterization of a
// triangle mesh guided by an N-RoSy field (paper section 4).
//
// Formulation (equivalent to the paper's cogradient local step, same minimizer of energy (4)):
// the mesh is cut into a disk per component (cut_graph.h); the unknowns are the lattice
// coordinates of each vertex in one master corner, the translation t_e ∈ R² of every cut edge and
// the lattice position of every singular vertex. Every corner's coordinates are an integer-matrix
// image of these (eq. (2): z_f1 = R^r z_f0 + t across the cut), the closure around each vertex gives
// integer equations among translations (regular vertices) or fixes the vertex as the fixed point of
// its holonomy (singular vertices), and these are eliminated exactly (integer_elimination.h).
// Energy (4) in lattice coordinates is a sparse least-squares problem; the local step minimizes it
// over all unknowns, the global step rounds the independent integer unknowns (direct rounding, sec.
// 4.4, or greedy mixed-integer rounding, sec. 4.5) and solves again with them fixed. Fold-overs are
// removed by stiffening (raising the weight of distorted triangles and re-solving).

#include <vector>

#include "core/common/run_context.h"
#include "core/field/rosy_field.h"
#include "core/mesh/mesh.h"
#include "core/param/parameterization.h"

namespace hexcover {

enum class RoundingMethod {
  Direct,  ///< round every independent integer unknown at once (paper sec. 4.4)
  Greedy,  ///< round the unknowns closest to the lattice first, re-solve, repeat (sec. 4.5, MIQ)
};

enum class LinearSolver {
  SimplicialLDLT,  ///< Eigen's simplicial LDLᵀ
  Cholmod,         ///< SuiteSparse CHOLMOD (supernodal) through Eigen's CholmodSupport
};

struct ParamOptions {
  /// h: surface length of one lattice unit (where the sizing is 1). When ≤ 0, h is derived from
  /// targetVertices; when both are unset, from a target of a quarter of the input's vertices
  /// (the pipeline's default).
  double edgeLength = 0.0;
  /// K: the remesh should have about K vertices (h from the sized area, see
  /// edgeLengthForVertexCount, times the conformal scale's correction, see conformal_scale.h).
  int targetVertices = 0;
  /// #V per-vertex sizing factors s > 0 (local lattice unit = h / s), or empty for uniform.
  /// See curvatureSizing for curvature-adaptive values.
  std::vector<double> vertexSizing;
  /// Scale the field by the conformal factor of core/param/conformal_scale.h (target lengths
  /// vary, angles are kept); false: unit field, energy (4) with |F_u| = 1/h.
  bool conformalScale = true;
  /// λ ≥ 0: extra weight on the anti-conformal part of the Jacobian (anisotropy), see energy.h.
  double conformalWeight = 1.0;
  /// Greedy by default: once the integers are solved on the Schur complement it costs under a
  /// millisecond on the bunny and lowers the energy by 0-50% (bench_param).
  RoundingMethod rounding = RoundingMethod::Greedy;
  /// After rounding, move single integer unknowns to neighbouring lattice points while the
  /// energy drops (exact changes on the Schur complement).
  bool latticeDescent = true;
  /// Greedy rounding: fraction of the remaining integer unknowns rounded per re-solve, in (0, 1].
  double greedyBatchFraction = 0.25;
  /// Weight of the creases of the field (RosyField::sharpEdges) per unit of crease length in
  /// lattice units, relative to energy (4) per unit of area: each crease edge along a lattice
  /// direction is pulled onto its nearest lattice line (see energy.h). 0 ignores them.
  double creaseWeight = 10.0;
  /// Maximum stiffening re-solves while flipped triangles remain (0 disables stiffening).
  int maxStiffeningIterations = 10;
  /// CHOLMOD by default: with OpenBLAS it factorizes the bunny's system 2.6x faster (bench_param).
  LinearSolver solver = LinearSolver::Cholmod;
  /// Threads: the conformal scale beside the setup (cut graph, system, ordering), the Schur
  /// complement's forward solve, and the rounding repair's response solves and trial moves. The
  /// result is the same for any count. At least 1.
  int threads = 2;

  /// Throws Error(InvalidOption) naming the first bad option.
  void validate() const;
};

/// The seamless parameterization of `mesh` along `field` (N = 4 or 6). The result's
/// cornerCoords satisfy the integer transitions exactly in floating point, every singular vertex
/// sits on a lattice point, and flipped/degenerate triangles are counted (see parameterization.h).
/// Throws Error(InvalidOption) for bad options or a field of another mesh, Error(InvalidMesh) for a
/// mesh without faces, Error(NumericalFailure) when a solve fails, Error(Canceled) on request.
Parameterization computeParameterization(const TriMesh& mesh, const RosyField& field,
                                         const ParamOptions& options, const RunContext& context = {});

/// Default d_sing of the field for a parameterization at edge length h (the remesh pipeline and
/// `hexcover param`): kSingularityDistanceInEdges · h. The paper picks d_sing = 0.1·B for models
/// remeshed at a few thousand vertices, about 6-10 edge lengths; singularities closer than a few
/// lattice units are rounded onto one lattice point and force local degeneration (its Fig. 15),
/// and more distant ones cost fewer irregular vertices.
inline constexpr double kSingularityDistanceInEdges = 6.0;

/// Creases of a parameterization's field (the remesh pipeline and `hexcover param`): sharp edges
/// of at least kDefaultFeatureAngle degrees on lines at least kCreaseLineInEdges · h long
/// (FieldOptions::sharpEdgeAngle, sharpLineLength). Measured at a quarter of the vertices: the
/// clean scans have no such line (camelhead's ear rim, 61-79° over 5.4 h, breaks into short
/// pieces at 70°); fandisk's creases are 90° and 3.4-25 h long (angle SD 6.66° with 60° and
/// 6 h, 6.13° with 70° and 4 h).
inline constexpr double kDefaultFeatureAngle = 70.0;
inline constexpr double kCreaseLineInEdges = 4.0;

/// The field options of a parameterization at edge length h (the remesh pipeline and
/// `hexcover param`): symmetry order n, singularities clustered at `singularityDistance` with
/// merges up to kMergedIndexForLattice, creases of at least `featureAngle` degrees on lines at
/// least kCreaseLineInEdges · h long.
FieldOptions parameterizationFieldOptions(int n, double edgeLength, double singularityDistance,
                                          double featureAngle);

/// FieldOptions::maxMergedIndex of the field for a parameterization (the remesh pipeline and
/// `hexcover param`): merges stop at index ±1/N, whose fixed point is a lattice point; a ±2/6 is
/// best placed at a ⅓ lattice point, which the rounding of section 4.4 does not support.
inline constexpr int kMergedIndexForLattice = 1;

}  // namespace hexcover
