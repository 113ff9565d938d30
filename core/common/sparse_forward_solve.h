#pragma once
// Forward substitution with a sparse right-hand side on CHOLMOD's supernodal factor, and solves
// with many dense right-hand sides split between threads.
//
// For P A Pᵀ = L Lᵀ, column j of W = L⁻¹ P B is nonzero only on the supernodes of the elimination
// tree's paths from the rows of B(:, j) to the root (Gilbert and Peierls, on supernodes), which
// on a mesh are a few separators: a small fraction of L. Then Bᵀ A⁻¹ B = Wᵀ W, the Schur
// complement of a few columns without a dense solve through the whole factor.

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <vector>

namespace hexcover {

/// Eigen's CHOLMOD supernodal LLᵀ with read access to the factor that supernodalForwardSolve
/// needs, and a symbolic analysis in a given fill-reducing order.
template <typename Matrix>
class CholmodSupernodalFactorization : public Eigen::CholmodSupernodalLLT<Matrix> {
 public:
  using Eigen::CholmodSupernodalLLT<Matrix>::analyzePattern;

  /// The symbolic analysis of `a` (lower triangle) with row order[k] eliminated k-th (CHOLMOD
  /// may still postorder it); factorize() then takes matrices with the same pattern.
  void analyzePattern(const Matrix& a, std::vector<int> order) {
    if (this->m_cholmodFactor) cholmod_free_factor(&this->m_cholmodFactor, &this->cholmod());
    cholmod_sparse view = Eigen::viewAsCholmod(a.template selfadjointView<Eigen::Lower>());
    cholmod_common& common = this->cholmod();
    const int methods = common.nmethods, ordering = common.method[0].ordering;
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_GIVEN;
    this->m_cholmodFactor = cholmod_analyze_p(&view, order.data(), nullptr, 0, &common);
    common.nmethods = methods;
    common.method[0].ordering = ordering;
    this->m_isInitialized = true;
    this->m_info = this->m_cholmodFactor ? Eigen::Success : Eigen::NumericalIssue;
    this->m_analysisIsOk = this->m_cholmodFactor != nullptr;
    this->m_factorizationIsOk = false;
  }

  /// The last factorization's factor; null before the first analysis.
  const cholmod_factor* factor() const { return this->m_cholmodFactor; }
};

/// W = L⁻¹ P B (rows in the factor's order) for a real supernodal LLᵀ factor (as CHOLMOD's
/// supernodal factorization computes it) and a sparse B with factor.n rows, on up to `threads`
/// threads (the same W for any count). Throws std::invalid_argument for another kind of factor
/// or a B of the wrong size.
Eigen::SparseMatrix<double> supernodalForwardSolve(const cholmod_factor& factor,
                                                   const Eigen::SparseMatrix<double>& b,
                                                   int threads = 1);

/// Columns per CHOLMOD solve in supernodalSolve.
inline constexpr int kSolveBlock = 4;

/// A⁻¹ B for the factor of A (CHOLMOD's solve, permutation included) and a dense B with factor.n
/// rows: blocks of kSolveBlock columns, each solved with its own CHOLMOD workspace, on up to
/// `threads` threads (the same result for any count). Throws std::invalid_argument for a factor
/// that is not a real supernodal LLᵀ one or a B of the wrong size, Error LimitExceeded when
/// CHOLMOD runs out of memory.
Eigen::MatrixXd supernodalSolve(const cholmod_factor& factor, const Eigen::MatrixXd& b,
                                int threads = 1);

}  // namespace hexcover
