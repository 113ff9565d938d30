#pragma once
// Refinement that keeps the surface: long edges split at their midpoints.

#include <cstddef>
#include <limits>

#include "core/mesh/mesh.h"

namespace hexcover {

/// Splits every edge longer than maxLength at its midpoint (each triangle beside it into two),
/// the longest first (ties: lower edge index), until none is left: the surface stays the same,
/// only its sampling gets finer. The field and the parameterization live on the input's vertices
/// and faces, so an input much coarser than the lattice (a CAD cylinder: a cap as one fan of
/// slivers, sides as strips of the full height) gives them no room for singularities or for the
/// lattice's detail. Stops early, with edges still longer, rather than exceed `maxFaces` faces.
/// Returns the number of splits; throws Error(InvalidOption) unless maxLength is finite and
/// positive.
long long splitLongEdges(TriMesh& mesh, double maxLength,
                         std::size_t maxFaces = std::numeric_limits<std::size_t>::max());

}  // namespace hexcover
