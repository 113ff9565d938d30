#include "core/param/integer_elimination.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>
#include <string>

#include "core/common/error.h"

namespace hexcover {
namespace {

constexpr std::int64_t kCoefficientLimit = std::int64_t{1} << 40;

// acc += scale · combination, dropping zeros.
void addScaled(std::map<int, std::int64_t>& acc, const IntegerCombination& combination,
               std::int64_t scale) {
  for (const auto& [variable, coefficient] : combination) {
    const std::int64_t value = (acc[variable] += scale * coefficient);
    if (std::llabs(value) > kCoefficientLimit)
      throw Error(ErrorCode::NumericalFailure,
                  "integer elimination of the seam translations overflowed (coefficient " +
                      std::to_string(value) + ")");
    if (value == 0) acc.erase(variable);
  }
}

IntegerCombination toCombination(const std::map<int, std::int64_t>& acc) {
  return {acc.begin(), acc.end()};
}

}  // namespace

IntegerElimination eliminateIntegerConstraints(int variableCount,
                                               const std::vector<IntegerCombination>& rows,
                                               const std::vector<bool>& preferredPivots) {
  IntegerElimination result;
  result.expression.resize(variableCount);
  std::vector<bool> dependent(variableCount, false);
  // occurrences[x]: dependent variables whose expression contains the free variable x.
  std::vector<std::set<int>> occurrences(variableCount);

  // Reduces a row to free variables; returns false if nothing is left.
  const auto reduce = [&](const IntegerCombination& row) {
    std::map<int, std::int64_t> acc;
    for (const auto& [variable, coefficient] : row) {
      if (dependent[variable])
        addScaled(acc, result.expression[variable], coefficient);
      else
        addScaled(acc, {{variable, 1}}, coefficient);
    }
    return acc;
  };

  // Makes `pivot` dependent through the reduced row (its coefficient is ±1).
  const auto eliminate = [&](const std::map<int, std::int64_t>& row, int pivot) {
    const std::int64_t sign = row.at(pivot);  // ±1: pivot = -sign · Σ_{j≠pivot} c_j x_j
    std::map<int, std::int64_t> acc;
    for (const auto& [variable, coefficient] : row)
      if (variable != pivot) acc[variable] = -sign * coefficient;
    const IntegerCombination pivotExpression = toCombination(acc);
    // Substitute into every expression that used the pivot.
    for (const int d : occurrences[pivot]) {
      std::map<int, std::int64_t> updated(result.expression[d].begin(), result.expression[d].end());
      const std::int64_t scale = updated.at(pivot);
      updated.erase(pivot);
      addScaled(updated, pivotExpression, scale);
      for (const auto& [variable, coefficient] : result.expression[d])
        if (variable != pivot) occurrences[variable].erase(d);
      result.expression[d] = toCombination(updated);
      for (const auto& [variable, coefficient] : result.expression[d]) occurrences[variable].insert(d);
    }
    occurrences[pivot].clear();
    result.expression[pivot] = pivotExpression;
    for (const auto& [variable, coefficient] : pivotExpression) occurrences[variable].insert(pivot);
    dependent[pivot] = true;
  };

  const auto choosePivot = [&](const std::map<int, std::int64_t>& row) {
    int best = -1;
    for (const auto& [variable, coefficient] : row) {
      if (std::llabs(coefficient) != 1) continue;
      if (best < 0) {
        best = variable;
        continue;
      }
      const bool preferred = !preferredPivots.empty() && preferredPivots[variable];
      const bool bestPreferred = !preferredPivots.empty() && preferredPivots[best];
      if (preferred != bestPreferred) {
        if (preferred) best = variable;
        continue;
      }
      if (occurrences[variable].size() < occurrences[best].size()) best = variable;
    }
    return best;
  };

  std::vector<const IntegerCombination*> pending;
  for (const auto& row : rows) pending.push_back(&row);
  while (!pending.empty()) {
    std::vector<const IntegerCombination*> deferred;
    for (const auto* row : pending) {
      const auto reduced = reduce(*row);
      if (reduced.empty()) {
        ++result.redundantRows;
        continue;
      }
      const int pivot = choosePivot(reduced);
      if (pivot < 0) {
        deferred.push_back(row);
        continue;
      }
      eliminate(reduced, pivot);
    }
    if (deferred.size() == pending.size())
      throw Error(ErrorCode::NumericalFailure,
                  "the integer constraints of the seam translations have no unit pivot (" +
                      std::to_string(deferred.size()) +
                      " rows left); the field's singularities cannot be placed on the lattice");
    pending = std::move(deferred);
  }

  for (int x = 0; x < variableCount; ++x) {
    if (dependent[x]) continue;
    result.freeVariables.push_back(x);
    result.expression[x] = {{x, 1}};
  }
  return result;
}

}  // namespace hexcover
