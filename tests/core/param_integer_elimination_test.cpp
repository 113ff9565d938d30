// Exact integer elimination of the seam-translation constraints (core/param/integer_elimination.h).

#include <gtest/gtest.h>

#include <cstdlib>

#include "core/common/error.h"
#include "core/param/integer_elimination.h"

namespace hexcover {
namespace {

std::int64_t evaluate(const IntegerCombination& combination, const std::vector<std::int64_t>& x) {
  std::int64_t sum = 0;
  for (const auto& [variable, coefficient] : combination) sum += coefficient * x[variable];
  return sum;
}

/// Any integer values of the free variables give integers that satisfy every row.
void expectRowsHoldForFreeValues(const IntegerElimination& e,
                                 const std::vector<IntegerCombination>& rows, int variables) {
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<std::int64_t> free(e.expression.size(), 0);
    for (const int x : e.freeVariables) free[x] = (x * 7 + trial * 3) % 11 - 5;
    std::vector<std::int64_t> all(variables);
    for (int x = 0; x < variables; ++x) all[x] = evaluate(e.expression[x], free);
    for (const auto& row : rows) EXPECT_EQ(evaluate(row, all), 0);
  }
}

TEST(IntegerElimination, ChainOfEqualTranslationsLeavesOneFreeVariable) {
  // x0 = x1 = x2 = x3 (a seam through three regular vertices).
  const std::vector<IntegerCombination> rows{{{0, 1}, {1, -1}}, {{2, 1}, {3, -1}}, {{1, 1}, {2, -1}}};
  const IntegerElimination e = eliminateIntegerConstraints(4, rows);
  EXPECT_EQ(e.freeVariables.size(), 1u);
  expectRowsHoldForFreeValues(e, rows, 4);
}

TEST(IntegerElimination, RedundantRowsAreCounted) {
  const std::vector<IntegerCombination> rows{{{0, 1}, {1, 1}}, {{0, -2}, {1, -2}}};
  const IntegerElimination e = eliminateIntegerConstraints(2, rows);
  EXPECT_EQ(e.redundantRows, 1);
  EXPECT_EQ(e.freeVariables.size(), 1u);
}

TEST(IntegerElimination, SingularFixedPointIsIntegralForIntegerTranslations) {
  // (I − R) z = t for the 60° rotation R = [[0,-1],[1,1]]: I − R = [[1,1],[-1,0]] is unimodular.
  // Variables: z = (0, 1), t = (2, 3); prefer pivoting on z.
  const std::vector<IntegerCombination> rows{{{0, 1}, {1, 1}, {2, -1}}, {{0, -1}, {3, -1}}};
  const IntegerElimination e = eliminateIntegerConstraints(4, rows, {true, true, false, false});
  EXPECT_EQ(e.freeVariables, (std::vector<int>{2, 3}));
  expectRowsHoldForFreeValues(e, rows, 4);
}

TEST(IntegerElimination, RowsWithoutUnitPivotAreReducedByUnimodularChanges) {
  // 2·x0 + 4·x1 = 0 (gcd 2) and 2·x2 + 3·x3 = 0 (Euclid): every integer solution is an integer
  // combination of the free variables, one per row.
  const std::vector<IntegerCombination> rows{{{0, 2}, {1, 4}}, {{2, 2}, {3, 3}}};
  const IntegerElimination e = eliminateIntegerConstraints(4, rows);
  EXPECT_EQ(e.freeVariables.size(), 2u);
  std::vector<std::int64_t> free(e.expression.size(), 0);
  for (const int x : e.freeVariables) free[x] = 1;
  std::vector<std::int64_t> all(4);
  for (int x = 0; x < 4; ++x) all[x] = evaluate(e.expression[x], free);
  for (const auto& row : rows) EXPECT_EQ(evaluate(row, all), 0);
  // The generator of 2·x2 + 3·x3 = 0 is ±(3, −2), not a multiple of it.
  EXPECT_EQ(std::abs(all[2]), 3);
  EXPECT_EQ(std::abs(all[3]), 2);
}

TEST(IntegerElimination, FixedVariablesBecomeZero) {
  const std::vector<IntegerCombination> rows{{{1, 1}}, {{0, 1}, {1, 1}, {2, 1}}};
  const IntegerElimination e = eliminateIntegerConstraints(3, rows);
  EXPECT_TRUE(e.expression[1].empty());
  expectRowsHoldForFreeValues(e, rows, 3);
}

}  // namespace
}  // namespace hexcover
