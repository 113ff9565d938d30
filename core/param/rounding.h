#pragma once
// Internal to core/param: the global step's rounding of the integer unknowns to lattice points
// (paper sections 4.4-4.5).

#include <Eigen/Core>
#include <vector>

#include "core/common/run_context.h"
#include "core/param/cut_mesh.h"
#include "core/param/energy_system.h"
#include "core/param/hexcover.h"

namespace hexcover::param_detail {

/// Rounding units (columns of x): both scalars of a pair when both are free (rounded to the
/// nearest lattice point), else single scalars (rounded to the nearest integer).
std::vector<std::vector<int>> roundingUnits(const Unknowns& u);

/// The Euclidean distance (in units of h) from one unit's values in x to their rounding, which
/// replaces them when `apply`; `basis` is the lattice's (lattice.h).
double roundUnit(const std::vector<int>& unit, Eigen::VectorXd& x, const Eigen::Matrix2d& basis,
                 bool apply);

/// Rounds the integer unknowns of x, the local step's minimizer (`system` holds its Schur
/// complement), to lattice points: all at once (RoundingMethod::Direct) or greedily, the units
/// closest to the lattice first with the rest re-solved on the Schur complement after each batch
/// (the real unknowns follow at the final solve); then, with options.latticeDescent, the lattice
/// descent of EnergySystem::descendIntegers. Returns the descent's moves.
int roundIntegers(const EnergySystem& system, const Unknowns& u, const ParamOptions& options, int n,
                  Eigen::VectorXd& x, const RunContext& context);

}  // namespace hexcover::param_detail
