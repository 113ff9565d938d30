#include "core/common/sparse_cholesky.h"

#include <stdexcept>

namespace hexcover {

std::vector<int> blockFillReducingOrder(const Eigen::SparseMatrix<double>& a, int blockSize) {
  const int n = static_cast<int>(a.rows());
  if (blockSize < 1 || n % blockSize != 0 || a.cols() != n)
    throw std::invalid_argument("blockFillReducingOrder: the matrix is not square in whole blocks");
  const int blocks = n / blockSize;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(a.nonZeros() / (blockSize * blockSize) + blocks);
  for (int col = 0; col < a.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, col); it; ++it)
      if (it.row() / blockSize >= col / blockSize)
        triplets.emplace_back(it.row() / blockSize, col / blockSize, 1.0);
  Eigen::SparseMatrix<double> pattern(blocks, blocks);
  pattern.setFromTriplets(triplets.begin(), triplets.end(), [](double x, double) { return x; });

  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  common.supernodal = CHOLMOD_SIMPLICIAL;  // only the order is wanted, not a supernodal analysis
  if (blocks >= kMetisOnlyBlocks) {
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_METIS;
  }
  cholmod_sparse view = Eigen::viewAsCholmod(pattern);
  view.stype = -1;  // the lower triangle of a symmetric matrix
  cholmod_factor* factor = cholmod_analyze(&view, &common);
  std::vector<int> order;
  if (factor) {
    const int* perm = static_cast<const int*>(factor->Perm);
    order.reserve(n);
    for (int k = 0; k < blocks; ++k)
      for (int j = 0; j < blockSize; ++j) order.push_back(perm[k] * blockSize + j);
    cholmod_free_factor(&factor, &common);
  }
  cholmod_finish(&common);
  if (order.empty())
    throw std::runtime_error("blockFillReducingOrder: CHOLMOD could not order the matrix");
  return order;
}

}  // namespace hexcover
