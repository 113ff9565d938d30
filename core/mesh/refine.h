#pragma once
// Refinement that keeps the surface: long edges split at their midpoints, flat regions flipped
// to Delaunay and relaxed within their planes.

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

/// Flips the interior edges between coplanar triangles (normals within kCoplanarCosine) that are
/// not locally Delaunay (opposite angles summing to more than π), until none is left or
/// maxPasses passes over the edges: on flat regions the same surface with better angles. CAD
/// exporters triangulate a planar face with slivers (a plate's face fanned from a hole to its
/// corners, angles below 0.1°), which midpoint splits keep; the flips improve them as far as the
/// points allow (a plate with a hole at K = 2000: angle SD 14.5 -> 13.2°). Returns the number of
/// flips.
long long flipFlatRegionsToDelaunay(TriMesh& mesh, int maxPasses = 32);

/// Relaxes the flat regions: `rounds` times, every vertex whose triangles are coplanar and which
/// is not on the boundary moves to the centroid of its neighbours when that leaves all its
/// triangles oriented as before (so they tile the same planar polygon), in index order, and the
/// flat regions are then flipped to Delaunay. The points that splits crowd along a fan's spokes
/// spread over the face; vertices on creases, boundaries and curved regions stay. Returns the
/// number of moves.
long long relaxFlatRegions(TriMesh& mesh, int rounds);

/// Rounds of relaxFlatRegions in refineLongEdges.
inline constexpr int kFlatRelaxationRounds = 5;

/// splitLongEdges, and when it split an edge, flipFlatRegionsToDelaunay and
/// relaxFlatRegions(kFlatRelaxationRounds): the same surface, sampled at most maxLength apart
/// (within maxFaces), with the slivers of planar faces opened up. Returns the number of splits.
long long refineLongEdges(TriMesh& mesh, double maxLength,
                          std::size_t maxFaces = std::numeric_limits<std::size_t>::max());

/// Normals whose dot product exceeds this are coplanar for flipFlatRegionsToDelaunay (an angle
/// of 1.4·10⁻⁵ rad: a CAD model's planar faces, not a scan's nearly flat ones).
inline constexpr double kCoplanarCosine = 1.0 - 1e-10;

}  // namespace hexcover
