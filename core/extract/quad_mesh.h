#pragma once
// Internal to core/extract: the quad-dominant remesh of the Gauss lattice (N = 4). The lattice's
// unit squares go through the triangle steps as two triangles each (split along the diagonal
// (a, b)-(a+1, b+1)). These functions pair the triangles again (for the surface fit's
// relaxation, which then aims at the quads' corners, and for the output), and mend the corners
// that the triangle-judged moves bend.

#include <array>
#include <vector>

#include "core/extract/boundary.h"
#include "core/geometry/closest_point.h"
#include "core/mesh/mesh.h"

namespace hexcover::extract_detail {

/// Partner of a face that is no half of a quad: kUnpaired may still be paired (pairTriangles),
/// kKeptAsIs not (a triangle of an input component copied unchanged).
inline constexpr int kUnpaired = -1;
inline constexpr int kKeptAsIs = -2;

/// Per face of `triangles` (built by buildMesh, `vertexOf` each assembly vertex's handle in it):
/// the other triangle of its unit square (`squares`, corners as assembly vertices,
/// counter-clockwise, split into (0, 1, 2) and (0, 2, 3)) when both are faces, else kUnpaired.
std::vector<int> squarePartners(const TriMesh& triangles,
                                const std::vector<std::array<int, 4>>& squares,
                                const std::vector<TriMesh::VertexHandle>& vertexOf);

/// The quad-dominant mesh: the two triangles of each square (`partner`, squarePartners) as one
/// quad, the other faces as triangles; the vertices and positions of `triangles`, in its order.
PolygonSoup pairSquares(const TriMesh& triangles, const std::vector<int>& partner);

/// Pairs kUnpaired triangles of `triangles` (`partner`: squarePartners; boundary strips, hole
/// fills) that share an edge into quads whose corners deviate from 90° by at most
/// kQuadCornerWindow, best quads first: a strip of triangles between a straight lattice front
/// and the boundary becomes a row of quads, which leaves the front's vertices valence 4. Returns
/// the number of new pairs.
long long pairTriangles(const TriMesh& triangles, std::vector<int>& partner);

/// The fit's moves may still leave a quad corner far from 90° (a move that makes a worse corner
/// of its fan better).
/// Where a corner of a polygon at a vertex deviates from its ideal (90°, 60° for a triangle) by
/// more than kQuadCornerWindow, the vertex moves back towards its position before the fit
/// (`unfitted`), half or all of the way, whichever makes its worst corner better. `triangles` (the
/// same vertices) moves along. Returns the number of moves.
long long restoreQuadCorners(PolygonSoup& quads, TriMesh& triangles,
                             const std::vector<Eigen::Vector3d>& unfitted);

/// Moves each interior vertex of `quads` whose valence is not 4 (a cone of index ±1/4) to the
/// centroid of its neighbours along polygon edges, projected onto the input, when that makes its
/// worst corner better and its triangles come no farther from the input: the lattice point sits
/// where the parameterization put the singular input vertex, which can leave one corner near
/// 180° and the others narrow (an icosphere's valence-3 vertices: 176° before, 140° after).
/// `triangles` moves along. The vertices marked in `copied` (of components copied unchanged)
/// stay. Returns the number of moves.
long long centreIrregularVertices(PolygonSoup& quads, TriMesh& triangles,
                                  const ClosestPointQuery& input, const std::vector<char>& copied);

/// Step 8 for N = 4 (repairBoundarySlivers) on the triangles of `triangles` that are no half of a
/// square (`partner`: squarePartners; boundary strips, hole fills) nor copied (kKeptAsIs): the
/// others keep their vertices, and `partner` follows the collapses' renumbering of the faces.
SliverRepairs repairSliversBesideSquares(TriMesh& triangles, std::vector<int>& partner,
                                         double sliverDegrees, double obtuseDegrees,
                                         double straightWithin);

}  // namespace hexcover::extract_detail
