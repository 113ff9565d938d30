#pragma once
// Internal to core/param: the normal equations of energy (4) (energy.h) with per-face weights,
// solved for the integer unknowns on the Schur complement.
//
// The normal equations AᵀWA x = AᵀW f split into the real columns r (vertex coordinates, many)
// and the integer columns i (few):
//   [A_rr A_ri; A_ir A_ii] [x_r; x_i] = [b_r; b_i].
// A_rr is factorized once per set of weights; the integer unknowns are solved on the dense Schur
// complement S = A_ii − A_ir A_rr⁻¹ A_ri, c = b_i − A_ir A_rr⁻¹ b_r, so the local solve, every
// greedy rounding step and the final solve cost back-substitutions instead of factorizations.
// S is kept as its diagonal blocks over independent groups of integer unknowns (integerGroups:
// one per mesh component), the only nonzero ones.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <map>
#include <memory>
#include <vector>

#include "core/common/normal_equations.h"
#include "core/param/energy.h"
#include "core/param/hexcover.h"

namespace hexcover::param_detail {

class SpdSolver;

class EnergySystem {
 public:
  /// The system of `ls` with `realCount` real columns first; `integerGroups` partitions the
  /// integer unknowns (counted from 0) into groups that no face couples. The assembly, the
  /// forward solve and the responses run on up to `threads` threads.
  EnergySystem(const LeastSquares& ls, int realCount, std::vector<std::vector<int>> integerGroups,
               LinearSolver kind, int threads);
  ~EnergySystem();
  EnergySystem(const EnergySystem&) = delete;
  EnergySystem& operator=(const EnergySystem&) = delete;

  /// The symbolic analysis of A_rr, which depends on the pattern only: it can run before the
  /// targets and weights are known (setFaceWeights does it otherwise).
  void analyze();

  /// Assembles and factorizes the system for the face weights (#F, > 0); with
  /// `integersFree` also the Schur complement that solveIntegers needs. Without it, weights that
  /// differ from the factorized ones in a few rows, each raised (the crease rows of the final
  /// solve), update the factorization instead (see updateFactor).
  void setFaceWeights(const Eigen::VectorXd& faceWeight, bool integersFree);

  /// Integer unknowns (#i) of the minimizer with x_i[j] = values[j] where fixed[j] (integer
  /// columns counted from 0).
  Eigen::VectorXd solveIntegers(const std::vector<bool>& fixed,
                                const Eigen::VectorXd& values) const;

  /// Lattice descent on the rounded integer unknowns xi (#i): moves one rounding unit (integer
  /// indices) to a neighbouring lattice point (for a pair: the 6 unit Eisenstein or 4 Gauss
  /// steps; for a scalar: ±1) while that lowers the energy with the reals minimized out,
  /// E(x_i) = x_iᵀ S x_i − 2 cᵀ x_i + const, whose change for a move d is 2 dᵀ(S x_i − c) + dᵀ S d.
  /// Returns the number of moves made.
  int descendIntegers(const std::vector<std::vector<int>>& units, int n, Eigen::VectorXd& xi) const;

  /// The whole minimizer for given integer unknowns: x_r = A_rr⁻¹ (b_r − A_ri x_i).
  Eigen::VectorXd withReals(const Eigen::VectorXd& integers) const;

  /// For each integer column j = columns[k] (counted over all columns): the real unknowns' part
  /// of ∂x/∂x_j for the minimizer with every integer unknown fixed, −A_rr⁻¹ A_ri e_j (its
  /// integer part is e_j): changing x_j by δ moves the minimizer by δ times this. Read from the
  /// kept columns of A_rr⁻¹ A_ri, else solved with the last factorization. The solved columns
  /// are kept until the weights change, within kResponseCacheBudget doubles (those of this call
  /// always); the pointers stay valid until the next call.
  std::vector<const Eigen::VectorXd*> realResponses(const std::vector<int>& columns);
  /// How many columns realResponses keeps at most (kResponseCacheBudget doubles).
  std::size_t responseCapacity() const;

  /// Σ_f A_f |rows_f x − target_f|² (energy (4) plus the anisotropy rows, unit face weights)
  /// plus the crease rows at their weights.
  double energy(const Eigen::VectorXd& x) const;

 private:
  using SparseMatrix = Eigen::SparseMatrix<double>;

  /// Takes the row weights `rowWeight` by a low-rank update of the last factorization when they
  /// differ from its weights in at most kMaxUpdatedRows rows, each raised: for the raises d of
  /// rows U of A (their real columns U_r, integer columns U_i), A_rr + U_rᵀ D U_r is solved by
  /// Sherman–Morrison–Woodbury (LowRankUpdate: two back-substitutions per solve instead of an
  /// assembly and a factorization; the final solve of the 1.1M-face bunny, whose 50 crease edges
  /// add 100 rows, takes 2.4 s instead of 6.0-6.8 s) and A_ri += U_rᵀ D U_i. False, and nothing
  /// changed, otherwise.
  bool updateFactor(const Eigen::VectorXd& rowWeight);

  /// A_rr of the normal matrix `a`, with a relative 1e-14 on its diagonal (a pattern, of zeros,
  /// keeps its values).
  SparseMatrix realBlock(const SparseMatrix& a) const;

  Eigen::VectorXd rowWeights(const Eigen::VectorXd& faceWeight) const;

  /// S_ab (integer unknowns a and b): 0 across groups.
  double schurEntry(int a, int b) const;

  const LeastSquares& ls_;
  NormalEquations normal_;  ///< AᵀWA for the face weights of each solve (integers: dense block)
  int realCount_;
  std::vector<std::vector<int>> groups_;   ///< independent groups of integer unknowns
  std::vector<int> groupOf_, localIndex_;  ///< per integer unknown: its group, its index there
  int threads_;                            ///< of the assembly, the forward solve and the responses
  std::unique_ptr<SpdSolver> solver_;
  SparseMatrix ari_;                    ///< A_ri
  Eigen::VectorXd factorRowWeight_;     ///< the row weights of the last factorization
  SparseMatrix factorAri_;              ///< and its A_ri
  Eigen::VectorXd z_;                   ///< A_rr⁻¹ b_r
  std::vector<Eigen::MatrixXd> schur_;  ///< S's diagonal blocks, one per group
  Eigen::MatrixXd responses_;  ///< A_rr⁻¹ A_ri for the current weights (empty: not kept)
  std::map<int, Eigen::VectorXd> solvedResponses_;  ///< columns of realResponses for these weights
  Eigen::VectorXd c_;                               ///< c
};

}  // namespace hexcover::param_detail
