#pragma once
// Improvement of the boundary zone (internal to core/extract): the triangles between the lattice
// front and the input boundary, stitched from two polylines of unequal spacing, can have slivers
// and vertices of high valence. Within the zone (the interior edges with an end on the boundary
// or next to it) edges flip towards valence 6 (interior) and 4 (boundary), as in the isotropic
// remeshing of Botsch and Kobbelt (2004), or towards a larger smallest angle, and the interior
// vertices next to the boundary move towards their neighbours' centroid projected onto the input
// when that lowers the largest deviation of their triangles' angles from 60°. Boundary vertices
// and vertices farther inside never move; no flip turns a triangle by more than 60° or creates an
// edge longer than 4/3 of the target length. The vertex count and the boundary stay.

#include "core/geometry/closest_point.h"
#include "core/mesh/mesh.h"

namespace hexcover::extract_detail {

struct BoundaryZoneCounts {
  long long flips = 0;
  long long smoothed = 0;  ///< vertex moves
};

/// Improves the boundary zone of `remesh` (vertices on the input surface behind `input`; target
/// edge length `targetLength` > 0) in up to `iterations` rounds of flips and smoothing, while
/// either changes something. Deterministic. A mesh without boundary is left as it is.
BoundaryZoneCounts improveBoundaryZone(const ClosestPointQuery& input, TriMesh& remesh,
                                       double targetLength, int iterations = 4);

}  // namespace hexcover::extract_detail
