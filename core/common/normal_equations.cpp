#include "core/common/normal_equations.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/common/concurrency.h"

namespace hexcover {
namespace {

/// The distinct columns of rows [begin, end) of a row-major matrix, in `columns` (sorted).
void groupColumns(const Eigen::SparseMatrix<double, Eigen::RowMajor>& rows, int begin, int end,
                  std::vector<int>& columns) {
  columns.clear();
  for (int r = begin; r < end; ++r)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows, r); it; ++it)
      columns.push_back(static_cast<int>(it.col()));
  std::sort(columns.begin(), columns.end());
  columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
}

}  // namespace

NormalEquations::NormalEquations(const Eigen::SparseMatrix<double>& a,
                                 const std::vector<int>& groupStart, int denseColumns)
    : rows_(a),
      groupStart_(groupStart),
      denseFrom_(static_cast<int>(a.cols()) -
                 (denseColumns <= kMaxDenseColumns
                      ? std::clamp(denseColumns, 0, static_cast<int>(a.cols()))
                      : 0)) {
  groupStart_.push_back(static_cast<int>(a.rows()));
  if (groupStart_.front() != 0 || !std::is_sorted(groupStart_.begin(), groupStart_.end()))
    throw std::invalid_argument("NormalEquations: groups must start at row 0 and increase");
  // The pattern of AᵀA: column c meets every column of every row that c has a nonzero in.
  const int n = static_cast<int>(a.cols());
  std::vector<int> mark(n, -1), outerStart(n + 1, 0), inner;
  for (int c = 0; c < n; ++c) {
    const std::size_t first = inner.size();
    for (Eigen::SparseMatrix<double>::InnerIterator row(a, c); row; ++row)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows_, row.row()); it;
           ++it)
        if (mark[it.col()] != c) {
          mark[it.col()] = c;
          inner.push_back(static_cast<int>(it.col()));
        }
    std::sort(inner.begin() + static_cast<std::ptrdiff_t>(first), inner.end());
    outerStart[c + 1] = static_cast<int>(inner.size());
  }
  pattern_.resize(n, n);
  pattern_.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outerStart.begin(), outerStart.end(), pattern_.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), pattern_.innerIndexPtr());
  std::fill(pattern_.valuePtr(), pattern_.valuePtr() + inner.size(), 0.0);
}

Eigen::SparseMatrix<double> NormalEquations::assemble(const Eigen::VectorXd& rowWeight, int threads,
                                                      DenseBlock denseBlock) const {
  if (rowWeight.size() != rows_.rows())
    throw std::invalid_argument("NormalEquations: one weight per row is needed");
  Eigen::SparseMatrix<double> result = pattern_;
  // Each worker sums the entries of its own range of the columns before the dense block (about
  // equal numbers of entries), over every group that reaches them: every entry is summed by one
  // worker, in the same order as by one thread. The last worker also sums the dense block.
  const int n = static_cast<int>(result.cols());
  const int* outer = result.outerIndexPtr();
  const int workers = std::clamp(threads, 1, std::max(1, denseFrom_));
  std::vector<int> bound(workers + 1, n);
  bound[0] = 0;
  for (int w = 1; w < workers; ++w)
    bound[w] =
        static_cast<int>(std::lower_bound(outer, outer + denseFrom_,
                                          static_cast<long long>(outer[denseFrom_]) * w / workers) -
                         outer);
  parallelFor(
      workers, workers,
      [&](std::size_t w) {
        assembleColumns(rowWeight, bound[w], bound[w + 1], denseBlock, result);
      },
      1);
  // The dense block's columns are long (a row meets many of them), so their entries in the
  // other rows are not looked up there but copied from their mirror images, (p, c) from (c, p)
  // in the short column p: a · b = b · a, the same sums.
  const int* inner = result.innerIndexPtr();
  double* value = result.valuePtr();
  parallelFor(
      static_cast<std::size_t>(n - denseFrom_), threads,
      [&](std::size_t d) {
        const int column = denseFrom_ + static_cast<int>(d);
        for (int k = outer[column]; k < outer[column + 1] && inner[k] < denseFrom_; ++k) {
          const int row = inner[k];
          value[k] =
              value[std::lower_bound(inner + outer[row], inner + outer[row + 1], column) - inner];
        }
      },
      1);
  return result;
}

void NormalEquations::assembleColumns(const Eigen::VectorXd& rowWeight, int firstColumn,
                                      int endColumn, DenseBlock denseBlock,
                                      Eigen::SparseMatrix<double>& result) const {
  double* value = result.valuePtr();
  const int* outer = result.outerIndexPtr();
  const int* inner = result.innerIndexPtr();
  // The dense block's sums in this range of columns: entry (i, j) of the block, j from
  // denseFirst, at dense[i + denseSize · (j − denseFirst)].
  const int denseSize = static_cast<int>(result.cols()) - denseFrom_;
  const int denseFirst = std::max(firstColumn, denseFrom_);
  const bool sumDense = denseBlock == DenseBlock::Summed;
  std::vector<double> dense(sumDense
                                ? static_cast<std::size_t>(denseSize) *
                                      static_cast<std::size_t>(std::max(0, endColumn - denseFirst))
                                : 0,
                            0.0);
  std::vector<int> columns, position, local;
  std::vector<double> scaled;
  const int groups = static_cast<int>(groupStart_.size()) - 1;
  for (int g = 0; g < groups; ++g) {
    const int begin = groupStart_[g], end = groupStart_[g + 1];
    groupColumns(rows_, begin, end, columns);
    if (columns.empty() || columns.back() < firstColumn || columns.front() >= endColumn) continue;
    const int m = static_cast<int>(columns.size());
    // The group's columns [0, split) are outside the dense block.
    const int split = static_cast<int>(
        std::lower_bound(columns.begin(), columns.end(), denseFrom_) - columns.begin());
    // Where entry (columns[p], columns[q]) of the result is stored, for q below split: looked
    // up when a row first needs it (two columns of a group need not share a row), at
    // position[q·m + p].
    position.assign(static_cast<std::size_t>(split) * m, -1);
    const auto at = [&](int p, int q) {
      int& index = position[static_cast<std::size_t>(q) * m + p];
      if (index < 0)
        index = static_cast<int>(
            std::lower_bound(inner + outer[columns[q]], inner + outer[columns[q] + 1], columns[p]) -
            inner);
      return index;
    };
    // Row by row, each entry summed over the rows in increasing order: the same sums, to the
    // last bit, as the product (√W A)ᵀ(√W A).
    for (int r = begin; r < end; ++r) {
      local.clear();
      scaled.clear();
      const double scale = std::sqrt(rowWeight[r]);
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows_, r); it; ++it) {
        local.push_back(static_cast<int>(
            std::lower_bound(columns.begin(), columns.end(), static_cast<int>(it.col())) -
            columns.begin()));
        scaled.push_back(it.value() * scale);
      }
      for (std::size_t b = 0; b < local.size(); ++b) {
        const int column = columns[local[b]];
        if (column < firstColumn || column >= endColumn) continue;
        if (local[b] < split) {
          for (std::size_t a = 0; a < local.size(); ++a)
            value[at(local[a], local[b])] += scaled[a] * scaled[b];
          continue;
        }
        // A column of the dense block: its other rows are mirrored afterwards (see assemble).
        if (!sumDense) continue;
        const std::size_t denseStart = static_cast<std::size_t>(denseSize) * (column - denseFirst);
        for (std::size_t a = 0; a < local.size(); ++a)
          if (local[a] >= split)
            dense[denseStart + (columns[local[a]] - denseFrom_)] += scaled[a] * scaled[b];
      }
    }
  }
  if (!sumDense) return;
  for (int column = denseFirst; column < endColumn; ++column)
    for (int k = outer[column]; k < outer[column + 1]; ++k)
      if (inner[k] >= denseFrom_)
        value[k] = dense[static_cast<std::size_t>(inner[k] - denseFrom_) +
                         static_cast<std::size_t>(denseSize) * (column - denseFirst)];
}

}  // namespace hexcover
