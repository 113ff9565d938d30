#pragma once
// Forward substitution with a sparse right-hand side on CHOLMOD's supernodal factor.
//
// For P A Pᵀ = L Lᵀ, column j of W = L⁻¹ P B is nonzero only on the supernodes of the elimination
// tree's paths from the rows of B(:, j) to the root (Gilbert and Peierls, on supernodes), which
// on a mesh are a few separators: a small fraction of L. Then Bᵀ A⁻¹ B = Wᵀ W, the Schur
// complement of a few columns without a dense solve through the whole factor.

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace hexcover {

/// Eigen's CHOLMOD supernodal LLᵀ with read access to the factor that supernodalForwardSolve needs.
template <typename Matrix>
class CholmodSupernodalFactorization : public Eigen::CholmodSupernodalLLT<Matrix> {
 public:
  /// The last factorization's factor; null before the first analysis.
  const cholmod_factor* factor() const { return this->m_cholmodFactor; }
};

/// W = L⁻¹ P B (rows in the factor's order) for a real supernodal LLᵀ factor (as CHOLMOD's
/// supernodal factorization computes it) and a sparse B with factor.n rows. Throws
/// std::invalid_argument for another kind of factor or a B of the wrong size.
Eigen::SparseMatrix<double> supernodalForwardSolve(const cholmod_factor& factor,
                                                   const Eigen::SparseMatrix<double>& b);

}  // namespace hexcover
