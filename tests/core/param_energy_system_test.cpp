// The parameterization's linear algebra (core/param/energy_system.h) against a direct solve of
// the whole normal equations: the integer unknowns solved on the Schur complement, free or partly
// held, and the real unknowns recovered from them, are the minimizer of energy (4).

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <vector>

#include "core/param/cut_graph.h"
#include "core/param/cut_mesh.h"
#include "core/param/energy.h"
#include "core/param/energy_system.h"
#include "tests/common/prescribed_fields.h"

namespace hexcover {
namespace {

using namespace param_detail;

/// Energy (4) of an icosphere along the icosahedral field (12 singularities: integer unknowns
/// for their lattice positions and for the cut edges' translations).
struct IcosphereEnergy {
  TriMesh mesh = makeIcosphere(2);
  RosyField field = test::icosahedralField(mesh);
  CutGraph cut = computeCutGraph(mesh, field);
  CutMesh cm = buildCutMesh(mesh, cut);
  Unknowns unknowns = buildUnknowns(mesh, cm, 6);
  FaceGeometry geometry = computeFaceGeometry(mesh, field, cut);
  LeastSquares ls = buildLeastSquares(mesh, cm, unknowns, geometry, 1.0, {});

  IcosphereEnergy() {
    std::vector<CreaseEdge> none;
    setLatticeScale(std::vector<double>(mesh.n_faces(), 1.0 / 0.2), 0.0, none, ls);
  }

  /// Face weights that differ from face to face (between 1 and 4).
  Eigen::VectorXd faceWeights() const {
    Eigen::VectorXd w(mesh.n_faces());
    for (Eigen::Index f = 0; f < w.size(); ++f) w[f] = 1.0 + 3.0 * ((f * 7919) % 101) / 100.0;
    return w;
  }

  /// The minimizer of Σ_f A_f w_f |rows_f x − target_f|² with the columns `held` at `values`,
  /// by a sparse LDLᵀ of the normal equations over the other columns.
  Eigen::VectorXd directMinimizer(const Eigen::VectorXd& faceWeight, const std::vector<bool>& held,
                                  const Eigen::VectorXd& values) const {
    const int columns = unknowns.columns();
    Eigen::VectorXd rowWeight(ls.target.size());
    for (Eigen::Index f = 0; f < faceWeight.size(); ++f)
      rowWeight.segment<kRowsPerFace>(kRowsPerFace * f).setConstant(ls.faceArea[f] * faceWeight[f]);
    std::vector<int> freeColumn(columns, -1);
    int free = 0;
    for (int j = 0; j < columns; ++j)
      if (!held[j]) freeColumn[j] = free++;
    Eigen::SparseMatrix<double> a(ls.target.size(), free);
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::VectorXd rhs = ls.target;
    for (int j = 0; j < columns; ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(ls.gradient, j); it; ++it) {
        if (held[j])
          rhs[it.row()] -= it.value() * values[j];
        else
          triplets.emplace_back(static_cast<int>(it.row()), freeColumn[j], it.value());
      }
    a.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::SparseMatrix<double> normal =
        Eigen::SparseMatrix<double>(a.transpose()) * rowWeight.asDiagonal() * a;
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
    EXPECT_EQ(solver.info(), Eigen::Success);
    const Eigen::VectorXd y = solver.solve(a.transpose() * rowWeight.cwiseProduct(rhs));
    Eigen::VectorXd x = values;
    for (int j = 0; j < columns; ++j)
      if (!held[j]) x[j] = y[freeColumn[j]];
    return x;
  }
};

TEST(ParamEnergySystem, SchurComplementSolveIsTheMinimizerOfTheWholeSystem) {
  const IcosphereEnergy problem;
  const Unknowns& u = problem.unknowns;
  ASSERT_GT(u.integerCount, 10);
  EnergySystem system(problem.ls, u.realCount,
                      integerGroups(problem.mesh, problem.cut, problem.cm, u),
                      LinearSolver::Cholmod, 2);
  const Eigen::VectorXd weights = problem.faceWeights();
  system.setFaceWeights(weights, true);

  // Every unknown free (the local step).
  const Eigen::VectorXd local = system.withReals(system.solveIntegers(
      std::vector<bool>(u.integerCount, false), Eigen::VectorXd::Zero(u.integerCount)));
  const Eigen::VectorXd direct = problem.directMinimizer(
      weights, std::vector<bool>(u.columns(), false), Eigen::VectorXd::Zero(u.columns()));
  EXPECT_LT((local - direct).norm(), 1e-8 * direct.norm());

  // Every other integer unknown held at its rounded value, the rest free (a greedy round).
  std::vector<bool> heldIntegers(u.integerCount, false), held(u.columns(), false);
  Eigen::VectorXd values = Eigen::VectorXd::Zero(u.columns());
  for (int j = 0; j < u.integerCount; j += 2) {
    heldIntegers[j] = held[u.realCount + j] = true;
    values[u.realCount + j] = std::round(local[u.realCount + j]);
  }
  const Eigen::VectorXd partly =
      system.withReals(system.solveIntegers(heldIntegers, values.tail(u.integerCount)));
  const Eigen::VectorXd partlyDirect = problem.directMinimizer(weights, held, values);
  EXPECT_LT((partly - partlyDirect).norm(), 1e-8 * partlyDirect.norm());

  // energy(): Σ_f A_f |rows_f x − target_f|² at unit face weights.
  const Eigen::VectorXd residual = problem.ls.gradient * partly - problem.ls.target;
  double energy = 0.0;
  for (Eigen::Index f = 0; f < problem.ls.faceArea.size(); ++f)
    energy +=
        problem.ls.faceArea[f] * residual.segment<kRowsPerFace>(kRowsPerFace * f).squaredNorm();
  EXPECT_NEAR(system.energy(partly), energy, 1e-10 * energy);
}

}  // namespace
}  // namespace hexcover
