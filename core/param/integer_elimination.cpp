#include "core/param/integer_elimination.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numeric>
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

  // Unimodular change of variables: the free x_p becomes x_p = y − k·x_q with a new free
  // variable y (appended); returns y.
  const auto shiftFree = [&](int p, int q, std::int64_t k) {
    const int y = static_cast<int>(result.expression.size());
    result.expression.emplace_back();
    occurrences.emplace_back();
    dependent.push_back(false);
    eliminate({{p, 1}, {q, k}, {y, -1}}, p);
    return y;
  };

  // Brings a row without unit coefficient to one with a unit: divide by the gcd of its
  // coefficients (same integer solutions), then Euclid on the two smallest coefficients through
  // unimodular changes of free variables. Never fails for a non-empty row.
  const auto makeUnit = [&](std::map<int, std::int64_t>& row) {
    while (true) {
      std::int64_t g = 0;
      for (const auto& [variable, coefficient] : row) g = std::gcd(g, std::llabs(coefficient));
      for (auto& [variable, coefficient] : row) coefficient /= g;
      int p = -1, q = -1;
      for (const auto& [variable, coefficient] : row) {
        if (std::llabs(coefficient) == 1) return;
        if (p < 0 || std::llabs(coefficient) < std::llabs(row.at(p))) {
          q = p;
          p = variable;
        } else if (q < 0 || std::llabs(coefficient) < std::llabs(row.at(q))) {
          q = variable;
        }
      }
      // c_p x_p + c_q x_q with x_p = y_p − k x_q: c_q becomes c_q − k c_p, |·| ≤ |c_p| / 2.
      const std::int64_t k = static_cast<std::int64_t>(
          std::llround(static_cast<double>(row.at(q)) / static_cast<double>(row.at(p))));
      const int y = shiftFree(p, q, k);
      row[y] = row.at(p);
      const std::int64_t value = (row[q] -= k * row.at(p));
      if (value == 0) row.erase(q);
      row.erase(p);
    }
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

  bool lastPass = false;
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
      if (pivot < 0 && !lastPass) {
        deferred.push_back(row);
        continue;
      }
      if (pivot < 0) {
        auto unit = reduced;
        makeUnit(unit);
        eliminate(unit, choosePivot(unit));
        continue;
      }
      eliminate(reduced, pivot);
    }
    // Rows without a unit pivot wait for the others; when none makes progress they are
    // brought to a unit pivot by unimodular changes of variables (makeUnit).
    lastPass = deferred.size() == pending.size();
    pending = std::move(deferred);
  }

  for (int x = 0; x < static_cast<int>(result.expression.size()); ++x) {
    if (dependent[x]) continue;
    result.freeVariables.push_back(x);
    result.expression[x] = {{x, 1}};
  }
  return result;
}

}  // namespace hexcover
