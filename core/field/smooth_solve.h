#pragma once
// Internal to core/field: the smoothness solve in the power representation (paper section 3.2,
// after Ray et al.). One complex unknown u_f = e^{iNθ_f} per face in its frame; the energy
//   E(u) = Σ_e w_e |u_f1 − r_e u_f0|² + Σ_f λ_f |u_f − q_f|²,   r_e = e^{iN(ρ_e + c_e)},
// over interior edges, with some faces fixed (hard constraints, or the field outside the
// re-solve region) and soft constraints q_f of weight λ_f. Its minimizer solves the Hermitian
// positive (semi)definite system (L + Λ) u = Λ q + (terms of the fixed faces), factored with a
// complex sparse Cholesky (core/common/sparse_cholesky.h). A connected group of free faces that
// touches no fixed face and has no soft constraint has only the trivial minimizer u = 0; it gets
// the smoothest unit field instead:
// the eigenvector of the smallest eigenvalue of L u = λ M u (M: the face areas, so that the
// field's norm is measured on the surface, not per face) by inverse power iteration from a
// fixed start vector (deterministic). With M = I the iteration would favour |u| where faces are
// many, and put the zeros (the singularities) where the mesh is coarse: a sphere whose
// triangles are 20 times larger at one pole than at the other got all 12 there. Its phase,
// which the energy leaves free, makes the plain sum Σ_f u_f real and positive: the phase that
// the start vector (u_f = 1: along the first edge of each face) gives it without M, which keeps
// the lattice of a mesh that is itself a lattice (the geodesic icosphere) on its edges.

#include <complex>
#include <vector>

#include "core/mesh/mesh.h"

namespace hexcover::field {

using Complex = std::complex<double>;

/// The energy's geometric terms, built once per mesh.
struct SmoothnessTerms {
  std::vector<int> edge;          ///< per interior edge: its mesh edge index e
  std::vector<int> face0, face1;  ///< f0 = face(h0), f1 = face(h1)
  std::vector<double> weight;     ///< w_e = |e| / |c_f0 − c_f1| (clamped to [1e-3, 1e3])
  std::vector<int> faceOrder;     ///< #F faces in the dual graph's minimum-degree order
};

/// Terms for the interior edges of `mesh`.
SmoothnessTerms smoothnessTerms(const TriMesh& mesh);

struct SmoothSolveInput {
  std::vector<bool> free;           ///< #F: unknown (true) or fixed to `value` (false)
  std::vector<Complex> value;       ///< #F values of the fixed faces (free entries unused)
  std::vector<double> softWeight;   ///< #F λ_f ≥ 0 (empty: none)
  std::vector<Complex> softTarget;  ///< #F q_f (used where λ_f > 0)
};

/// Minimizer u (#F; fixed faces keep their values) for the transport angles ρ + c (#E each) and
/// symmetry order n; r_e is evaluated only on the edges at a free face. `faceArea` (#F, e.g.
/// FaceFrames::area) is the mass matrix M of a floating group's eigenproblem. Throws
/// Error(NumericalFailure) when the factorization fails.
std::vector<Complex> solveSmoothField(const SmoothnessTerms& terms,
                                      const std::vector<double>& transport,
                                      const std::vector<double>& corrections,
                                      const std::vector<double>& faceArea, int n,
                                      const SmoothSolveInput& input);

}  // namespace hexcover::field
