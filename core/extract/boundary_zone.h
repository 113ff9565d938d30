#pragma once
// Improvement of the boundary zone (internal to core/extract): the triangles between the lattice
// front and the input boundary, stitched from two polylines of unequal spacing, can have slivers
// and vertices of high valence. With operations of the isotropic remeshing of Botsch and Kobbelt
// (2004), restricted to the boundary and the vertices next to it:
// - edges shorter than half the target length collapse into one end when that lowers the largest
//   deviation from 60° of the removed end's triangles (the removed end: an interior vertex next to
//   the boundary, or a boundary vertex that is not a corner, along the boundary); so does the tip
//   of a poor ear (a boundary vertex with one triangle, which has an angle below 20°), along its
//   shorter boundary edge;
// - interior edges with an end on or next to the boundary flip towards valence 6 (interior) and 4
//   (boundary), or towards a larger smallest angle;
// - interior vertices next to the boundary move towards their neighbours' centroid projected onto
//   the input, when that lowers the largest deviation of their triangles' angles from 60°.
// Boundary vertices never move and vertices farther inside are never touched; no operation turns
// a triangle by more than 60° or creates an edge longer than 4/3 of the target length.

#include "core/geometry/closest_point.h"
#include "core/mesh/mesh.h"

namespace hexcover::extract_detail {

struct BoundaryZoneCounts {
  long long collapses = 0;
  long long flips = 0;
  long long smoothed = 0;  ///< vertex moves
};

/// Improves the boundary zone of `remesh` (vertices on the input surface behind `input`; target
/// edge length `targetLength` > 0) in up to `iterations` rounds of collapses, flips and smoothing,
/// while any changes something. Removed vertices are garbage-collected (indices change).
/// Deterministic. A mesh without boundary is left as it is.
BoundaryZoneCounts improveBoundaryZone(const ClosestPointQuery& input, TriMesh& remesh,
                                       double targetLength, int iterations = 4);

}  // namespace hexcover::extract_detail
