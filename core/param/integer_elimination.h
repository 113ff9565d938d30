#pragma once
// Exact elimination of homogeneous integer linear constraints Σ c_j x_j = 0 (c_j ∈ Z) over
// integer variables, by Gaussian elimination with unit pivots only (paper sec. 4.4: the
// translations of the seams meeting at a cut-graph node are related by integer equations; the
// dependent ones are eliminated with integer arithmetic, so that rounding the independent ones
// keeps every translation integral).
//
// After elimination every variable is an integer combination of the free ones: free variables map
// to themselves, dependent ones to their expression, variables fixed at 0 to the empty sum.

#include <cstdint>
#include <utility>
#include <vector>

namespace hexcover {

/// Σ coefficient · x_variable, sorted by variable, no zero coefficients.
using IntegerCombination = std::vector<std::pair<int, std::int64_t>>;

struct IntegerElimination {
  /// #variables (+ variables introduced by unimodular changes, see below): each variable as a
  /// combination of free variables.
  std::vector<IntegerCombination> expression;
  /// Free variables in increasing order.
  std::vector<int> freeVariables;
  int redundantRows = 0;  ///< rows implied by the others (reduced to 0 = 0)
};

/// Eliminates `rows` over `variableCount` integer variables. Pivots: a unit coefficient, preferring
/// variables listed in `preferredPivots` (flags, #variables or empty), then variables that occur in
/// fewer expressions, then the lowest index. A row left without a unit coefficient (e.g. the
/// fixed point of a 90° holonomy, I − R = [[1, 1], [−1, 1]]) is divided by the gcd of its
/// coefficients and reduced by Euclid's algorithm through unimodular changes of the free
/// variables, which append new free variables (indices ≥ variableCount). Throws
/// Error(NumericalFailure) when coefficients overflow.
IntegerElimination eliminateIntegerConstraints(int variableCount,
                                               const std::vector<IntegerCombination>& rows,
                                               const std::vector<bool>& preferredPivots = {});

}  // namespace hexcover
