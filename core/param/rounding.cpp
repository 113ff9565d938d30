#include "core/param/rounding.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/param/lattice.h"

namespace hexcover::param_detail {
namespace {

// Nearest lattice point of a 2D unknown in the Euclidean metric of the plane: the best corner
// of the lattice cell around it.
Eigen::Vector2d nearestLatticePoint(const Eigen::Vector2d& z, const Eigen::Matrix2d& basis) {
  Eigen::Vector2d best(std::round(z[0]), std::round(z[1]));
  double bestDistance = (basis * (best - z)).norm();
  for (int da = 0; da < 2; ++da)
    for (int db = 0; db < 2; ++db) {
      const Eigen::Vector2d candidate(std::floor(z[0]) + da, std::floor(z[1]) + db);
      const double distance = (basis * (candidate - z)).norm();
      if (distance < bestDistance) {
        best = candidate;
        bestDistance = distance;
      }
    }
  return best;
}

}  // namespace

std::vector<std::vector<int>> roundingUnits(const Unknowns& u) {
  std::vector<std::vector<int>> units;
  const auto& free = u.elimination.freeVariables;
  for (std::size_t i = 0; i < free.size(); ++i) {
    const int x = free[i];
    if (x % 2 == 0 && x + 1 < u.scalarCount && i + 1 < free.size() && free[i + 1] == x + 1) {
      units.push_back({u.freeColumn[x], u.freeColumn[x + 1]});
      ++i;
    } else {
      units.push_back({u.freeColumn[x]});
    }
  }
  return units;
}

double roundUnit(const std::vector<int>& unit, Eigen::VectorXd& x, const Eigen::Matrix2d& basis,
                 bool apply) {
  if (unit.size() == 2) {
    const Eigen::Vector2d z(x[unit[0]], x[unit[1]]);
    const Eigen::Vector2d rounded = nearestLatticePoint(z, basis);
    if (apply) x[unit[0]] = rounded[0], x[unit[1]] = rounded[1];
    return (basis * (rounded - z)).norm();
  }
  const double rounded = std::round(x[unit[0]]);
  const double distance = std::abs(rounded - x[unit[0]]);
  if (apply) x[unit[0]] = rounded;
  return distance;
}

int roundIntegers(const EnergySystem& system, const Unknowns& u, const ParamOptions& options, int n,
                  Eigen::VectorXd& x, const RunContext& context) {
  const int columns = u.columns();
  const int realCount = u.realCount;
  const Eigen::Matrix2d basis = latticeBasis(n);
  auto units = roundingUnits(u);
  if (options.rounding == RoundingMethod::Direct) {
    for (const auto& unit : units) roundUnit(unit, x, basis, true);
  } else {
    // Greedy: round the units closest to the lattice, re-solve the rest on the Schur
    // complement (the real unknowns follow at the final solve).
    std::vector<bool> fixed(columns - realCount, false);
    while (!units.empty()) {
      std::vector<std::pair<double, std::size_t>> order;
      for (std::size_t i = 0; i < units.size(); ++i)
        order.emplace_back(roundUnit(units[i], x, basis, false), i);
      std::sort(order.begin(), order.end());
      const std::size_t count = std::max<std::size_t>(
          1, static_cast<std::size_t>(std::ceil(options.greedyBatchFraction * units.size())));
      std::vector<bool> taken(units.size(), false);
      for (std::size_t k = 0; k < count; ++k) {
        const auto& unit = units[order[k].second];
        roundUnit(unit, x, basis, true);
        for (const int column : unit) fixed[column - realCount] = true;
        taken[order[k].second] = true;
      }
      std::vector<std::vector<int>> remaining;
      for (std::size_t i = 0; i < units.size(); ++i)
        if (!taken[i]) remaining.push_back(std::move(units[i]));
      units = std::move(remaining);
      if (!units.empty())
        x.tail(columns - realCount) = system.solveIntegers(fixed, x.tail(columns - realCount));
      context.throwIfCanceled();
    }
  }
  std::vector<std::vector<int>> integerUnits = roundingUnits(u);
  for (auto& unit : integerUnits)
    for (int& column : unit) column -= realCount;
  Eigen::VectorXd integers = x.tail(columns - realCount);
  const int moves = options.latticeDescent ? system.descendIntegers(integerUnits, n, integers) : 0;
  x.tail(columns - realCount) = integers;
  return moves;
}

}  // namespace hexcover::param_detail
