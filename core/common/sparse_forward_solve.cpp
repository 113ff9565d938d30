#include "core/common/sparse_forward_solve.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace hexcover {

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
