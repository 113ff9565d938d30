#pragma once
// Extraction of the triangle remesh and its hexagonal dual from a HexCover parameterization
// (paper section 5.2).
//
// The output vertices are the lattice points (a, b) ∈ Z² (the Eisenstein integers of eq. (3) in
// lattice coordinates) that the parameterization maps onto the surface; the output triangles are
// the lattice's unit triangles {(a,b), (a+1,b), (a,b+1)} and {(a+1,b), (a+1,b+1), (a,b+1)},
// connected across cut edges through the transitions of eq. (2). Around a singularity of index
// ±1/6 the lattice closes up with 5 or 7 triangles, so irregular vertices appear only there.
//
// Steps:
// 1. Sanitize: every edge's transition is recomputed from the corner coordinates; corner
//    coordinates are snapped to a fixed-point grid (2^-24 lattice units) on which the integer
//    transitions hold exactly, and every singular vertex is put exactly on its holonomy's fixed
//    point. All later predicates are exact integer arithmetic on that grid.
// 2. Lattice points: for each parameter triangle, the integer points in its closed triangle; a
//    point on an edge or a vertex is shared with the neighbouring triangles (through the
//    transitions), so each is emitted exactly once, at its barycentric position on the surface.
// 3. Triangles: each unit lattice triangle is emitted by the parameter triangle that contains its
//    centroid (a+⅓, b+⅓) / (a+⅔, b+⅔); its corners are found by walking from the centroid across
//    parameter triangles (applying transitions). Triangles whose walk leaves the surface are cut by
//    the boundary; walks through flipped or degenerate parameter triangles are coverage gaps.
// 4. Repair: triangles covered more than once are dropped after the first; holes that do not
//    touch the input boundary (coverage gaps near folds or singularities) are filled locally;
//    an interior edge far shorter than its triangles' other edges, between two copies of one
//    lattice point (two singularities the rounding put on one point), is collapsed when that
//    makes the valences more regular: a +2/6 cone becomes one valence-4 vertex.
// 5. Boundary (BoundaryMode::Follow): lattice vertices closer than `boundarySnapDistance` edge
//    lengths to the input boundary of their own component are removed (a scan's loose triangles
//    beside a surface are not its boundary); where the lattice then touches itself at a vertex
//    near the boundary (squeezed between two nearby loops), only the vertex's largest fan of
//    triangles stays, so that no front passes a vertex twice. Each input boundary loop is
//    resampled (keeping corners sharper than `sharpBoundaryAngle`) and the strip between it and
//    the lattice front is triangulated, so the output boundary lies on the input boundary. The
//    samples are chosen so that every front vertex gets valence 6 (6 − a samples for a lattice
//    edges), which keeps the irregular vertices at the singularities next to the boundary too; a
//    sharp corner replaces the nearest sample within half a spacing (three quarters, for
//    triangles, at a corner turning by up to 80° between sides straight for a spacing), and one
//    with no sample that close gets a sample of its own when it turns by more than 80° or
//    (triangles) the chord between the samples around it would cut it off by more than half a
//    spacing (its front vertex then has valence 7). For squares (N = 4) a front vertex with a
//    polygon edges gets 5 − a samples, and along straight stretches of the front the strip is a row
//    of squares (valence 4 at the front). A front along several loops is zipped to their samples;
//    where the lattice keeps away from holes closer together than it, that strip is several edge
//    lengths wide, and its edges longer than 1.75 spacings are split at their midpoints (on the
//    input) before the strip's min-angle flips, so that it has interior vertices.
// 6. Components of the input whose remesh has fewer triangles than one hexagon (6), or not the
//    component's topology (Euler characteristic, boundary loops, one piece), are copied
//    unchanged (as given, before any refinement): steps 7 and 8 leave their vertices and
//    triangles as they are, and are skipped when every component is copied (the output is then
//    the input as it is), or, with ExtractOptions::finishOtherTopology off, when one was copied
//    for its topology.
// 7. Fit (surface_fit.h): vertices move over the input surface where the lattice cuts off a
//    sharp crease or tip (feature snapping), next to poor triangles (smoothing) and where the
//    angles stray from 60° (relaxation), when that does not raise the local deviation from the
//    input; last, interior vertices move off the input along their normal where that lowers the
//    two-sided deviation (balancing: a convex patch's triangles no longer lie all inside it);
//    the connectivity stays.
// 8. Boundary slivers: a triangle at the output boundary that still has an angle below
//    `sliverAngle` loses an edge by a collapse that raises the smallest angle around it (a
//    boundary vertex moves only onto a boundary neighbour, where the boundary runs straight or
//    stays within a quarter edge length without it; an interior vertex onto any neighbour),
//    then gets the edge flip that raises its pair's smallest angle (or lowers its largest,
//    above `obtuseAngle`: a reflex corner of the boundary in too few triangles). Both move valences
//    away from 6. The collapses remove the fans of slivers where the input boundary curls in a lip
//    narrower than an edge length (the Stanford bunny's base at K = V/16 and V/8: 3° and 6°
//    before). For N = 4 both run after the quads' corners are mended, on the triangles that are
//    no halves of squares.

#include <vector>

#include "core/common/run_context.h"
#include "core/common/timings.h"
#include "core/mesh/mesh.h"
#include "core/param/hexcover.h"
#include "core/param/parameterization.h"

namespace hexcover {

enum class BoundaryMode {
  Follow,   ///< output boundary loops lie on the input boundary loops (the remeshing default)
  Lattice,  ///< keep the jagged lattice boundary: only unit lattice triangles (pattern tiling)
};

struct ExtractOptions {
  BoundaryMode boundary = BoundaryMode::Follow;
  /// Lattice vertices closer than this many local edge lengths to the input boundary are
  /// replaced by boundary samples (Follow mode). In (0, 1).
  double boundarySnapDistance = 0.5;
  /// Boundary vertices of the input whose boundary turns by more than this many degrees are kept
  /// as output vertices (sharp corners). In [0, 180].
  double sharpBoundaryAngle = 30.0;
  /// Step 7: fit the remesh to the input surface (feature snapping, smoothing of poor triangles,
  /// relaxation, balancing). Off: the vertices stay at the lattice points' positions.
  bool fitToSurface = true;
  /// Step 7's balancing: interior vertices move off the input along their normal where that
  /// lowers the two-sided deviation (surface_fit.h). Off: every vertex stays on the input.
  bool balanceDeviation = true;
  /// Steps 7 and 8 also for a remesh with a component copied for its topology (step 6). Off:
  /// such a remesh, which a caller redoes with another lattice, is left as assembled
  /// (ExtractionReport::unfinished); extracting it again with this on finishes it.
  bool finishOtherTopology = true;
  /// Input vertices farther than this many local edge lengths from the remesh pull a remesh
  /// vertex onto themselves (step 7). In [0, 1); 0 disables snapping.
  double featureSnapDistance = 0.35;
  /// Step 8: triangles at the output boundary with an angle below this many degrees (issue 5's
  /// floor) get the edge collapse and the edge flip that raise it, at the cost of valences. In
  /// [0, 60); 0 disables the step.
  double sliverAngle = 20.0;
  /// Step 8: and a pair of triangles at the output boundary with an angle above this many
  /// degrees gets the edge flip that lowers it without lowering the pair's smallest (a reflex
  /// corner of the boundary split into two triangles only; the floor is 130°). In (60, 180];
  /// 180 disables these flips.
  double obtuseAngle = 120.0;
  /// Step 7's relaxation keeps the remesh close to the input's crease vertices: those with an
  /// edge whose dihedral angle is at least this many degrees. In [0, 180]; 0: none.
  double creaseAngle = kDefaultFeatureAngle;
  /// Worker threads of step 7's relaxation (the result is the same for any count). At least 1.
  int threads = 2;

  /// Throws Error(InvalidOption) naming the first bad option.
  void validate() const;
};

/// What extraction found and repaired. Counts are over the whole mesh.
struct ExtractionReport {
  long long latticePoints = 0;        ///< lattice points emitted (each exactly once)
  long long latticeTriangles = 0;     ///< unit lattice triangles emitted (N = 4: two per square)
  long long latticeSquares = 0;       ///< N = 4: unit lattice squares emitted
  long long boundaryClipped = 0;      ///< lattice triangles dropped because they leave the surface
  long long boundarySnapped = 0;      ///< lattice vertices removed near the input boundary
  long long boundarySamples = 0;      ///< vertices placed on the input boundary
  long long stripTriangles = 0;       ///< triangles between the lattice front and the boundary
  long long stripFlips = 0;           ///< edge flips among strip and fill triangles (min angle)
  long long stripSplits = 0;          ///< long strip and fill edges split at their midpoints
  long long boundarySlides = 0;       ///< boundary samples slid along the input boundary
  long long flippedParamTriangles = 0;     ///< parameter triangles with negative orientation
  long long degenerateParamTriangles = 0;  ///< parameter triangles with zero area
  long long transitionsCorrected = 0;  ///< edges whose given transition disagreed with the coords
  long long inconsistentVertices = 0;  ///< vertices whose transitions do not close up (not seamless)
  long long uncoveredTriangles = 0;    ///< lattice triangles whose walk met a fold (coverage gaps)
  long long overlappingTriangles = 0;  ///< lattice triangles covered more than once, dropped
  long long degenerateTriangles = 0;   ///< lattice triangles with repeated corners, dropped
  long long holesFilled = 0;           ///< interior holes (coverage gaps) closed locally
  long long holeTriangles = 0;         ///< triangles added to close them
  long long unmatchedBoundaryLoops = 0;  ///< input boundary loops without a single lattice front
  /// Lattice triangles near the input boundary dropped where the lattice touched itself at a
  /// vertex (all but the vertex's largest fan), before the strips were stitched.
  long long pinchedFanTriangles = 0;
  long long components = 0;              ///< components of the input (connected through edges)
  long long componentsKept = 0;  ///< input components too small for the lattice (step 6), copied
  long long keptVertices = 0;    ///< the vertices of those components
  /// Of those, components with lattice triangles enough whose triangles did not have the
  /// component's topology (BoundaryMode::Follow): another lattice (edge length) may fit.
  long long componentsKeptForTopology = 0;
  long long featureSnaps = 0;          ///< vertices moved onto a sharp feature of the input
  long long smoothedVertices = 0;      ///< vertex moves that opened up poor triangles
  long long relaxedVertices = 0;       ///< relaxation moves (angles nearer 60°)
  long long balancedVertices = 0;      ///< balancing moves (off the input, along the normal)
  long long outlierAngleMoves = 0;     ///< moves of corners of angles outside [30°, 100°]
  long long restoredVertices = 0;      ///< N = 4: fit moves taken back for the quad corners
  long long centredVertices = 0;       ///< N = 4: irregular quad vertices centred (quad_mesh.h)
  long long mergedTrianglePairs = 0;   ///< N = 4: pairs of strip or fill triangles made quads
  long long boundarySliverCollapses = 0;  ///< step 8: boundary vertices collapsed at slivers
  long long boundarySliverFlips = 0;   ///< step 8: flips of slivers at the output boundary
  long long nonManifoldVertices = 0;   ///< vertices with several fans, re-triangulated locally
  long long nonManifoldFacesDropped = 0;  ///< faces OpenMesh still refused (would be non-manifold)
  /// Step 4: short edges between two copies of one lattice point, collapsed.
  long long latticePointCopiesMerged = 0;
  /// Largest distance of an output triangle's centroid from the input surface (model units; 0
  /// without the fit, step 7): a triangle far off it spans a hole or a fold of a strip or fill.
  double farthestCentroid = 0.0;
  /// Steps 7 and 8 were left out: a component was copied for its topology and
  /// ExtractOptions::finishOtherTopology is off (never when every component was copied: such a
  /// remesh has no steps 7 and 8 to finish).
  bool unfinished = false;
  Timings timings;
};

/// The remesh: a triangle mesh, its hexagonal dual and the extraction report; for N = 4 also the
/// quad-dominant mesh.
struct Remesh {
  /// Manifold, consistently oriented triangle mesh (same orientation as the input). For N = 4
  /// each unit square of the lattice is two of its triangles, split along the square's diagonal
  /// (a, b)-(a+1, b+1).
  TriMesh triangles;
  /// Hexagonal dual as polygons: for each vertex of `triangles` the polygon through the centroids
  /// of its triangles in counter-clockwise order (hexagons at valence 6, pentagons/heptagons at
  /// singularities); at boundary vertices the polygon is closed through the midpoints of the two
  /// boundary edges and the vertex itself.
  PolygonSoup hexDual;  ///< empty for N = 4
  /// N = 4: `triangles` with the two triangles of each unit lattice square joined into a quad; the
  /// boundary strips, hole fills and squares cut by a repair stay triangles. Empty for N = 6.
  PolygonSoup quads;
  ExtractionReport report;
};

/// Extracts the remesh of `mesh` from its parameterization.
/// mesh: the repaired input (the mesh `param` was computed on).
/// param: #halfedges corner coordinates and #E transitions (core/param/parameterization.h).
/// given: null, or the input that `mesh` refines (refineLongEdges: its vertices are the first of
/// `mesh`'s, in the same components); the components copied unchanged (step 6) are taken from it.
/// Throws Error(InvalidOption) for bad options, Error(NumericalFailure) when the coordinates do
/// not fit the fixed-point grid (|a|, |b| ≥ 2^20 lattice units: the edge length is far too
/// small for the mesh), Error(Canceled) when context asks to stop.
Remesh extractRemesh(const TriMesh& mesh, const Parameterization& param,
                     const ExtractOptions& options = {}, const RunContext& context = {},
                     const TriMesh* given = nullptr);

/// The hexagonal dual of a triangle mesh (see Remesh::hexDual).
PolygonSoup hexagonalDual(const TriMesh& triangles);

}  // namespace hexcover
