#include "core/common/sparse_forward_solve.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/common/concurrency.h"
#include "core/common/error.h"

namespace hexcover {
namespace {

/// The supernodal factor as arrays, and each supernode's parent in the elimination tree.
struct SupernodalFactor {
  explicit SupernodalFactor(const cholmod_factor& factor)
      : n(static_cast<int>(factor.n)),
        supernodes(static_cast<int>(factor.nsuper)),
        firstColumn(static_cast<const int*>(factor.super)),
        rowStart(static_cast<const int*>(factor.pi)),
        valueStart(static_cast<const int*>(factor.px)),
        rowIndex(static_cast<const int*>(factor.s)),
        value(static_cast<const double*>(factor.x)),
        position(n),
        supernodeOf(n),
        parent(supernodes, -1) {
    const int* perm = static_cast<const int*>(factor.Perm);  // position k holds row perm[k]
    for (int k = 0; k < n; ++k) position[perm ? perm[k] : k] = k;
    for (int s = 0; s < supernodes; ++s)
      for (int k = firstColumn[s]; k < firstColumn[s + 1]; ++k) supernodeOf[k] = s;
    for (int s = 0; s < supernodes; ++s) {  // the supernode of the first row below the diagonal
      const int columns = firstColumn[s + 1] - firstColumn[s];
      if (rowStart[s + 1] - rowStart[s] > columns)
        parent[s] = supernodeOf[rowIndex[rowStart[s] + columns]];
    }
  }

  int n, supernodes;
  const int* firstColumn;  // supernode s: columns [firstColumn[s], firstColumn[s + 1])
  const int* rowStart;     // its rows rowIndex[rowStart[s] .. rowStart[s + 1])
  const int* valueStart;
  const int* rowIndex;
  const double* value;
  std::vector<int> position, supernodeOf, parent;
};

/// Solves the columns [begin, end) of B into triplets of W (Gilbert–Peierls on supernodes: only
/// the supernodes on the elimination-tree paths from a column's rows to the root).
void forwardSolveColumns(const SupernodalFactor& l, const Eigen::SparseMatrix<double>& b, int begin,
                         int end, std::vector<Eigen::Triplet<double>>& triplets) {
  std::vector<double> work(l.n, 0.0);
  std::vector<char> inReach(l.supernodes, 0);
  std::vector<int> reach;
  for (int j = begin; j < end; ++j) {
    reach.clear();
    for (Eigen::SparseMatrix<double>::InnerIterator it(b, j); it; ++it) {
      const int k = l.position[it.row()];
      work[k] += it.value();
      for (int s = l.supernodeOf[k]; s >= 0 && !inReach[s]; s = l.parent[s]) {
        inReach[s] = 1;
        reach.push_back(s);
      }
    }
    std::sort(reach.begin(), reach.end());  // a parent's index exceeds its children's
    for (const int s : reach) {
      const int first = l.firstColumn[s], columns = l.firstColumn[s + 1] - first;
      const int rows = l.rowStart[s + 1] - l.rowStart[s];
      const int* row = l.rowIndex + l.rowStart[s];      // row[c] = first + c for c < columns
      const double* block = l.value + l.valueStart[s];  // column-major, leading dimension `rows`
      for (int c = 0; c < columns; ++c) {  // x_c = (b_c − Σ_{c' < c} L(c, c') x_c') / L(c, c)
        const double x = work[first + c] / block[c + c * rows];
        work[first + c] = x;
        if (x == 0.0) continue;
        for (int i = c + 1; i < rows; ++i) work[row[i]] -= block[i + c * rows] * x;
      }
    }
    for (const int s : reach) {  // every row that was written belongs to a supernode of the reach
      for (int k = l.firstColumn[s]; k < l.firstColumn[s + 1]; ++k) {
        if (work[k] != 0.0) triplets.emplace_back(k, j, work[k]);
        work[k] = 0.0;
      }
      inReach[s] = 0;
    }
  }
}

void requireRealSupernodalLL(const cholmod_factor& factor, const char* caller) {
  if (!factor.is_super || !factor.is_ll || factor.xtype != CHOLMOD_REAL ||
      factor.itype != CHOLMOD_INT || factor.dtype != CHOLMOD_DOUBLE)
    throw std::invalid_argument(std::string(caller) + ": needs a real supernodal LL' factor");
}

/// One thread's CHOLMOD workspace.
class CholmodWorkspace {
 public:
  CholmodWorkspace() { cholmod_start(&common_); }
  ~CholmodWorkspace() { cholmod_finish(&common_); }
  CholmodWorkspace(const CholmodWorkspace&) = delete;
  CholmodWorkspace& operator=(const CholmodWorkspace&) = delete;
  cholmod_common& common() { return common_; }

 private:
  cholmod_common common_;
};

}  // namespace

Eigen::SparseMatrix<double> supernodalForwardSolve(const cholmod_factor& factor,
                                                   const Eigen::SparseMatrix<double>& b,
                                                   int threads) {
  requireRealSupernodalLL(factor, "supernodalForwardSolve");
  if (b.rows() != static_cast<Eigen::Index>(factor.n))
    throw std::invalid_argument("supernodalForwardSolve: the right-hand side has the wrong size");
  const SupernodalFactor l(factor);
  // Each worker solves a contiguous range of columns into its own triplets, with its own
  // workspace; columns are independent, so W does not depend on the split.
  const int columns = static_cast<int>(b.cols());
  const int workers = std::clamp(threads, 1, std::max(1, columns));
  std::vector<std::vector<Eigen::Triplet<double>>> triplets(workers);
  parallelFor(
      workers, workers,
      [&](std::size_t w) {
        forwardSolveColumns(l, b, static_cast<int>(columns * w / workers),
                            static_cast<int>(columns * (w + 1) / workers), triplets[w]);
      },
      1);
  for (std::size_t w = 1; w < triplets.size(); ++w)
    triplets[0].insert(triplets[0].end(), triplets[w].begin(), triplets[w].end());
  Eigen::SparseMatrix<double> result(l.n, b.cols());
  result.setFromTriplets(triplets[0].begin(), triplets[0].end());
  return result;
}

Eigen::MatrixXd supernodalSolve(const cholmod_factor& factor, const Eigen::MatrixXd& b,
                                int threads) {
  requireRealSupernodalLL(factor, "supernodalSolve");
  if (b.rows() != static_cast<Eigen::Index>(factor.n))
    throw std::invalid_argument("supernodalSolve: the right-hand side has the wrong size");
  const int columns = static_cast<int>(b.cols());
  const int width0 = std::max(kSolveBlock, (columns + 1) / 2);
  const int blocks = (columns + width0 - 1) / width0;
  Eigen::MatrixXd x(b.rows(), b.cols());
  // The blocks do not depend on the thread count, so neither does any column's result.
  parallelFor(
      blocks, threads,
      [&](std::size_t block) {
        const int first = static_cast<int>(block) * width0;
        const int width = std::min(width0, columns - first);
        Eigen::MatrixXd rhs = b.middleCols(first, width);
        cholmod_dense view = Eigen::viewAsCholmod(rhs);
        CholmodWorkspace workspace;
        // cholmod_solve reads the factor only.
        cholmod_dense* solved = cholmod_solve(CHOLMOD_A, const_cast<cholmod_factor*>(&factor),
                                              &view, &workspace.common());
        if (!solved)
          throw Error(ErrorCode::LimitExceeded, "out of memory in a sparse solve (CHOLMOD)");
        x.middleCols(first, width) = Eigen::Map<const Eigen::MatrixXd>(
            static_cast<const double*>(solved->x), b.rows(), width);
        cholmod_free_dense(&solved, &workspace.common());
      },
      1);
  return x;
}

}  // namespace hexcover
