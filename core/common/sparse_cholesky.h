#pragma once
// Sparse Cholesky factorization of a symmetric (Hermitian) positive definite matrix: CHOLMOD's
// supernodal LLᵀ on single-threaded OpenBLAS (blas_threads.h), which is 1.5-2x faster than
// Eigen's up-looking SimplicialLDLT on the meshes' Laplacian-like systems, with SimplicialLDLT as
// the fallback when CHOLMOD refuses the matrix (semidefinite up to round-off).

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <memory>

#include "core/common/blas_threads.h"

namespace hexcover {

template <typename Scalar>
class SparseCholesky {
 public:
  using Matrix = Eigen::SparseMatrix<Scalar>;

  SparseCholesky() { useSingleThreadedBlas(); }
  explicit SparseCholesky(const Matrix& a) : SparseCholesky() { compute(a); }

  /// Factorizes `a` (only its lower triangle is read); false when both factorizations failed.
  bool compute(const Matrix& a) {
    rows_ = a.rows();
    ldlt_.reset();
    cholmod_.reset();
    if (rows_ == 0) return true;  // nothing to factorize (CHOLMOD cannot take a 0×0 matrix)
    cholmod_ = std::make_unique<Eigen::CholmodSupernodalLLT<Matrix>>();
    cholmod_->cholmod().print = 0;  // failures are reported through info(), never on stdout
    cholmod_->compute(a);
    if (cholmod_->info() == Eigen::Success) return true;
    cholmod_.reset();
    ldlt_ = std::make_unique<Eigen::SimplicialLDLT<Matrix>>(a);
    return ldlt_->info() == Eigen::Success;
  }

  bool ok() const {
    if (rows_ == 0) return true;
    return cholmod_ ? cholmod_->info() == Eigen::Success : ldlt_ && ldlt_->info() == Eigen::Success;
  }
  Eigen::Index rows() const { return rows_; }

  /// A⁻¹ b (one or several columns); b itself for the 0×0 matrix.
  template <typename Rhs>
  Eigen::Matrix<Scalar, Eigen::Dynamic, Rhs::ColsAtCompileTime> solve(const Rhs& b) const {
    if (rows_ == 0 || b.cols() == 0) return b;
    if (cholmod_) return cholmod_->solve(b);
    return ldlt_->solve(b);
  }

 private:
  Eigen::Index rows_ = 0;
  std::unique_ptr<Eigen::CholmodSupernodalLLT<Matrix>> cholmod_;
  std::unique_ptr<Eigen::SimplicialLDLT<Matrix>> ldlt_;
};

}  // namespace hexcover
