#pragma once
// Distances between two triangulated surfaces: exact point-to-triangle distances over a
// bounding-volume hierarchy (Embree 3 point queries), surface sampling with certified refinement.
//
// One-sided distance from surface A to surface B: d_B(p) = min over triangles T of B of |p − T|,
// for p on A. The Hausdorff distance is max(sup_A d_B, sup_B d_A).
//
// Sampling: every vertex of A, then A's faces as cells (3 corner samples + 1 centroid sample),
// split 1-to-4 until each cell is at most twice the area of a cell of an even partition into
// max(#faces, minSamples) cells (area-proportional sampling; centroids give the mean by the
// midpoint rule). Refinement: d(·, T) is convex for a fixed triangle T, so on a convex piece of
// a cell d_B ≤ max over the piece's corners of d(·, T). A cell's bound U is the lower of
// min_{T ∈ C} max_i d(c_i, T) over its corners c_i, where C holds the closest triangles of the
// cell's corners and centroid, and, for a cell that would be split, the cell cut by planes that
// separate C's triangles (through a shared edge, bisecting the dihedral angle, or a shared
// vertex), each piece bounded by its side's triangle: exact where the surface is smooth, where a
// single triangle overshoots by the cell's reach past its edges. Cells with U above the largest
// sampled distance L by more than the tolerance are split again, largest U first, until none is
// left (then sup_A d_B lies in [L, (1 + tolerance)·L], i.e. the reported maximum is certified)
// or the sample budget is spent.
// Results do not depend on the number of threads.

#include <Eigen/Core>
#include <cstddef>
#include <memory>

#include "core/geometry/closest_point.h"
#include "core/mesh/mesh.h"

namespace hexcover {

/// Sampling and refinement settings of the surface distance; defaults suit meshes up to ~10^6
/// faces. `validate()` throws Error(InvalidOption) naming the bad field.
struct DistanceOptions {
  /// Refinement stops once the certified upper bound of each one-sided maximum is within this
  /// fraction of the sampled maximum (0.005: within 0.5%).
  double relativeTolerance = 0.005;
  /// Minimum number of face cells per surface, so that small meshes are sampled finely enough
  /// for the mean and RMS distance.
  std::size_t minSamples = 4096;
  /// Upper limit on distance queries per direction; when refinement reaches it, the sampled
  /// maximum is reported with the bound reached (`certified` = false). Surfaces that are close
  /// everywhere need the most: the icosphere of shared/meshes and its remesh at a quarter of its
  /// vertices (0.032%) are certified with 355K queries for both directions together.
  std::size_t maxSamples = 500'000;
  /// Worker threads for the queries (results are identical for any count).
  int threads = 2;

  void validate() const;
};

/// Distances from the points of one surface to another, in the meshes' length unit.
struct OneSidedDistance {
  double max = 0.0;            ///< largest sampled distance: a lower bound of sup d
  double maxUpperBound = 0.0;  ///< certified upper bound of sup d (≥ max)
  bool certified = false;      ///< maxUpperBound ≤ (1 + relativeTolerance)·max (or both ~0)
  double mean = 0.0;           ///< area-weighted mean ∫ d dA / ∫ dA
  double rms = 0.0;            ///< sqrt(∫ d² dA / ∫ dA)
  double area = 0.0;           ///< area of the sampled surface
  Eigen::Vector3d farthestPoint = Eigen::Vector3d::Zero();  ///< where `max` is attained
  std::size_t samples = 0;                                  ///< distance queries made
  int refinementRounds = 0;  ///< rounds of cell splitting (area-proportional and refinement)
};

/// Distance from every point of `from` to the mesh behind `to`. Isolated vertices of `from` are
/// ignored. Refuses a mesh without faces (Error InvalidMesh).
OneSidedDistance oneSidedDistance(const TriMesh& from, const ClosestPointQuery& to,
                                  const DistanceOptions& options = {});

/// Both one-sided distances between surfaces a and b.
struct TwoSidedDistance {
  OneSidedDistance aToB;
  OneSidedDistance bToA;

  /// Hausdorff distance max(sup_a d_b, sup_b d_a) (sampled, i.e. the lower end of the bound).
  double hausdorff() const;
  /// Certified upper bound of the Hausdorff distance.
  double hausdorffUpperBound() const;
  /// Two-sided mean: (∫_a d_b + ∫_b d_a) / (|a| + |b|); rms likewise with d².
  double mean() const;
  double rms() const;
};

TwoSidedDistance twoSidedDistance(const TriMesh& a, const TriMesh& b,
                                  const DistanceOptions& options = {});

}  // namespace hexcover
