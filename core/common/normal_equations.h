#pragma once
// The normal matrix AᵀWA of a least-squares problem whose rows come in small groups (a face's
// rows), for row weights W that change between solves while A stays.
//
// A generic sparse product (√W A)ᵀ(√W A) finds the pattern again for each W and merges the
// rows' contributions through a dense column mask. Here the pattern (columns that share a row)
// is found once, and an assembly adds each row's outer product where it belongs, looking the
// places up once per group of rows: the same values to the last bit. On the parameterization of
// a 1.1M-face mesh (6 rows per face): 1.3 s for the pattern, then 1.0-1.5 s per assembly,
// against 4.1-4.4 s per product. Two threads sum disjoint ranges of columns (the Stanford
// bunny's parameterization: 0.11-0.12 → 0.065-0.08 s).
//
// A few trailing columns that many rows meet (the parameterization's integer unknowns: a face
// near the cut graph can depend on a hundred of them) are summed among themselves in a dense
// block, without looking places up: a row over m of them adds m² products. Their entries in the
// other rows are copied from the mirror images, which sit in short columns, instead of being
// looked up in their long ones. Feline's quad parameterization (rows over up to 165 columns):
// 0.47 s per assembly without the block, 0.24 s with it.
#include <Eigen/SparseCore>
#include <vector>

namespace hexcover {

class NormalEquations {
 public:
  /// Dense blocks of trailing columns are kept to this many columns (8 MiB of sums).
  static constexpr int kMaxDenseColumns = 1024;

  /// `groupStart`: the first row of each group, increasing, from 0; the last group ends at
  /// a.rows(). Any grouping gives the same matrix; groups of a few rows over the same few
  /// columns make it fast. The products among the last `denseColumns` columns (at most
  /// kMaxDenseColumns; more are summed like the others) are summed in a dense block. Throws
  /// std::invalid_argument for groups that do not start at 0 or decrease.
  NormalEquations(const Eigen::SparseMatrix<double>& a, const std::vector<int>& groupStart,
                  int denseColumns = 0);

  /// Whether an assembly sums the entries among the dense block's columns or leaves them 0 (a
  /// caller that holds those unknowns fixed does not read them).
  enum class DenseBlock { Summed, Skipped };

  /// AᵀWA (both triangles) for W = diag(rowWeight) (#rows of A), on up to `threads` threads
  /// (the same values for any count).
  Eigen::SparseMatrix<double> assemble(const Eigen::VectorXd& rowWeight, int threads = 1,
                                       DenseBlock denseBlock = DenseBlock::Summed) const;

  /// The pattern of AᵀA (both triangles), every stored value 0: that of every assembly.
  const Eigen::SparseMatrix<double>& pattern() const { return pattern_; }

  /// A, row by row.
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix() const { return rows_; }

 private:
  /// Adds the entries of `result`'s columns [firstColumn, endColumn) of AᵀWA.
  void assembleColumns(const Eigen::VectorXd& rowWeight, int firstColumn, int endColumn,
                       DenseBlock denseBlock, Eigen::SparseMatrix<double>& result) const;

  Eigen::SparseMatrix<double, Eigen::RowMajor> rows_;  ///< A, row by row
  std::vector<int> groupStart_;                        ///< with rows_.rows() appended
  int denseFrom_;  ///< the first column of the dense block (rows_.cols() without one)
  Eigen::SparseMatrix<double> pattern_;                ///< AᵀA's pattern, values 0
};

}  // namespace hexcover
