#include "core/common/sparse_forward_solve.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
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

/// Columns of B solved together: each supernode of their reach is read once for the group (a
/// dense triangular solve and product on the columns that reach it) instead of once per column.
/// At most 64 (a bit mask per supernode).
constexpr int kForwardGroup = 32;

/// Solves the columns `group` of B (Gilbert–Peierls on supernodes: only the supernodes on the
/// elimination-tree paths from the columns' rows to the root) and appends W's nonzeros to
/// `triplets`.
void forwardSolveGroup(const SupernodalFactor& l, const Eigen::SparseMatrix<double>& b,
                       const std::vector<int>& group,
                       std::vector<Eigen::Triplet<double>>& triplets) {
  // active[s]: bit t set when column group[t] reaches supernode s; the reach is closed towards
  // the root, so a walk stops at the first supernode that has the bit already.
  std::vector<std::uint64_t> active(l.supernodes, 0);
  std::vector<int> reach;
  for (std::size_t t = 0; t < group.size(); ++t) {
    const std::uint64_t bit = std::uint64_t{1} << t;
    for (Eigen::SparseMatrix<double>::InnerIterator it(b, group[t]); it; ++it)
      for (int s = l.supernodeOf[l.position[it.row()]]; s >= 0 && !(active[s] & bit);
           s = l.parent[s]) {
        if (!active[s]) reach.push_back(s);
        active[s] |= bit;
      }
  }
  std::sort(reach.begin(), reach.end());  // a parent's index exceeds its children's
  // The reach's rows, supernode after supernode, × the group's columns, dense.
  std::vector<int> offset(l.supernodes, -1);
  int height = 0;
  for (const int s : reach) {
    offset[s] = height;
    height += l.firstColumn[s + 1] - l.firstColumn[s];
  }
  const auto compactRow = [&](int k) {
    const int s = l.supernodeOf[k];
    return offset[s] + k - l.firstColumn[s];
  };
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(height, static_cast<Eigen::Index>(group.size()));
  for (std::size_t t = 0; t < group.size(); ++t)
    for (Eigen::SparseMatrix<double>::InnerIterator it(b, group[t]); it; ++it)
      x(compactRow(l.position[it.row()]), static_cast<Eigen::Index>(t)) += it.value();

  std::vector<int> reaching, below;  // the group's columns that reach s; rows below s in x
  Eigen::MatrixXd y, update;
  for (const int s : reach) {
    const int first = l.firstColumn[s], width = l.firstColumn[s + 1] - first;
    const int rows = l.rowStart[s + 1] - l.rowStart[s];
    const int* row = l.rowIndex + l.rowStart[s];  // row[c] = first + c for c < width
    const Eigen::Map<const Eigen::MatrixXd> block(l.value + l.valueStart[s], rows, width);
    reaching.clear();
    for (std::size_t t = 0; t < group.size(); ++t)
      if (active[s] >> t & 1U) reaching.push_back(static_cast<int>(t));
    // y = L_ss⁻¹ x_s on the columns that reach s, then x_below −= L_below y.
    y.resize(width, static_cast<Eigen::Index>(reaching.size()));
    for (std::size_t q = 0; q < reaching.size(); ++q)
      y.col(static_cast<Eigen::Index>(q)) = x.col(reaching[q]).segment(offset[s], width);
    block.topRows(width).triangularView<Eigen::Lower>().solveInPlace(y);
    for (std::size_t q = 0; q < reaching.size(); ++q)
      x.col(reaching[q]).segment(offset[s], width) = y.col(static_cast<Eigen::Index>(q));
    if (rows == width) continue;
    update.noalias() = block.bottomRows(rows - width) * y;
    below.resize(rows - width);
    for (int i = 0; i < rows - width; ++i) below[i] = compactRow(row[width + i]);
    for (std::size_t q = 0; q < reaching.size(); ++q)
      for (int i = 0; i < rows - width; ++i)
        x(below[i], reaching[q]) -= update(i, static_cast<Eigen::Index>(q));
  }
  for (const int s : reach)
    for (int k = l.firstColumn[s]; k < l.firstColumn[s + 1]; ++k)
      for (std::size_t t = 0; t < group.size(); ++t)
        if (const double value = x(compactRow(k), static_cast<Eigen::Index>(t)); value != 0.0)
          triplets.emplace_back(k, group[t], value);
}

/// The columns of B in groups of up to kForwardGroup that reach similar supernodes: sorted by
/// the first supernode of their rows (CHOLMOD postorders the supernodes, so nearby indices lie
/// in one subtree, and their paths to the root soon merge).
std::vector<std::vector<int>> forwardGroups(const SupernodalFactor& l,
                                            const Eigen::SparseMatrix<double>& b) {
  std::vector<std::pair<int, int>> keyed;  // (first supernode, column)
  for (int j = 0; j < b.cols(); ++j) {
    int first = l.supernodes;
    for (Eigen::SparseMatrix<double>::InnerIterator it(b, j); it; ++it)
      first = std::min(first, l.supernodeOf[l.position[it.row()]]);
    keyed.emplace_back(first, j);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::vector<int>> groups;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i % kForwardGroup == 0) groups.emplace_back();
    groups.back().push_back(keyed[i].second);
  }
  return groups;
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
  // The groups depend on B and the factor only, and each is solved on its own: W does not
  // depend on the thread count.
  const std::vector<std::vector<int>> groups = forwardGroups(l, b);
  std::vector<std::vector<Eigen::Triplet<double>>> triplets(groups.size());
  parallelFor(
      groups.size(), threads,
      [&](std::size_t g) { forwardSolveGroup(l, b, groups[g], triplets[g]); }, 1);
  std::vector<Eigen::Triplet<double>> all;
  for (const auto& part : triplets) all.insert(all.end(), part.begin(), part.end());
  Eigen::SparseMatrix<double> result(l.n, b.cols());
  result.setFromTriplets(all.begin(), all.end());
  return result;
}

Eigen::MatrixXd supernodalInverseForm(const cholmod_factor& factor,
                                      const Eigen::SparseMatrix<double>& b, int threads) {
  const Eigen::SparseMatrix<double> w = supernodalForwardSolve(factor, b, threads);
  return Eigen::MatrixXd(Eigen::SparseMatrix<double>(w.transpose()) * w);
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

LowRankUpdate::LowRankUpdate(const cholmod_factor& factor, Eigen::SparseMatrix<double> u,
                             const Eigen::VectorXd& d, int threads)
    : factor_(factor), u_(std::move(u)) {
  requireRealSupernodalLL(factor, "LowRankUpdate");
  if (u_.rows() != static_cast<Eigen::Index>(factor.n) || d.size() != u_.cols())
    throw std::invalid_argument("LowRankUpdate: U or d has the wrong size");
  if (!(d.array() > 0.0).all())
    throw std::invalid_argument("LowRankUpdate: the update's weights must be positive");
  Eigen::MatrixXd c = supernodalInverseForm(factor, u_, threads);
  c.diagonal() += d.cwiseInverse();
  capacitance_.compute(c);
  if (capacitance_.info() != Eigen::Success)
    throw Error(ErrorCode::NumericalFailure, "a low-rank update of a factorization failed");
}

Eigen::MatrixXd LowRankUpdate::solve(const Eigen::MatrixXd& b, int threads) const {
  Eigen::MatrixXd x = supernodalSolve(factor_, b, threads);
  if (u_.cols() == 0 || b.cols() == 0) return x;
  const Eigen::MatrixXd correction = u_ * capacitance_.solve(Eigen::MatrixXd(u_.transpose() * x));
  return x - supernodalSolve(factor_, correction, threads);
}

}  // namespace hexcover
