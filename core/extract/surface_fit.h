#pragma once
// Fitting the extracted remesh to the input surface (internal to core/extract): vertices move
// over the input surface, and last off it where that halves the distance; the connectivity
// stays. Five moves, each kept only when it does not raise the local deviation between the
// remesh and the input (beyond 0.1 local edge lengths for smoothing and relaxation):
//
// - Feature snapping: an input vertex farther than `featureSnapDistance` edge lengths from the
//   remesh (the smaller of the local and the mean edge length: where the conformal scale makes
//   triangles large, as on the rocker arm's creases, the mean bounds the distance) pulls the
//   nearest corner of its closest remesh triangle onto itself, when that corner is within
//   `kSnapReach` edge lengths and its triangles keep their angles in [kSnapMinAngle,
//   kSnapMaxAngle]; failing that, 0.7 or 0.45 of the way (projected onto the input), and such a
//   part-way move may go on in a later round. Points sampled inside the input's crease edges
//   (every half mean edge length) do the same for a corner within kCreaseSnapReach (0.2) edge
//   lengths of their crease edge, whose closest point is its target: where lattice rows cross a
//   crease, the vertices beside it move onto it, between the input's vertices too (a plate
//   with a hole at K = 2000: Hausdorff 0.88 -> 0.71%).
// - Smoothing of poor triangles: a corner of a triangle with an angle below kPoorMinAngle or above
//   kPoorMaxAngle (next to hole fills, folds and strips) moves to the best of a few trial
//   positions (towards the centroid of its neighbours, and 8 directions in its tangent plane),
//   projected onto the input, when that lowers its triangles' angle badness (fan_geometry.h: the
//   deviation from 60° relative to the 20° and 130° floors).
// - Relaxation (after the rounds of the first two): gradient descent on the angles, on the
//   interior vertices (snapped ones too). A vertex whose triangles' angles deviate from 60° by
//   more than kRelaxMinRms RMS steps down the gradient, in its tangent plane, of their sum of
//   squared deviations from 60°, projected onto the input, when the sum drops, their badness
//   does not rise, its fan's local deviation stays within kRelaxDeviation local edge lengths
//   and the largest fan deviation before relaxation (the two-sided distance is a maximum: the
//   angles may use the room below it), and the distance of the input's crease vertices to the
//   fan within kRelaxCreaseDeviation local edge lengths (or, either way, no larger than
//   before). Up to kRelaxPasses passes, each over the vertices whose fans changed. Vertices
//   that share no triangle move in parallel (a greedy colouring), so the result does not
//   depend on the thread count. This is what lowers the angle SD (at K = V/4: fandisk
//   6.13 → 5.87°, rocker-arm 3.91 → 3.22°, feline 5.28 → 4.74°).
// - Balancing (last, kBalancePasses passes): a vertex whose fan deviates from the input by at
//   least half the largest fan deviation (and kBalanceMinDeviation local edge lengths) moves
//   along its fan's normal to the offset (within ±kBalanceReach local edge lengths,
//   golden-section search) that minimizes the fan's local deviation, sampled on a barycentric
//   grid of the fan, when its triangles stay within the snap's angle window (or no worse than
//   before). Snapped vertices too. This leaves the vertex off the input: on a convex patch an
//   interpolating triangle lies inside the surface by up to its sagitta δ, and lifting its
//   corners by about δ/2 halves the two-sided distance (an icosphere of 42 vertices against the
//   unit sphere: see the test; fandisk at K = V/4: 1.34 → 0.87%).
// - Outlier angles (last, triangles only, up to kOutlierPasses passes): a corner of a triangle
//   with an angle outside the goal window [30°, 100°] moves to the best of smoothing's trial
//   positions, projected onto the input, that brings its triangles' smallest or largest angle
//   nearer the window and neither farther from it (least excess, then least Σ (α − 60°)²),
//   when neither its fan's local deviation (sampled on a finer grid than balancing's) nor (a)
//   and the distance of the input's crease vertices, below, rises; the neighbours of a move
//   wait for the next pass, after the input points are assigned again. Such angles sit near
//   the largest deviations, where relaxation stops: at K = V/4 feline's angles went from
//   25.1-106.0° to 26.0-104.1°, spot's from 25.0-103.9° to 29.2-98.0°.
//
// The local deviation of a vertex's fan is the largest of (a) the distances from the input
// vertices whose closest remesh triangle is in the fan to the fan, and (b) the distances from the
// vertex, the fan's triangle centroids and the midpoints of the vertex's edges to the input; the
// input points are its vertices and its face centroids (only vertices are snap targets).
// Balancing samples (b) on the grid instead.
// Boundary vertices are never moved (they lie on the input boundary; see boundary.h for their
// slides), nor are those of copied components. Deterministic. For the quads of the Gauss lattice (N
// = 4) relaxation aims at 90° quad corners, snapping and balancing keep quad corners within 45° of
// 90° (or no worse) instead of triangle angles in their windows, and smoothing is left out
// (fitRemeshToSurface's squarePartner).

#include <vector>

#include "core/geometry/closest_point.h"
#include "core/mesh/mesh.h"

namespace hexcover::extract_detail {

/// Counts of what fitRemeshToSurface moved.
struct SurfaceFitCounts {
  long long snapped = 0;   ///< vertices moved onto an input feature
  long long smoothed = 0;  ///< vertex moves that opened up poor triangles
  long long relaxed = 0;   ///< relaxation moves
  long long balanced = 0;  ///< balancing moves
  long long outliers = 0;  ///< moves that brought angles nearer the goal window [30°, 100°]
};

/// Rounds of feature snapping and smoothing (fewer when one moves nothing).
inline constexpr int kSurfaceFitRounds = 4;

/// What fitRemeshToSurface does.
struct SurfaceFitOptions {
  /// Input vertices farther than this many edge lengths from the remesh snap; ≤ 0: no snapping.
  double featureSnapDistance = 0.0;
  /// The input's crease vertices, which relaxation keeps close, are those with an edge whose
  /// dihedral angle is at least this many degrees (≤ 0: none).
  double creaseAngle = 0.0;
  bool balanceDeviation = true;   ///< balancing (moves off the input)
  bool openOutlierAngles = true;  ///< the outlier-angle moves (triangles only)
  int threads = 1;                ///< relaxation's (the result is the same for any count)
  int rounds = kSurfaceFitRounds;
};

/// Fits `remesh` (vertices on the surface of `input`; `inputQuery` answers closest points on it)
/// to `input`: feature snapping and smoothing of poor triangles, alternating for up to
/// options.rounds rounds while either moves a vertex, then relaxation, balancing and the
/// outlier-angle moves (see above). `squarePartner` (N = 4; squarePartners in quad_mesh.h: per
/// face the other triangle of its lattice square, or −1) makes relaxation aim at 90° quad
/// corners, and leaves smoothing and the outlier-angle moves, which aim at 60° triangles, out.
/// `copied` (per remesh vertex, or empty for none) marks the vertices of input components copied
/// unchanged (extraction's step 6), which stay where they are, as boundary vertices do.
SurfaceFitCounts fitRemeshToSurface(const TriMesh& input, const ClosestPointQuery& inputQuery,
                                    TriMesh& remesh, const SurfaceFitOptions& options,
                                    const std::vector<int>& squarePartner = {},
                                    const std::vector<char>& copied = {});

}  // namespace hexcover::extract_detail
