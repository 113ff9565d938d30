#pragma once
// Internal to core/param: exact corner coordinates, their orientation, and the local remedies for
// fold-overs and degenerate triangles of a solution (hexcover.cpp tries them, cheapest first,
// before the global stiffening).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/param/cut_mesh.h"
#include "core/param/energy.h"
#include "core/param/energy_system.h"

namespace hexcover::param_detail {

/// Exact corner coordinates: the masters' lattice coordinates M⁻¹(u, v) snapped to multiples of
/// 2^-k, integer unknowns exact, every corner computed from them with the integer transforms, so
/// that the transitions hold bit-exactly (|values| < 2^52 quanta).
struct SnappedCoordinates {
  int exponent = 0;                                ///< quantum 2^-exponent
  std::vector<std::array<std::int64_t, 2>> wedge;  ///< #wedges, in units of the quantum
};

/// The exact corner coordinates of the solution x (lattice of order n).
SnappedCoordinates snapCoordinates(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u,
                                   const Eigen::VectorXd& x, int n);

/// Flipped (negative orientation) and degenerate (zero area) parameter triangles.
struct Orientation {
  int flipped = 0;
  int degenerate = 0;
};

/// Fewer flipped triangles, or as many and fewer degenerate ones.
bool fewerFaults(const Orientation& a, const Orientation& b);

/// The orientation of every parameter triangle, exact; the flags per face when asked for.
Orientation countOrientation(const TriMesh& mesh, const CutMesh& cm, const SnappedCoordinates& s,
                             std::vector<bool>* flippedFaces = nullptr,
                             std::vector<bool>* degenerateFaces = nullptr);

/// Rounding repair: fold-overs and degenerate triangles that stiffening cannot remove come from
/// the rounding (typically two singularities rounded onto the same lattice point, or next to each
/// other). For the integer unknowns that the corners of flipped or degenerate triangles depend
/// on, try moving each to a neighbouring lattice point (its effect on the minimizer is linear: one
/// back-substitution per unknown with the last factorization, those of a pass in one solve when
/// they fit in the system's response cache) and keep a move when it leaves fewer flipped
/// triangles, or as many and fewer degenerate ones. At most four passes over at most 32 units
/// each; the trial moves are judged on up to `threads` threads, with the same result.
/// x, snapped, orientation and flippedFaces describe the solution before and after.
void repairRounding(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u, EnergySystem& system,
                    int n, int threads, Eigen::VectorXd& x, SnappedCoordinates& snapped,
                    Orientation& orientation, std::vector<bool>& flippedFaces);

/// Local fold-over relaxation: re-solves only the real unknowns of the vertices within `rings`
/// edge rings of a flipped triangle (everything else held), with the faces there stiffened as in
/// the global loop (weight 1 + min(5·relative misfit, 20), doubled at flipped triangles), a few
/// times per region; the region doubles while triangles stay flipped, up to a fifth of the real
/// unknowns (the global stiffening re-solves larger ones at a lower cost). A small sparse solve per
/// step instead of a refactorization of the whole system. Keeps a step only when it leaves fewer
/// flipped triangles and no more degenerate ones; returns the number of local solves.
int relaxFoldsLocally(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u,
                      const LeastSquares& ls, const std::vector<double>& faceScale, int n,
                      Eigen::VectorXd& x, SnappedCoordinates& snapped, Orientation& orientation,
                      std::vector<bool>& flippedFaces);

}  // namespace hexcover::param_detail
