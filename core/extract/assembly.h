#pragma once
// Internal to core/extract: the output under construction (vertices and indexed triangles) and
// the repairs that keep it a manifold with the input's components (extract.h, steps 4 and 6).

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/extract/boundary.h"
#include "core/extract/extract.h"
#include "core/mesh/mesh.h"

namespace hexcover::extract_detail {

/// The output under construction: vertices (with the input component they belong to) and
/// triangles as indices.
struct Assembly {
  std::vector<Eigen::Vector3d> positions;
  std::vector<int> component;
  std::vector<Triangle> triangles;
  /// Vertices that make up the output's boundary loops (samples on the input boundary, or the
  /// lattice fronts in BoundaryMode::Lattice); holes through other vertices are gaps to fill.
  std::vector<bool> onBoundary;
  /// N = 4: the unit lattice squares (counter-clockwise corners), each also in `triangles` as
  /// (0, 1, 2) and (0, 2, 3); the quad output pairs the two triangles again where both remain.
  std::vector<std::array<int, 4>> squares;
  /// N of the lattice: 6 (Eisenstein: triangles) or 4 (Gauss: squares).
  int latticeOrder = 6;

  int addVertex(const Eigen::Vector3d& p, int inputComponent) {
    positions.push_back(p);
    component.push_back(inputComponent);
    onBoundary.push_back(false);
    return static_cast<int>(positions.size()) - 1;
  }
};

/// Mean length of the triangle edges at each vertex (0 where none): the local edge length.
std::vector<double> localEdgeLength(const Assembly& out);

/// Per vertex: the number of distinct neighbours in the triangles.
std::vector<int> vertexValences(const Assembly& out);

/// Per vertex: the number of its edges in the output polygons: vertexValences less, for N = 4,
/// the diagonals of the squares whose two triangles are both in `out.triangles`.
std::vector<int> polygonValences(const Assembly& out);

/// Area-weighted normal of the triangles at each vertex (zero where none).
std::vector<Eigen::Vector3d> vertexNormals(const Assembly& out);

/// Step 4a: drops triangles with a repeated corner and triangles that reuse a directed edge
/// (a lattice triangle covered twice, or overlapping ones at a fold), keeping the first.
void dropDegenerateAndOverlapping(std::vector<Triangle>& triangles, ExtractionReport& report);

/// Removes the vertices listed in `drop` with their triangles.
void removeVertices(Assembly& out, const std::vector<bool>& drop);

/// Fills the stretches of a boundary loop that are not on the output boundary: the whole loop
/// when none of it is, else each run of off-boundary vertices together with the boundary
/// vertices on either side (a notch in the boundary). The triangles go to `added`.
void fillGap(const std::vector<int>& loop, Assembly& out, std::vector<Triangle>& added,
             ExtractionReport& report);

/// Step 4c: what the previous steps left non-manifold is repaired locally: triangles that reuse
/// a directed edge are dropped, the triangles around a vertex with several fans are removed, and
/// the holes this leaves are filled (only their stretches off the output boundary).
void repairNonManifold(Assembly& out, ExtractionReport& report);

/// Step 4b, first: a vertex marked `eligible` whose triangles form several fans keeps only the
/// largest fan (on a tie the one with the lowest triangle index); the others' triangles are
/// dropped, again while dropping leaves such vertices. Near the input boundary this is where the
/// lattice, squeezed between two boundary loops, touches itself: a front through the vertex twice
/// would get a strip fan on each pass, and removing the vertex afterwards would open the strip
/// between the two loops and join them. Returns the number of triangles dropped.
long long keepLargestFans(std::vector<Triangle>& triangles, std::size_t vertexCount,
                          const std::vector<bool>& eligible);

/// Step 4, last: collapses each interior edge far shorter than the other edges of its two triangles
/// (kCopyEdgeRatio) whose collapse makes the valences of its four vertices more regular: the
/// two ends are copies of one lattice point, where the rounding put two singularities (spot's
/// horn: two +1/6 singularities 0.27 edge lengths apart leave a hole whose diagonal is 0.18 of
/// its sides; the diagonal fill gave two valence-4 and two valence-7 vertices, the merged point
/// is the +2/6 cone's one valence-4 vertex). Only where the two ends share exactly the two
/// apexes as neighbours (the collapse keeps the surface manifold); the merged vertex lies at the
/// edge's midpoint. Returns the number of collapses.
long long collapseLatticePointCopies(Assembly& out);

/// Step 6: an input component is copied unchanged when no lattice triangle fits on it, or (Follow
/// mode) when its lattice triangles do not have its topology (Euler characteristic, boundary
/// loops, one piece): a component too small for the lattice, or one whose remesh would close a
/// hole (counted apart: the pipeline redoes such a run on another lattice). The copy is taken
/// from `given`: `mesh` itself, or the input that `mesh` refines (its vertices are the first of
/// `mesh`'s, in the same components), so a kept component comes back as it was given.
void keepComponentsTooSmallForTheLattice(const TriMesh& mesh, const TriMesh& given,
                                         const std::vector<int>& faceComponent, int componentCount,
                                         const ExtractOptions& options, Assembly& out,
                                         ExtractionReport& report);

/// The referenced vertices and the triangles as an OpenMesh mesh; faces OpenMesh refuses (they
/// would make a vertex or edge non-manifold) are counted, and the holes they leave (boundary
/// loops through no vertex of the output's boundary) are closed by a fan around the loop's
/// centroid, as in step 4. `vertexOf` (#assembly vertices) receives each assembly vertex's handle
/// in the result (invalid for vertices not in it).
TriMesh buildMesh(const Assembly& out, ExtractionReport& report,
                  std::vector<TriMesh::VertexHandle>& vertexOf);

}  // namespace hexcover::extract_detail
