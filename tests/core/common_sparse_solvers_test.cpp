// The sparse solvers of core/common: Cholesky with a shared elimination order, the supernodal
// forward solve with sparse right-hand sides behind the parameterization's Schur complement, the
// dense solve split by columns, the solve after a low-rank update, and the normal equations of
// its least squares; the OpenMP regions of CHOLMOD run as plain calls.

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "core/common/blas_threads.h"
#include "core/common/normal_equations.h"
#include "core/common/sparse_cholesky.h"
#include "core/common/sparse_forward_solve.h"

namespace hexcover {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

/// Edges of a side × side grid graph (4-neighbours).
std::vector<std::pair<int, int>> gridEdges(int side) {
  std::vector<std::pair<int, int>> edges;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      if (x + 1 < side) edges.emplace_back(y * side + x, y * side + x + 1);
      if (y + 1 < side) edges.emplace_back(y * side + x, (y + 1) * side + x);
    }
  return edges;
}

/// Graph Laplacian plus `shift` on the diagonal, with varying edge weights (SPD).
SparseMatrix shiftedLaplacian(int nodes, const std::vector<std::pair<int, int>>& edges,
                              double shift) {
  std::vector<Eigen::Triplet<double>> triplets;
  std::vector<double> diagonal(nodes, shift);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto [a, b] = edges[e];
    const double w = 1.0 + 0.5 * static_cast<double>(e % 7);
    triplets.emplace_back(a, b, -w);
    triplets.emplace_back(b, a, -w);
    diagonal[a] += w;
    diagonal[b] += w;
  }
  for (int i = 0; i < nodes; ++i) triplets.emplace_back(i, i, diagonal[i]);
  SparseMatrix m(nodes, nodes);
  m.setFromTriplets(triplets.begin(), triplets.end());
  return m;
}

class SimplicialFactor : public Eigen::CholmodSimplicialLLT<SparseMatrix> {
 public:
  const cholmod_factor& factor() const { return *m_cholmodFactor; }
};

TEST(SingleThreadedBlas, RunsTheLibrariesParallelRegionsAsPlainCalls) {
  useSingleThreadedBlas();
  // libgomp is loaded through CHOLMOD; its omp_get_level() counts the enclosing regions, inactive
  // ones too.
  using Level = int (*)();
  const auto level = reinterpret_cast<Level>(dlsym(RTLD_DEFAULT, "omp_get_level"));
  ASSERT_NE(level, nullptr) << "libgomp is not loaded";
  // GOMP_parallel as CHOLMOD's calls find it runs a region's body once, on the calling thread,
  // for any thread count asked, without opening a region (libgomp's would: level 1).
  struct Calls {
    Level level = nullptr;
    int count = 0;
    int levelInside = -1;
    std::thread::id thread;
  } calls;
  calls.level = level;
  const auto found = reinterpret_cast<void (*)(void (*)(void*), void*, unsigned, unsigned)>(
      dlsym(RTLD_DEFAULT, "GOMP_parallel"));
  ASSERT_NE(found, nullptr);
  found(
      [](void* data) {
        auto& c = *static_cast<Calls*>(data);
        ++c.count;
        c.levelInside = c.level();
        c.thread = std::this_thread::get_id();
      },
      &calls, 4, 0);
  EXPECT_EQ(calls.count, 1);
  EXPECT_EQ(calls.levelInside, 0);
  EXPECT_EQ(calls.thread, std::this_thread::get_id());
}

TEST(MinimumDegreeOrder, IsAPermutationOfTheNodes) {
  const int side = 30;
  std::vector<int> order = minimumDegreeOrder(side * side, gridEdges(side));
  std::sort(order.begin(), order.end());
  for (int i = 0; i < side * side; ++i) ASSERT_EQ(order[i], i);
}

TEST(SparseCholesky, RowsNumberedAlongASharedOrderGiveTheSameSolution) {
  const int side = 40, n = side * side;
  const auto edges = gridEdges(side);
  const std::vector<int> order = minimumDegreeOrder(n, edges);
  std::vector<int> renumber(n);
  for (int k = 0; k < n; ++k) renumber[order[k]] = k;
  std::vector<std::pair<int, int>> renumbered;
  for (const auto& [a, b] : edges) renumbered.emplace_back(renumber[a], renumber[b]);
  const SparseMatrix a = shiftedLaplacian(n, edges, 0.01);
  const SparseMatrix ordered =
      shiftedLaplacian(n, renumbered, 0.01);  // the same matrix, renumbered
  Eigen::VectorXd b(n), orderedB(n);
  for (int i = 0; i < n; ++i) b[i] = std::sin(0.37 * i);
  for (int i = 0; i < n; ++i) orderedB[renumber[i]] = b[i];

  const SparseCholesky<double> reordered(a, RowOrder::Reorder);
  const SparseCholesky<double> given(ordered, RowOrder::AsGiven);
  ASSERT_TRUE(reordered.ok());
  ASSERT_TRUE(given.ok());
  const Eigen::VectorXd x = reordered.solve(b), orderedX = given.solve(orderedB);
  EXPECT_LT((a * x - b).norm(), 1e-9 * b.norm());
  for (int i = 0; i < n; ++i)
    ASSERT_NEAR(orderedX[renumber[i]], x[i], 1e-9 * x.cwiseAbs().maxCoeff());
}

TEST(SupernodalForwardSolve, GivesTheSchurComplementAndStaysSparse) {
  const int side = 60, n = side * side, columns = 12;
  const SparseMatrix a = shiftedLaplacian(n, gridEdges(side), 1e-3);
  // Columns with a few nonzeros each, like the integer unknowns' couplings to a few vertices.
  std::vector<Eigen::Triplet<double>> triplets;
  for (int j = 0; j < columns; ++j)
    for (int t = 0; t < 3; ++t) triplets.emplace_back((j * 977 + t * 61) % n, j, 1.0 + t - 0.3 * j);
  SparseMatrix b(n, columns);
  b.setFromTriplets(triplets.begin(), triplets.end());

  CholmodSupernodalFactorization<SparseMatrix> cholesky;
  cholesky.compute(a);
  ASSERT_EQ(cholesky.info(), Eigen::Success);
  ASSERT_NE(cholesky.factor(), nullptr);
  ASSERT_TRUE(cholesky.factor()->is_super);
  const SparseMatrix w = supernodalForwardSolve(*cholesky.factor(), b);
  const Eigen::MatrixXd schur = Eigen::MatrixXd(SparseMatrix(w.transpose()) * w);
  const Eigen::MatrixXd expected =
      Eigen::MatrixXd(b).transpose() * cholesky.solve(Eigen::MatrixXd(b));
  EXPECT_LT((schur - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff());
  // Only the elimination-tree paths are touched: far fewer than n entries per column.
  EXPECT_LT(w.nonZeros(), static_cast<Eigen::Index>(columns) * n / 4);

  // The columns split between threads: the same W, to the last bit.
  for (const int threads : {2, 3, 16}) {
    const SparseMatrix split = supernodalForwardSolve(*cholesky.factor(), b, threads);
    ASSERT_EQ(split.nonZeros(), w.nonZeros()) << threads << " threads";
    EXPECT_EQ(Eigen::MatrixXd(split), Eigen::MatrixXd(w)) << threads << " threads";
  }
}

TEST(SupernodalForwardSolve, SolvesManyColumnsInGroupsOfDifferentReach) {
  // More columns than a group holds, on rows all over the grid: groups whose columns reach
  // different supernodes, single-row and empty columns among them.
  const int side = 70, n = side * side, columns = 150;
  const SparseMatrix a = shiftedLaplacian(n, gridEdges(side), 1e-2);
  std::vector<Eigen::Triplet<double>> triplets;
  for (int j = 0; j < columns; ++j) {
    if (j % 37 == 5) continue;  // empty
    const int count = 1 + j % 3;
    for (int t = 0; t < count; ++t)
      triplets.emplace_back((j * 7919 + t * 131) % n, j, 1.0 + 0.1 * t - 0.01 * j);
  }
  SparseMatrix b(n, columns);
  b.setFromTriplets(triplets.begin(), triplets.end());
  CholmodSupernodalFactorization<SparseMatrix> cholesky;
  cholesky.compute(a);
  ASSERT_EQ(cholesky.info(), Eigen::Success);
  const SparseMatrix w = supernodalForwardSolve(*cholesky.factor(), b, 2);
  const Eigen::MatrixXd expected =
      Eigen::MatrixXd(b).transpose() * cholesky.solve(Eigen::MatrixXd(b));
  EXPECT_LT((supernodalInverseForm(*cholesky.factor(), b, 2) - expected).cwiseAbs().maxCoeff(),
            1e-9 * expected.cwiseAbs().maxCoeff());
  for (int j = 5; j < columns; j += 37) EXPECT_EQ(w.col(j).nonZeros(), 0) << "column " << j;
  EXPECT_EQ(Eigen::MatrixXd(supernodalForwardSolve(*cholesky.factor(), b, 1)), Eigen::MatrixXd(w));
}

TEST(LowRankUpdate, SolvesTheUpdatedMatrixWithoutRefactorizing) {
  const int side = 40, n = side * side, rank = 9;
  const SparseMatrix a0 = shiftedLaplacian(n, gridEdges(side), 1e-3);
  // U: rows of two or three entries, like the crease rows of the parameterization; one empty.
  std::vector<Eigen::Triplet<double>> triplets;
  for (int q = 0; q < rank; ++q)
    if (q != 4)
      for (int t = 0; t < 2 + q % 2; ++t)
        triplets.emplace_back((q * 613 + t * 17) % n, q, t == 0 ? 1.0 : -0.5 * t);
  SparseMatrix u(n, rank);
  u.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::VectorXd d(rank);
  for (int q = 0; q < rank; ++q) d[q] = std::pow(10.0, q % 5 - 1);  // 0.1 to 1000
  const SparseMatrix a = a0 + SparseMatrix(u * d.asDiagonal() * SparseMatrix(u.transpose()));

  CholmodSupernodalFactorization<SparseMatrix> factor0;
  factor0.compute(a0);
  ASSERT_EQ(factor0.info(), Eigen::Success);
  Eigen::MatrixXd b(n, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < n; ++i) b(i, j) = std::sin(0.13 * i + j) + (i == 613 ? 3.0 : 0.0);
  const LowRankUpdate updated(*factor0.factor(), u, d);
  const Eigen::MatrixXd x = updated.solve(b);
  EXPECT_LT((a * x - b).norm(), 1e-9 * b.norm());
  // Not the solution of the matrix without the update.
  EXPECT_GT((a * factor0.solve(b) - b).norm(), 1e-3 * b.norm());
  EXPECT_EQ(updated.solve(b, 2), x);
  EXPECT_LT((updated.solve(b.col(1)) - x.col(1)).cwiseAbs().maxCoeff(),
            1e-12 * x.cwiseAbs().maxCoeff());

  // No columns: the solve of A₀ itself.
  const LowRankUpdate none(*factor0.factor(), SparseMatrix(n, 0), Eigen::VectorXd(0));
  EXPECT_LT((a0 * none.solve(b) - b).norm(), 1e-9 * b.norm());

  EXPECT_THROW(LowRankUpdate(*factor0.factor(), u, -d), std::invalid_argument);
  EXPECT_THROW(LowRankUpdate(*factor0.factor(), SparseMatrix(n + 1, rank), d),
               std::invalid_argument);
}

TEST(SupernodalSolve, SolvesManyRightHandSidesTheSameOnAnyThreadCount) {
  const int side = 50, n = side * side, columns = 11;
  const SparseMatrix a = shiftedLaplacian(n, gridEdges(side), 1e-3);
  Eigen::MatrixXd b(n, columns);
  for (int j = 0; j < columns; ++j)
    for (int i = 0; i < n; ++i) b(i, j) = std::sin(0.37 * i + 1.3 * j) + (i == 97 * j ? 5.0 : 0.0);
  CholmodSupernodalFactorization<SparseMatrix> cholesky;
  cholesky.compute(a);
  ASSERT_EQ(cholesky.info(), Eigen::Success);
  const Eigen::MatrixXd x = supernodalSolve(*cholesky.factor(), b);
  ASSERT_EQ(x.rows(), n);
  ASSERT_EQ(x.cols(), columns);
  EXPECT_LT((a * x - b).cwiseAbs().maxCoeff(), 1e-9 * b.cwiseAbs().maxCoeff());
  // The blocks of columns do not depend on the thread count: the same bits.
  for (const int threads : {2, 3}) EXPECT_EQ(supernodalSolve(*cholesky.factor(), b, threads), x);
  // A single column is one block.
  EXPECT_EQ(supernodalSolve(*cholesky.factor(), b.col(4), 2),
            Eigen::MatrixXd(cholesky.solve(b.col(4))));
}

/// `normal`, built from `a` with a dense block of its last `denseColumns` columns, against the
/// product (√W A)ᵀ(√W A) for two weightings: the same values to the last bit, for any thread
/// count, on the places of its pattern(); without the block's sums, 0 there and the same
/// elsewhere.
void checkNormalEquations(const SparseMatrix& a, const NormalEquations& normal, int denseColumns) {
  const int row = static_cast<int>(a.rows()), columns = static_cast<int>(a.cols());
  for (int weighting = 0; weighting < 2; ++weighting) {
    Eigen::VectorXd weight(row);
    for (int r = 0; r < row; ++r) weight[r] = weighting == 0 ? 1.0 : 0.1 + (r % 5) * 0.7;
    SparseMatrix scaled = a;
    for (int col = 0; col < scaled.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(scaled, col); it; ++it)
        it.valueRef() *= std::sqrt(weight[it.row()]);
    const SparseMatrix expected = SparseMatrix(scaled.transpose()) * scaled;
    const SparseMatrix assembled = normal.assemble(weight);
    ASSERT_EQ(assembled.nonZeros(), expected.nonZeros());
    for (int col = 0; col < columns; ++col)
      for (SparseMatrix::InnerIterator it(expected, col); it; ++it)
        EXPECT_EQ(assembled.coeff(it.row(), col), it.value()) << it.row() << ", " << col;
    // Split between threads by columns: the same values.
    for (const int threads : {2, 3, 7}) {
      const SparseMatrix split = normal.assemble(weight, threads);
      ASSERT_EQ(split.nonZeros(), assembled.nonZeros());
      for (Eigen::Index k = 0; k < split.nonZeros(); ++k)
        ASSERT_EQ(split.valuePtr()[k], assembled.valuePtr()[k]) << threads << " threads";
    }
    const SparseMatrix skipped = normal.assemble(weight, 2, NormalEquations::DenseBlock::Skipped);
    ASSERT_EQ(skipped.nonZeros(), assembled.nonZeros());
    const int denseFrom = columns - denseColumns;
    for (int col = 0; col < columns; ++col)
      for (SparseMatrix::InnerIterator it(assembled, col); it; ++it)
        EXPECT_EQ(skipped.coeff(it.row(), col),
                  it.row() >= denseFrom && col >= denseFrom ? 0.0 : it.value())
            << it.row() << ", " << col;
    // pattern(): the assembly's places, in the same order, every value 0 (the parameterization
    // analyzes its system on it before the weights are known).
    const SparseMatrix& pattern = normal.pattern();
    ASSERT_EQ(pattern.nonZeros(), assembled.nonZeros());
    for (int col = 0; col <= columns; ++col)
      ASSERT_EQ(pattern.outerIndexPtr()[col], assembled.outerIndexPtr()[col]);
    for (Eigen::Index k = 0; k < pattern.nonZeros(); ++k) {
      ASSERT_EQ(pattern.innerIndexPtr()[k], assembled.innerIndexPtr()[k]);
      ASSERT_EQ(pattern.valuePtr()[k], 0.0);
    }
  }
  EXPECT_THROW(normal.assemble(Eigen::VectorXd::Ones(row + 1)), std::invalid_argument);
}

TEST(NormalEquations, EqualTheWeightedProductToTheLastBitForEveryWeighting) {
  // Groups of 1-6 rows over a few of 50 columns each (a face's rows over its corners' unknowns),
  // one empty row, and rows that reach other groups' columns.
  const int columns = 50;
  std::vector<Eigen::Triplet<double>> triplets;
  std::vector<int> groupStart;
  int row = 0;
  for (int g = 0; g < 40; ++g) {
    groupStart.push_back(row);
    const int size = 1 + g % 6;
    for (int r = 0; r < size; ++r, ++row)
      for (int k = 0; k < 3 + (r + g) % 4; ++k)
        if (g != 7 || r != 0)  // row 0 of group 7 stays empty
          triplets.emplace_back(row, (g * 7 + k * (3 + r) + (k == 3 ? 23 : 0)) % columns,
                                std::sin(1.0 + row * 0.37 + k * 1.3));
  }
  // Every fifth row also meets the 8 last columns (a face's rows near the cut graph meet many
  // integer unknowns).
  for (int r = 0; r < row; r += 5)
    for (int c = columns - 8; c < columns; ++c) triplets.emplace_back(r, c, std::cos(r + 0.5 * c));
  SparseMatrix a(row, columns);
  a.setFromTriplets(triplets.begin(), triplets.end());
  // Without a dense block, with the 8 last columns in one, and with all of them in one.
  for (const int denseColumns : {0, 8, columns}) {
    SCOPED_TRACE(std::to_string(denseColumns) + " dense columns");
    checkNormalEquations(a, NormalEquations(a, groupStart, denseColumns), denseColumns);
  }
  EXPECT_THROW(NormalEquations(a, {1, 5}), std::invalid_argument);
}

/// a ⊗ [[2, 0.5], [0.5, 1]]: two unknowns per node, coupled at each node and along each edge,
/// like the u and v of a vertex in the parameterization.
SparseMatrix withTwoByTwoBlocks(const SparseMatrix& a) {
  const double block[2][2] = {{2.0, 0.5}, {0.5, 1.0}};
  std::vector<Eigen::Triplet<double>> triplets;
  for (int col = 0; col < a.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(a, col); it; ++it)
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
          triplets.emplace_back(2 * it.row() + i, 2 * col + j, it.value() * block[i][j]);
  SparseMatrix m(2 * a.rows(), 2 * a.cols());
  m.setFromTriplets(triplets.begin(), triplets.end());
  return m;
}

TEST(BlockFillReducingOrder, OrdersLargeGraphsByNestedDissection) {
  // A 320 × 320 grid has more blocks than kMetisOnlyBlocks: METIS alone orders it, and on a grid
  // this large nested dissection fills clearly less than minimum degree.
  const int side = 320, n = 2 * side * side;
  ASSERT_GE(side * side, kMetisOnlyBlocks);
  const SparseMatrix a = withTwoByTwoBlocks(shiftedLaplacian(side * side, gridEdges(side), 0.01));
  const std::vector<int> order = blockFillReducingOrder(a, 2);
  ASSERT_EQ(static_cast<int>(order.size()), n);
  for (int k = 0; k < n; k += 2) ASSERT_EQ(order[k + 1], order[k] + 1) << "a block is split";
  CholmodSupernodalFactorization<SparseMatrix> nestedDissection, minimumDegree;
  nestedDissection.analyzePattern(a, order);
  minimumDegree.cholmod().nmethods = 1;
  minimumDegree.cholmod().method[0].ordering = CHOLMOD_AMD;
  minimumDegree.analyzePattern(a);
  ASSERT_EQ(nestedDissection.info(), Eigen::Success);
  ASSERT_EQ(minimumDegree.info(), Eigen::Success);
  EXPECT_LT(nestedDissection.cholmod().lnz, 0.9 * minimumDegree.cholmod().lnz);
}

TEST(BlockFillReducingOrder, KeepsBlocksTogetherAndReducesFillLikeCholmodsOwnOrder) {
  const int side = 40, n = 2 * side * side;
  const SparseMatrix a = withTwoByTwoBlocks(shiftedLaplacian(side * side, gridEdges(side), 0.01));
  const std::vector<int> order = blockFillReducingOrder(a, 2);
  ASSERT_EQ(static_cast<int>(order.size()), n);
  for (int k = 0; k < n; k += 2) {
    ASSERT_EQ(order[k] % 2, 0) << "a block starts at position " << k;
    ASSERT_EQ(order[k + 1], order[k] + 1) << "the block at position " << k << " is split";
  }
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i);

  CholmodSupernodalFactorization<SparseMatrix> blockOrdered, cholmodOrdered, natural;
  blockOrdered.analyzePattern(a, order);
  blockOrdered.factorize(a);
  cholmodOrdered.compute(a);
  std::vector<int> identity(n);
  for (int i = 0; i < n; ++i) identity[i] = i;
  natural.analyzePattern(a, identity);
  natural.factorize(a);
  ASSERT_EQ(blockOrdered.info(), Eigen::Success);
  ASSERT_EQ(cholmodOrdered.info(), Eigen::Success);
  ASSERT_EQ(natural.info(), Eigen::Success);
  const double fill = blockOrdered.cholmod().lnz, cholmodFill = cholmodOrdered.cholmod().lnz;
  EXPECT_LT(fill, 1.25 * cholmodFill);
  EXPECT_LT(fill, 0.5 * natural.cholmod().lnz);  // the grid's natural order fills a band

  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = std::cos(0.21 * i);
  const Eigen::VectorXd x = blockOrdered.solve(b);
  EXPECT_LT((a * x - b).norm(), 1e-9 * b.norm());
  EXPECT_LT((x - cholmodOrdered.solve(b)).cwiseAbs().maxCoeff(), 1e-9 * x.cwiseAbs().maxCoeff());

  // The forward solve reads the given order from the factor.
  SparseMatrix columns(n, 2);
  columns.insert(17, 0) = 1.0;
  columns.insert(n - 5, 1) = -2.0;
  const SparseMatrix w = supernodalForwardSolve(*blockOrdered.factor(), columns);
  const Eigen::MatrixXd expected =
      Eigen::MatrixXd(columns).transpose() * blockOrdered.solve(Eigen::MatrixXd(columns));
  EXPECT_LT((Eigen::MatrixXd(SparseMatrix(w.transpose()) * w) - expected).cwiseAbs().maxCoeff(),
            1e-9 * expected.cwiseAbs().maxCoeff());

  EXPECT_THROW(blockFillReducingOrder(SparseMatrix(5, 5), 2), std::invalid_argument);
}

TEST(SupernodalForwardSolve, AndSolveRefuseASimplicialFactorAndAWrongSize) {
  const int side = 10, n = side * side;
  const SparseMatrix a = shiftedLaplacian(n, gridEdges(side), 1.0);
  SimplicialFactor simplicial;
  simplicial.compute(a);
  ASSERT_EQ(simplicial.info(), Eigen::Success);
  SparseMatrix b(n, 1);
  b.insert(3, 0) = 1.0;
  EXPECT_THROW(supernodalForwardSolve(simplicial.factor(), b), std::invalid_argument);
  CholmodSupernodalFactorization<SparseMatrix> supernodal;
  supernodal.compute(a);
  ASSERT_EQ(supernodal.info(), Eigen::Success);
  EXPECT_THROW(supernodalForwardSolve(*supernodal.factor(), SparseMatrix(n + 1, 1)),
               std::invalid_argument);
  EXPECT_THROW(supernodalSolve(simplicial.factor(), Eigen::MatrixXd::Ones(n, 2)),
               std::invalid_argument);
  EXPECT_THROW(supernodalSolve(*supernodal.factor(), Eigen::MatrixXd::Ones(n + 1, 2)),
               std::invalid_argument);
}

}  // namespace
}  // namespace hexcover
