#include "core/param/energy_system.h"

#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <optional>
#include <type_traits>

#include "core/common/blas_threads.h"
#include "core/common/error.h"
#include "core/common/sparse_cholesky.h"
#include "core/common/sparse_forward_solve.h"

namespace hexcover::param_detail {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

// A sparse symmetric positive definite factorization that keeps its symbolic analysis across
// refactorizations with the same pattern (new face weights only change values).
class SpdSolver {
 public:
  explicit SpdSolver(LinearSolver kind) : kind_(kind) {
    useSingleThreadedBlas();
    cholmod_.cholmod().print = 0;  // failures are reported through info(), never on stdout
  }

  /// The symbolic analysis (fill-reducing order included) for matrices with the pattern of `a`;
  /// factorize() does it on its first call otherwise.
  void analyze(const SparseMatrix& a) {
    if (kind_ == LinearSolver::Cholmod)
      analyze(cholmod_, a);
    else
      analyze(ldlt_, a);
  }

  void factorize(const SparseMatrix& a) {
    update_.reset();
    if (kind_ == LinearSolver::Cholmod)
      run(cholmod_, a);
    else
      run(ldlt_, a);
  }

  /// Solves from now on with A + U diag(d) Uᵀ, A the last factorized matrix (see LowRankUpdate),
  /// until the next factorize(); false, and nothing changed, without a supernodal factor.
  bool updateLowRank(const SparseMatrix& u, const Eigen::VectorXd& d, int threads) {
    const cholmod_factor* factor = supernodalFactor();
    if (!factor) return false;
    update_.emplace(*factor, u, d, threads);
    return true;
  }

  /// CHOLMOD's supernodal factor of the last factorization (without a low-rank update), null
  /// with SimplicialLDLT.
  const cholmod_factor* supernodalFactor() const {
    const cholmod_factor* factor = kind_ == LinearSolver::Cholmod ? cholmod_.factor() : nullptr;
    return factor && factor->is_super ? factor : nullptr;
  }

  /// A⁻¹ b for one or several right-hand sides, with the last factorization (b itself when
  /// nothing was factorized: the 0×0 system); several on up to `threads` threads.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b, int threads = 1) const {
    if (b.rows() == 0 || b.cols() == 0) return b;
    const cholmod_factor* factor = supernodalFactor();
    Eigen::MatrixXd x = update_                          ? update_->solve(b, threads)
                        : factor && b.cols() > 1         ? supernodalSolve(*factor, b, threads)
                        : kind_ == LinearSolver::Cholmod ? Eigen::MatrixXd(cholmod_.solve(b))
                                                         : Eigen::MatrixXd(ldlt_.solve(b));
    if (!x.allFinite())
      throw Error(ErrorCode::NumericalFailure,
                  "the parameterization solve produced non-finite values");
    return x;
  }

 private:
  template <typename Factorization>
  void analyze(Factorization& factorization, const SparseMatrix& a) {
    // CHOLMOD orders the graph of the vertices, whose u and v columns stay together.
    if constexpr (std::is_same_v<Factorization, CholmodSupernodalFactorization<SparseMatrix>>)
      factorization.analyzePattern(a, blockFillReducingOrder(a, 2));
    else
      factorization.analyzePattern(a);
    analyzed_ = true;
  }

  template <typename Factorization>
  void run(Factorization& factorization, const SparseMatrix& a) {
    if (!analyzed_) analyze(factorization, a);
    factorization.factorize(a);
    if (factorization.info() != Eigen::Success)
      throw Error(ErrorCode::NumericalFailure,
                  "the parameterization system could not be factorized (degenerate mesh or field)");
  }

  LinearSolver kind_;
  bool analyzed_ = false;
  Eigen::SimplicialLDLT<SparseMatrix> ldlt_;
  CholmodSupernodalFactorization<SparseMatrix> cholmod_;
  std::optional<LowRankUpdate> update_;  // of cholmod_'s factor
};

namespace {

// m restricted to the rows and columns `indices`, dense.
Eigen::MatrixXd denseBlock(const SparseMatrix& m, const std::vector<int>& indices) {
  std::vector<int> position(m.rows(), -1);
  for (std::size_t k = 0; k < indices.size(); ++k) position[indices[k]] = static_cast<int>(k);
  Eigen::MatrixXd block = Eigen::MatrixXd::Zero(indices.size(), indices.size());
  for (std::size_t k = 0; k < indices.size(); ++k)
    for (SparseMatrix::InnerIterator it(m, indices[k]); it; ++it)
      if (position[it.row()] >= 0) block(position[it.row()], k) = it.value();
  return block;
}

// The columns `indices` of m, in that order.
SparseMatrix columnsOf(const SparseMatrix& m, const std::vector<int>& indices) {
  if (static_cast<Eigen::Index>(indices.size()) == m.cols() &&
      std::is_sorted(indices.begin(), indices.end()))
    return m;  // all of them
  SparseMatrix out(m.rows(), static_cast<Eigen::Index>(indices.size()));
  std::vector<Triplet> triplets;
  for (std::size_t k = 0; k < indices.size(); ++k)
    for (SparseMatrix::InnerIterator it(m, indices[k]); it; ++it)
      triplets.emplace_back(static_cast<int>(it.row()), static_cast<int>(k), it.value());
  out.setFromTriplets(triplets.begin(), triplets.end());
  return out;
}

// The least squares' row groups for the normal equations: each face's rows, then each
// crease edge's.
std::vector<int> rowGroups(const LeastSquares& ls) {
  std::vector<int> start;
  const int faceRows = kRowsPerFace * static_cast<int>(ls.faceArea.size());
  for (int row = 0; row < faceRows; row += kRowsPerFace) start.push_back(row);
  for (int row = faceRows; row < ls.target.size(); row += kRowsPerCrease) start.push_back(row);
  if (start.empty()) start.push_back(0);
  return start;
}

}  // namespace

EnergySystem::EnergySystem(const LeastSquares& ls, int realCount,
                           std::vector<std::vector<int>> integerGroups, LinearSolver kind,
                           int threads)
    : ls_(ls),
      normal_(ls.gradient, rowGroups(ls), static_cast<int>(ls.gradient.cols()) - realCount),
      realCount_(realCount),
      groups_(std::move(integerGroups)),
      threads_(threads),
      solver_(std::make_unique<SpdSolver>(kind)) {
  std::size_t integers = 0;  // the groups partition the integer unknowns
  for (const auto& group : groups_) integers += group.size();
  groupOf_.resize(integers);
  localIndex_.resize(integers);
  for (std::size_t g = 0; g < groups_.size(); ++g)
    for (std::size_t k = 0; k < groups_[g].size(); ++k) {
      groupOf_[groups_[g][k]] = static_cast<int>(g);
      localIndex_[groups_[g][k]] = static_cast<int>(k);
    }
}

EnergySystem::~EnergySystem() = default;

void EnergySystem::analyze() {
  if (realCount_ > 0) solver_->analyze(realBlock(normal_.pattern()));
}

void EnergySystem::setFaceWeights(const Eigen::VectorXd& faceWeight, bool integersFree) {
  const Eigen::VectorXd rowWeight = rowWeights(faceWeight);
  const Eigen::VectorXd b = ls_.gradient.transpose() * rowWeight.cwiseProduct(ls_.target);
  const int r = realCount_;
  responses_.resize(0, 0);  // solved for the previous weights
  solvedResponses_.clear();
  if (!integersFree && updateFactor(rowWeight)) {
    z_ = solver_->solve(b.head(r));
    return;
  }
  // With the integers fixed, A_ii is not read.
  const SparseMatrix a = normal_.assemble(
      rowWeight, threads_,
      integersFree ? NormalEquations::DenseBlock::Summed : NormalEquations::DenseBlock::Skipped);
  const int k = static_cast<int>(a.cols()) - realCount_;
  ari_ = a.topRightCorner(r, k);
  z_ = b.head(r);
  if (r > 0) {  // r = 0 when every vertex is singular (a minimal cube)
    solver_->factorize(realBlock(a));
    factorRowWeight_ = rowWeight;
    factorAri_ = ari_;
    z_ = solver_->solve(z_);
  }
  if (!integersFree) return;
  c_ = b.tail(k) - ari_.transpose() * z_;
  schur_.clear();
  const SparseMatrix aii = a.bottomRightCorner(k, k);
  for (const auto& group : groups_) schur_.push_back(denseBlock(aii, group));
  if (r == 0 || k == 0) return;
  const cholmod_factor* factor = solver_->supernodalFactor();
  constexpr int kBlock = 64;
  constexpr double kResponseBudget = 32e6;  // 256 MB
  const bool keep = !factor && static_cast<double>(r) * k <= kResponseBudget;
  if (keep) responses_.resize(r, k);
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const SparseMatrix arig = columnsOf(ari_, groups_[g]);
    if (factor) {
      schur_[g] -= supernodalInverseForm(*factor, arig, threads_);
      continue;
    }
    const int width = static_cast<int>(groups_[g].size());
    for (int first = 0; first < width; first += kBlock) {
      const int count = std::min(kBlock, width - first);
      const Eigen::MatrixXd y = solver_->solve(Eigen::MatrixXd(arig.middleCols(first, count)));
      schur_[g].middleCols(first, count) -= arig.transpose() * y;
      if (keep)
        for (int q = 0; q < count; ++q) responses_.col(groups_[g][first + q]) = y.col(q);
    }
  }
}

Eigen::VectorXd EnergySystem::solveIntegers(const std::vector<bool>& fixed,
                                            const Eigen::VectorXd& values) const {
  Eigen::VectorXd x = values;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const auto& group = groups_[g];
    const Eigen::MatrixXd& s = schur_[g];
    std::vector<int> free, held;  // indices into the group
    for (std::size_t j = 0; j < group.size(); ++j)
      (fixed[group[j]] ? held : free).push_back(static_cast<int>(j));
    if (free.empty()) continue;
    Eigen::MatrixXd sff(free.size(), free.size());
    Eigen::VectorXd rhs(free.size());
    for (std::size_t p = 0; p < free.size(); ++p) {
      rhs[p] = c_[group[free[p]]];
      for (const int h : held) rhs[p] -= s(free[p], h) * values[group[h]];
      for (std::size_t q = 0; q < free.size(); ++q) sff(p, q) = s(free[p], free[q]);
    }
    const Eigen::VectorXd xf = sff.ldlt().solve(rhs);
    if (!xf.allFinite())
      throw Error(ErrorCode::NumericalFailure, "the parameterization's integer system is singular");
    for (std::size_t p = 0; p < free.size(); ++p) x[group[free[p]]] = xf[p];
  }
  return x;
}

int EnergySystem::descendIntegers(const std::vector<std::vector<int>>& units, int n,
                                  Eigen::VectorXd& xi) const {
  const std::vector<Eigen::Vector2d> pairMoves =
      n == 6 ? std::vector<Eigen::Vector2d>{{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}}
             : std::vector<Eigen::Vector2d>{{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  const std::vector<Eigen::Vector2d> scalarMoves = {{1, 0}, {-1, 0}};
  Eigen::VectorXd gradient(xi.size());
  double energy = 0.0;  // x_iᵀ S x_i
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const Eigen::VectorXd xg = xi(groups_[g]);
    const Eigen::VectorXd sx = schur_[g] * xg;
    gradient(groups_[g]) = sx - c_(groups_[g]);
    energy += xg.dot(sx);
  }
  const double tolerance = 1e-12 * (1.0 + std::abs(energy));  // round-off guard
  int moves = 0;
  constexpr int kMaxPasses = 50;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    bool moved = false;
    for (const auto& unit : units) {
      double bestChange = -tolerance;
      const Eigen::Vector2d* best = nullptr;
      for (const auto& move : unit.size() == 2 ? pairMoves : scalarMoves) {
        double change = 0.0;
        for (std::size_t a = 0; a < unit.size(); ++a) {
          change += 2.0 * move[a] * gradient[unit[a]];
          for (std::size_t b = 0; b < unit.size(); ++b)
            change += move[a] * move[b] * schurEntry(unit[a], unit[b]);
        }
        if (change < bestChange) {
          bestChange = change;
          best = &move;
        }
      }
      if (!best) continue;
      for (std::size_t a = 0; a < unit.size(); ++a) {
        xi[unit[a]] += (*best)[a];
        const int g = groupOf_[unit[a]];
        gradient(groups_[g]) += (*best)[a] * schur_[g].col(localIndex_[unit[a]]);
      }
      ++moves;
      moved = true;
    }
    if (!moved) break;
  }
  return moves;
}

Eigen::VectorXd EnergySystem::withReals(const Eigen::VectorXd& integers) const {
  Eigen::VectorXd x(realCount_ + integers.size());
  if (integers.size() == 0)
    x.head(realCount_) = z_;
  else if (responses_.cols() == integers.size())
    x.head(realCount_) = z_ - responses_ * integers;
  else
    x.head(realCount_) = z_ - solver_->solve(ari_ * integers);
  x.tail(integers.size()) = integers;
  return x;
}

namespace {
constexpr double kResponseCacheBudget = 8e6;  // doubles: 64 MB
}  // namespace

std::size_t EnergySystem::responseCapacity() const {
  return realCount_ > 0 ? static_cast<std::size_t>(kResponseCacheBudget / realCount_) : 0;
}

std::vector<const Eigen::VectorXd*> EnergySystem::realResponses(const std::vector<int>& columns) {
  std::vector<int> unsolved;
  for (const int column : columns)
    if (!solvedResponses_.count(column) &&
        std::find(unsolved.begin(), unsolved.end(), column) == unsolved.end())
      unsolved.push_back(column);
  const auto doubles = [&](std::size_t count) { return static_cast<double>(count) * realCount_; };
  if (doubles(solvedResponses_.size() + unsolved.size()) > kResponseCacheBudget)
    for (auto it = solvedResponses_.begin(); it != solvedResponses_.end();)
      it = std::find(columns.begin(), columns.end(), it->first) == columns.end()
               ? solvedResponses_.erase(it)
               : std::next(it);
  if (!unsolved.empty()) {
    Eigen::MatrixXd y(realCount_, unsolved.size());
    if (responses_.cols() > 0) {
      for (std::size_t i = 0; i < unsolved.size(); ++i)
        y.col(i) = responses_.col(unsolved[i] - realCount_);
    } else {
      for (std::size_t i = 0; i < unsolved.size(); ++i)
        y.col(i) = ari_.col(unsolved[i] - realCount_);
      y = solver_->solve(y, threads_);
    }
    for (std::size_t i = 0; i < unsolved.size(); ++i) solvedResponses_[unsolved[i]] = -y.col(i);
  }
  std::vector<const Eigen::VectorXd*> result;
  for (const int column : columns) result.push_back(&solvedResponses_.at(column));
  return result;
}

double EnergySystem::energy(const Eigen::VectorXd& x) const {
  const Eigen::VectorXd residual = ls_.gradient * x - ls_.target;
  return rowWeights(Eigen::VectorXd::Ones(ls_.faceArea.size())).dot(residual.cwiseAbs2());
}

bool EnergySystem::updateFactor(const Eigen::VectorXd& rowWeight) {
  constexpr std::size_t kMaxUpdatedRows = 256;
  if (realCount_ == 0 || factorRowWeight_.size() != rowWeight.size()) return false;
  std::vector<int> changed;
  for (Eigen::Index row = 0; row < rowWeight.size(); ++row) {
    if (rowWeight[row] == factorRowWeight_[row]) continue;
    if (rowWeight[row] < factorRowWeight_[row] || changed.size() == kMaxUpdatedRows) return false;
    changed.push_back(static_cast<int>(row));
  }
  const auto& a = normal_.matrix();
  const int k = static_cast<int>(a.cols()) - realCount_;
  std::vector<Eigen::Triplet<double>> real, integer;
  Eigen::VectorXd d(static_cast<Eigen::Index>(changed.size()));
  for (std::size_t q = 0; q < changed.size(); ++q) {
    const int row = changed[q];
    d[static_cast<Eigen::Index>(q)] = rowWeight[row] - factorRowWeight_[row];
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(a, row); it; ++it)
      (it.col() < realCount_ ? real : integer)
          .emplace_back(it.col() < realCount_ ? it.col() : it.col() - realCount_, q, it.value());
  }
  SparseMatrix ur(realCount_, d.size()), ui(k, d.size());
  ur.setFromTriplets(real.begin(), real.end());
  ui.setFromTriplets(integer.begin(), integer.end());
  if (!solver_->updateLowRank(ur, d, threads_)) return false;
  ari_ = factorAri_ + SparseMatrix(ur * d.asDiagonal() * SparseMatrix(ui.transpose()));
  return true;
}

SparseMatrix EnergySystem::realBlock(const SparseMatrix& a) const {
  SparseMatrix arr = a.topLeftCorner(realCount_, realCount_);
  const double regularization = 1e-14 * arr.diagonal().cwiseAbs().maxCoeff();
  for (int j = 0; j < realCount_; ++j) arr.coeffRef(j, j) += regularization;
  return arr;
}

Eigen::VectorXd EnergySystem::rowWeights(const Eigen::VectorXd& faceWeight) const {
  Eigen::VectorXd w(ls_.target.size());
  for (Eigen::Index f = 0; f < ls_.faceArea.size(); ++f)
    w.segment<kRowsPerFace>(kRowsPerFace * f).setConstant(ls_.faceArea[f] * faceWeight[f]);
  w.tail(ls_.rowWeight.size()) = ls_.rowWeight;
  return w;
}

double EnergySystem::schurEntry(int a, int b) const {
  const int g = groupOf_[a];
  return groupOf_[b] == g ? schur_[g](localIndex_[a], localIndex_[b]) : 0.0;
}

}  // namespace hexcover::param_detail
