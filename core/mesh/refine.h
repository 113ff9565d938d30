#pragma once
// Refinement that keeps the surface: long edges split at their midpoints.

#include "core/mesh/mesh.h"

namespace hexcover {

/// Splits every edge longer than maxLength at its midpoint (each triangle beside it into two),
/// the longest first (ties: lower edge index), until none is left: the surface stays the same,
/// only its sampling gets finer. The field and the parameterization live on the input's vertices
/// and faces, so an input much coarser than the lattice (a CAD cylinder: a cap as one fan of
/// slivers, sides as strips of the full height) gives them no room for singularities or for the
/// lattice's detail. Returns the number of splits; throws Error(InvalidOption) unless maxLength
/// is finite and positive.
long long splitLongEdges(TriMesh& mesh, double maxLength);

}  // namespace hexcover
