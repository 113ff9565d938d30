#include "core/common/sparse_forward_solve.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

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
  if (order.empty()) throw std::runtime_error("blockFillReducingOrder: CHOLMOD could not order the matrix");
  return order;
}

Eigen::SparseMatrix<double> supernodalForwardSolve(const cholmod_factor& factor,
                                                   const Eigen::SparseMatrix<double>& b) {
  if (!factor.is_super || !factor.is_ll || factor.xtype != CHOLMOD_REAL ||
      factor.itype != CHOLMOD_INT || factor.dtype != CHOLMOD_DOUBLE)
    throw std::invalid_argument("supernodalForwardSolve: needs a real supernodal LL' factor");
  const int n = static_cast<int>(factor.n);
  if (b.rows() != n)
    throw std::invalid_argument("supernodalForwardSolve: the right-hand side has the wrong size");
  const int supernodes = static_cast<int>(factor.nsuper);
  const int* firstColumn = static_cast<const int*>(factor.super);  // supernode s: columns
  const int* rowStart = static_cast<const int*>(factor.pi);        // [first[s], first[s + 1])
  const int* valueStart = static_cast<const int*>(factor.px);
  const int* rowIndex = static_cast<const int*>(factor.s);
  const double* value = static_cast<const double*>(factor.x);
  const int* perm = static_cast<const int*>(factor.Perm);  // position k holds row perm[k]

  std::vector<int> position(n), supernodeOf(n), parent(supernodes, -1);
  for (int k = 0; k < n; ++k) position[perm ? perm[k] : k] = k;
  for (int s = 0; s < supernodes; ++s) {
    for (int k = firstColumn[s]; k < firstColumn[s + 1]; ++k) supernodeOf[k] = s;
  }
  for (int s = 0; s < supernodes; ++s) {  // the supernode of the first row below the diagonal block
    const int columns = firstColumn[s + 1] - firstColumn[s];
    if (rowStart[s + 1] - rowStart[s] > columns)
      parent[s] = supernodeOf[rowIndex[rowStart[s] + columns]];
  }

  std::vector<double> work(n, 0.0);
  std::vector<char> inReach(supernodes, 0);
  std::vector<int> reach;
  std::vector<Eigen::Triplet<double>> triplets;
  for (int j = 0; j < b.cols(); ++j) {
    reach.clear();
    for (Eigen::SparseMatrix<double>::InnerIterator it(b, j); it; ++it) {
      const int k = position[it.row()];
      work[k] += it.value();
      for (int s = supernodeOf[k]; s >= 0 && !inReach[s]; s = parent[s]) {
        inReach[s] = 1;
        reach.push_back(s);
      }
    }
    std::sort(reach.begin(), reach.end());  // a parent's index exceeds its children's
    for (const int s : reach) {
      const int first = firstColumn[s], columns = firstColumn[s + 1] - first;
      const int rows = rowStart[s + 1] - rowStart[s];
      const int* row = rowIndex + rowStart[s];      // row[c] = first + c for c < columns
      const double* block = value + valueStart[s];  // column-major, leading dimension `rows`
      for (int c = 0; c < columns; ++c) {  // x_c = (b_c − Σ_{c' < c} L(c, c') x_c') / L(c, c)
        const double x = work[first + c] / block[c + c * rows];
        work[first + c] = x;
        if (x == 0.0) continue;
        for (int i = c + 1; i < rows; ++i) work[row[i]] -= block[i + c * rows] * x;
      }
    }
    for (const int s : reach) {  // every row that was written belongs to a supernode of the reach
      for (int k = firstColumn[s]; k < firstColumn[s + 1]; ++k) {
        if (work[k] != 0.0) triplets.emplace_back(k, j, work[k]);
        work[k] = 0.0;
      }
      inReach[s] = 0;
    }
  }
  Eigen::SparseMatrix<double> w(n, b.cols());
  w.setFromTriplets(triplets.begin(), triplets.end());
  return w;
}

}  // namespace hexcover
