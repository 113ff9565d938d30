#pragma once
// N-RoSy direction fields on the faces of a triangle mesh (paper section 3).
//
// Conventions shared by every later stage:
// - faceDirection[f] is one representative of the N directions in face f: a unit 3D vector in
//   the face's plane. The others are it rotated by 2πk/N counter-clockwise about the face normal.
// - edgeMatching[e] = r_e in {0..N-1} for the edge e with halfedges h0 = halfedge(e,0) in face
//   f0 and h1 = halfedge(e,1) in face f1: the representative of f0, parallel-transported across
//   the edge into f1 (unfolding the two triangles about the edge), is closest to the
//   representative of f1 rotated by 2π r_e / N (paper eq. (2): F_u in f0 pairs with R^{r} F_u in
//   f1). Read from f1 to f0 it is (N - r_e) mod N. Boundary edges have 0. Exception: on the
//   edges of a clustering re-solve region, the matching is the one the corrected connection
//   ρ_e + c_e intends (closest relative to ρ_e + c_e), which differs from the closest one only
//   where |c_e| > π/N, next to needle-like vertices; δ_e below then lies within π/N of c_e.
// - A singularity of index I/N at a vertex (I ≠ 0). Indices include the angle defect, so that on
//   every component Σ I/N = χ (Poincaré–Hopf, with boundary vertices by their own rule).
//
// How the index of a vertex v is computed (N even; θ_f = tangent angle of faceDirection[f] in the
// frame of core/geometry/frames.h, ρ_e = transport angle of edge e from f0 to f1):
// - Per interior edge e: δ_e = θ_f1 − θ_f0 − ρ_e + 2π r_e / N, the turn of the field across e
//   relative to parallel transport, in [−π/N, π/N] (the matching r_e is the one that makes it so).
// - Per boundary edge b, with face-side halfedge u→w in face f (surface on its left): ψ_b = the
//   angle from the edge's direction u→w to the nearest of the N field directions in f, in
//   [−π/N, π/N] (0 when the field follows the boundary).
// - I_v = (N / 2π) · (K_v + Σ_e s_{v,e} δ_e + Σ_b t_{v,b} ψ_b), an exact integer up to rounding,
//   where K_v is the angle defect of core/geometry/frames.h (2π − Σ angles inside, π − Σ angles
//   = the boundary's turning angle at a boundary vertex), the first sum runs over the interior
//   edges at v with s = +1 when the counter-clockwise loop around v (seen from the normal side)
//   crosses e from f0 to f1 (v = to_vertex(h0)) and −1 otherwise, and the second sum over the two
//   boundary edges at a boundary vertex with t = +1 for the edge leaving v (v = u) and −1 for the
//   edge arriving at v (v = w).
// - Interior vertices: this is the usual index, Σ_edges Arg(u_g / (r^N u_f)) + N K_v over 2π in
//   the power representation u = e^{iNθ}. Boundary vertices: the field's turn relative to the
//   boundary tangent through the vertex's fan, plus the boundary's turning angle; a field that
//   follows the boundary gets I_v = N (turning angle + field turn) / 2π, e.g. I = 2 (index 2/6)
//   at a 60° corner of a flat equilateral patch whose field follows both edges.
// - Both sums telescope over a component (each δ_e enters two vertices with opposite signs, each
//   ψ_b the two ends of its edge), so Σ_v I_v / N = (Σ K_v) / 2π = χ by discrete Gauss–Bonnet.
//   Every construction checks this per component and that each I_v is an integer to 1e-6; a
//   failure is a bug and throws std::logic_error.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/common/run_context.h"
#include "core/common/timings.h"
#include "core/geometry/curvature.h"
#include "core/mesh/mesh.h"

namespace hexcover {

struct Singularity {
  int vertex = -1;  ///< vertex index in the mesh the field lives on
  int index = 0;    ///< I: the singularity's index is I / N
  Eigen::Vector3d position{0, 0, 0};
  bool onBoundary = false;  ///< a boundary vertex (its index counts by the boundary rule)
};

struct RosyField {
  int n = 6;                                   ///< symmetry order N (6 or 4)
  std::vector<Eigen::Vector3d> faceDirection;  ///< #F unit representatives
  std::vector<int> edgeMatching;               ///< #E matchings r_e, see above
  std::vector<Singularity> singularities;      ///< final singularities, sorted by vertex
  int singularitiesInitial = 0;                ///< count before clustering
  int eulerCharacteristic = 0;                 ///< χ = Σ over components = Σ I / N
  double singularityDistance = 0.0;            ///< d_sing used by clustering (mesh units)
  std::vector<bool> sharpEdges;                ///< #E creases the field follows (empty: none)
  Timings timings;                             ///< per step: geometry, curvature, ...
  double seconds = 0.0;  ///< wall time (less than the sum of the steps: two run concurrently)
};

/// What one field direction does along mesh boundaries.
enum class BoundaryAlignment {
  Tangent,  ///< faces with a boundary edge have one direction along it (hard constraint)
  Free,     ///< no boundary condition (natural boundary)
};

/// Options of computeRosyField; every default is the paper's choice where it makes one.
struct FieldOptions {
  int n = 6;  ///< symmetry order N: 6 (triangle/hex remeshing) or 4 (quads)
  CurvatureOptions curvature;
  /// Directional constraints at strong cylindrical faces (section 3.2).
  bool curvatureConstraints = true;
  /// λ: weight of a directional constraint relative to the smoothness weights (≈ 1.7 per edge
  /// on equilateral triangles). Soft: noisy curvature directions are smoothed over.
  double constraintWeight = 0.1;
  /// Radius of the filter that turns the angle defect K into K̄ (Ray et al.), as a fraction of
  /// the bounding-box diagonal. 0 keeps K̄ = K (plain smoothest field).
  double curvatureFilterRadius = 0.02;
  /// Singularity clustering (section 3.3).
  bool clusterSingularities = true;
  /// d_sing in mesh units; 0 means singularityDistanceFraction × bounding-box diagonal.
  double singularityDistance = 0.0;
  double singularityDistanceFraction = 0.1;  ///< the paper's 0.1 B
  /// Largest |I| a merge may create, unless it lowers the larger |I| of the pair; 0: no limit
  /// (the paper: every pair closer than d_sing is merged). The parameterization sets 1
  /// (kMergedIndexForLattice in core/param/hexcover.h): every merged singularity then has index
  /// ±1/N, whose fixed point is a lattice point, and pairs of +1/N may stay closer than d_sing.
  int maxMergedIndex = 0;
  /// Creases: sharp edges (core/geometry/sharp_edges.h) of at least this dihedral angle in
  /// degrees, on lines at least sharpLineLength long (mesh units), constrain the field of their
  /// faces along the crease with weight sharpEdgeWeight (instead of a curvature constraint), and
  /// are passed on in RosyField::sharpEdges for the parameterization to put lattice lines on.
  /// 0: none (the paper has no creases; its future work).
  double sharpEdgeAngle = 0.0;
  double sharpLineLength = 0.0;
  double sharpEdgeWeight = 1.0;
  /// Follow only the crease lines that a lattice of this symmetry can follow all at once
  /// (latticeCompatibleCreases: of two lines meeting at 90°, the longer one for N = 6).
  bool compatibleCreasesOnly = false;
  BoundaryAlignment boundary = BoundaryAlignment::Tangent;
  /// With Tangent: a boundary edge's tangent is the chord from the boundary vertex `reach` steps
  /// before it to the one `reach` steps after it (0: the edge itself). Smooths the zigzags of
  /// scanned boundaries, each of which would otherwise be a boundary singularity.
  int boundaryTangentReach = 1;
  /// Threads: with 2 or more, the solve's terms are built while the frames are computed, the
  /// curvature and the constraints while the connection is corrected for K̄, and clustering
  /// searches for close pairs on both. The result is the same for any count.
  int threads = 2;

  /// Empty when valid; otherwise names the bad option and its valid range.
  std::string validate() const;
};

/// The geometry-aware N-RoSy field of paper section 3: curvature (core/geometry), directional
/// constraints at strong cylindrical faces, the smooth solve with the filtered Gauss curvature K̄
/// (Ray et al.), singularity extraction, clustering with d_sing and the re-solve in the region R
/// around the collapsed singularities (K̄ zero except 2πI/N at the remaining ones), repeated on the
/// result (R = the newly collapsed ones) while each round collapses fewer pairs than the one before
/// (at most 6 rounds); then, with maxMergedIndex > 0, interior singularities of a higher |I| that
/// their vertex's angle defect does not carry (the smoothest field's +N/N at the centre of a flat
/// cap whose rim it follows) are split into first-order ones around it and the field re-solved
/// there the same way (core/field/clustering.h, splitHighOrderNodes). Interior singularities
/// then end up at least d_sing apart (graph-geodesic
/// distance along edges) except pairs whose merge maxMergedIndex forbids; boundary vertices keep
/// the indices of the boundary rule and are not clustered. At needle-like vertices (angle defect
/// far from a multiple of 2π/N, e.g. 109° at a valence-4 vertex of feline) the corrected connection
/// of a re-solve turns by more than π/N across single edges; the matchings there follow the
/// corrected connection (see above), so that the re-solved field has its target
/// singularities instead of a cluster around the needle. Known limitation: when R contains a loop
/// that is not contractible on the surface, the correction does not control the holonomy along it,
/// and the re-solve may bring cancelled pairs back. Every component is solved on its own terms (its
/// own constraints, or its smoothest field when it has none). Deterministic: the same mesh and
/// options give the same bytes, whatever options.threads. Poincaré–Hopf is checked per component
/// after every solve (std::logic_error on failure: a bug). Timings: geometry, connection,
/// filter_gauss_curvature, initial_solve (its terms), curvature, constraints (see
/// FieldOptions::threads for what runs concurrently), initial_solve, initial_singularities, then
/// per clustering round clustering, cluster_solve, cluster_singularities, then split (and
/// split_solve, split_singularities when a singularity was split). Throws
/// Error(InvalidOption) for invalid options, Error(InvalidMesh) for a mesh without faces,
/// Error(NumericalFailure) if a factorization fails, Error(Canceled) when `context` asks.
RosyField computeRosyField(const TriMesh& mesh, const FieldOptions& options = {},
                           const RunContext& context = {});

/// The field along only the creases that a lattice of `field`'s symmetry can follow together
/// (`options` with compatibleCreasesOnly, core/geometry/sharp_edges.h latticeCompatibleCreases),
/// when `field`, computed with `options`, follows others too (a box's creases meeting at 90°);
/// nullopt when it follows no crease or only compatible ones. The remesh pipeline and
/// `hexcover param` parameterize along both and keep the better result.
std::optional<RosyField> computeCompatibleCreaseField(const TriMesh& mesh, const RosyField& field,
                                                      const FieldOptions& options,
                                                      const RunContext& context = {});

/// Builds a RosyField from given per-face representative directions (#F vectors, any tangent
/// vectors: they are projected to the face plane and normalized): computes the matchings and the
/// singularities (interior and boundary, see above) and checks Poincaré–Hopf per component.
/// singularitiesInitial = singularities.size(). Used by the solver and by tests that prescribe
/// fields. Throws Error(InvalidOption) for n not in {2, 4, 6, ...} or a wrong-sized or non-finite
/// `directions`, std::logic_error if the index check fails (a bug).
RosyField rosyFieldFromDirections(const TriMesh& mesh, std::vector<Eigen::Vector3d> directions,
                                  int n);

}  // namespace hexcover
