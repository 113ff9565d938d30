#pragma once
// Forward substitution with a sparse right-hand side on CHOLMOD's supernodal factor, solves with
// many dense right-hand sides split between threads, and solves after a low-rank update of the
// factorized matrix.
//
// For P A Pᵀ = L Lᵀ, column j of W = L⁻¹ P B is nonzero only on the supernodes of the elimination
// tree's paths from the rows of B(:, j) to the root (Gilbert and Peierls, on supernodes), which
// on a mesh are a few separators: a small fraction of L. Then Bᵀ A⁻¹ B = Wᵀ W, the Schur
// complement of a few columns without a dense solve through the whole factor.

#include <Eigen/Cholesky>
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

/// Bᵀ A⁻¹ B = Wᵀ W (dense, B's columns square) from W = supernodalForwardSolve(factor, b,
/// threads); the same exceptions.
Eigen::MatrixXd supernodalInverseForm(const cholmod_factor& factor,
                                      const Eigen::SparseMatrix<double>& b, int threads = 1);

/// Columns per CHOLMOD solve in supernodalSolve.
inline constexpr int kSolveBlock = 4;

/// A⁻¹ B for the factor of A (CHOLMOD's solve, permutation included) and a dense B with factor.n
/// rows: blocks of kSolveBlock columns, each solved with its own CHOLMOD workspace, on up to
/// `threads` threads (the same result for any count). Throws std::invalid_argument for a factor
/// that is not a real supernodal LLᵀ one or a B of the wrong size, Error LimitExceeded when
/// CHOLMOD runs out of memory.
Eigen::MatrixXd supernodalSolve(const cholmod_factor& factor, const Eigen::MatrixXd& b,
                                int threads = 1);

/// Solves with A = A₀ + U diag(d) Uᵀ, given the supernodal LLᵀ factor of A₀, a sparse U with few
/// columns and d > 0, without factorizing A (Sherman–Morrison–Woodbury):
///   A⁻¹ = A₀⁻¹ − A₀⁻¹ U C⁻¹ Uᵀ A₀⁻¹,   C = diag(d)⁻¹ + Uᵀ A₀⁻¹ U = diag(d)⁻¹ + Wᵀ W,
/// with W = L⁻¹ P U from supernodalForwardSolve. A solve costs two solves with A₀'s factor; the
/// setup, m sparse forward solves and an m×m Cholesky factorization (m = U's columns). Keeps a
/// reference to the factor, which must outlive it unchanged.
class LowRankUpdate {
 public:
  /// Throws std::invalid_argument for a factor that is not a real supernodal LLᵀ one, a U of the
  /// wrong size or a d that is not positive.
  LowRankUpdate(const cholmod_factor& factor, Eigen::SparseMatrix<double> u,
                const Eigen::VectorXd& d, int threads = 1);

  /// A⁻¹ B (B dense with factor.n rows), on up to `threads` threads (the same for any count).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b, int threads = 1) const;

 private:
  const cholmod_factor& factor_;
  Eigen::SparseMatrix<double> u_;
  Eigen::LLT<Eigen::MatrixXd> capacitance_;  // of C
};

}  // namespace hexcover
