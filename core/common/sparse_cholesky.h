#pragma once
// Sparse Cholesky factorization of a symmetric (Hermitian) positive definite matrix: CHOLMOD's
// supernodal LLᵀ on single-threaded OpenBLAS (blas_threads.h), which is 1.5-2x faster than
// Eigen's up-looking SimplicialLDLT on the meshes' Laplacian-like systems, with SimplicialLDLT as
// the fallback when CHOLMOD refuses the matrix (semidefinite up to round-off).
//
// Families of systems on subsets of one graph (the field's re-solves on regions of the mesh)
// can share one fill-reducing order: eliminating a subgraph in the order induced by an order of
// the whole graph fills no more than the whole graph does, and skips the per-system ordering.
// Such a system numbers its unknowns along the shared order and is factorized with
// RowOrder::AsGiven.

#include <Eigen/CholmodSupport>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <memory>
#include <utility>
#include <vector>

#include "core/common/blas_threads.h"

namespace hexcover {

/// The nodes of the graph with the given edges in Eigen's approximate minimum degree order (the
/// order CHOLMOD's AMD would pick, up to ties): node order[k] is eliminated k-th.
inline std::vector<int> minimumDegreeOrder(int nodes,
                                           const std::vector<std::pair<int, int>>& edges) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(2 * edges.size() + nodes);
  for (int i = 0; i < nodes; ++i) triplets.emplace_back(i, i, 1.0);
  for (const auto& [a, b] : edges) {
    triplets.emplace_back(a, b, 1.0);
    triplets.emplace_back(b, a, 1.0);
  }
  Eigen::SparseMatrix<double> pattern(nodes, nodes);
  pattern.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
  Eigen::AMDOrdering<int>()(pattern, order);
  return {order.indices().data(), order.indices().data() + nodes};
}

/// From this many blocks on, METIS alone: on mesh graphs that large, CHOLMOD's choice (AMD, then
/// METIS where AMD fills much, the smaller fill kept) ends at METIS anyway, and the AMD try costs
/// 0.5 s of the 4.9 s on the 556K vertices of a 1.1M-face mesh (the same order without it).
constexpr int kMetisOnlyBlocks = 100'000;

/// A fill-reducing order of a symmetric matrix whose unknowns come in consecutive blocks of
/// `blockSize` (the u and v of a vertex): CHOLMOD's choice (AMD, or METIS where AMD fills
/// much) for the graph of the blocks, each block's unknowns kept together. Ordering the block
/// graph instead of the whole matrix costs a fraction of the time (METIS on the 2V unknowns of
/// a 1M-face mesh: 7 s; on its V vertices: 3 s) for the same fill where the blocks' unknowns
/// share their neighbours. METIS alone from kMetisOnlyBlocks blocks on.
std::vector<int> blockFillReducingOrder(const Eigen::SparseMatrix<double>& a, int blockSize);

/// Whether a system's rows are to be reordered before the factorization.
enum class RowOrder {
  /// CHOLMOD's approximate minimum degree order (AMD). CHOLMOD's default also tries METIS when
  /// AMD fills much, which on a mesh Laplacian of 1M faces costs 3.3 s of ordering to save 0.1 s
  /// of factorization: a loss for systems that are factorized once.
  Reorder,
  AsGiven,  ///< the rows are already numbered in a fill-reducing order (see minimumDegreeOrder)
};

template <typename Scalar>
class SparseCholesky {
 public:
  using Matrix = Eigen::SparseMatrix<Scalar>;

  SparseCholesky() { useSingleThreadedBlas(); }
  explicit SparseCholesky(const Matrix& a, RowOrder order = RowOrder::Reorder) : SparseCholesky() {
    compute(a, order);
  }

  /// Factorizes `a` (only its lower triangle is read); false when both factorizations failed.
  bool compute(const Matrix& a, RowOrder order = RowOrder::Reorder) {
    rows_ = a.rows();
    ldlt_.reset();
    cholmod_.reset();
    if (rows_ == 0) return true;  // nothing to factorize (CHOLMOD cannot take a 0×0 matrix)
    cholmod_ = std::make_unique<Eigen::CholmodSupernodalLLT<Matrix>>();
    cholmod_->cholmod().print = 0;  // failures are reported through info(), never on stdout
    // Supernodes amalgamated twice as far as CHOLMOD's default (4, 16, 48 columns): larger dense
    // blocks for BLAS; 25-30% faster on the vertex Laplacians of the clean/ meshes, the same on
    // the field's complex systems (bench_field, bench_param).
    constexpr std::array<std::size_t, 3> kRelaxedColumns{8, 32, 96};
    std::copy(kRelaxedColumns.begin(), kRelaxedColumns.end(), cholmod_->cholmod().nrelax);
    cholmod_->cholmod().nmethods = 1;
    cholmod_->cholmod().method[0].ordering =
        order == RowOrder::AsGiven ? CHOLMOD_NATURAL : CHOLMOD_AMD;
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
