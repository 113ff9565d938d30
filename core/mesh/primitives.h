#pragma once
// Meshes that the project generates itself: test shapes with known answers and the example mesh
// that scripts/run uses. All are manifold, consistently oriented (outward normals) and clean.

#include "core/mesh/mesh.h"

namespace hexcover {

/// Icosahedron subdivided `subdivisions` times (1-to-4 splits), vertices projected to the sphere.
/// 20·4^s faces; vertices of valence 5 at the 12 icosahedron corners, 6 elsewhere. χ = 2.
TriMesh makeIcosphere(int subdivisions, double radius = 1.0);

/// Torus with major radius R, minor radius r, a `around` × `tube` grid of quads each split along
/// the same diagonal: every vertex has valence 6. χ = 0.
TriMesh makeTorus(double majorRadius, double minorRadius, int around, int tube);

/// Open cylinder (a tube, two boundary loops) of the given radius and height along z, with
/// `around` vertices per ring and `rings` rings; alternate rings are offset by half a step so
/// that triangles are close to equilateral when height/(rings-1) ≈ √3/2 · 2πr/around. χ = 0.
TriMesh makeTube(double radius, double height, int around, int rings);

/// Planar patch of equilateral triangles with unit-free edge length `edge`, `columns` × `rows`
/// vertices in the z = 0 plane (rows offset by half an edge): all angles are 60°. One boundary
/// loop, χ = 1.
TriMesh makeEquilateralGrid(int columns, int rows, double edge = 1.0);

/// Closed box with edge lengths (sx, sy, sz) centred at the origin, each side a grid of
/// `divisions` × `divisions` rectangles split along alternating diagonals: 12 sharp edges of 90°
/// meeting at 8 corners (a CAD-like shape with known creases). χ = 2.
TriMesh makeBox(double sx, double sy, double sz, int divisions);

/// Closed cylinder of the given radius and height along z, tessellated as CAD exporters do: two
/// rims of `around` vertices, each side quad of the full height split into two triangles, each
/// cap a fan of `around` slivers around its centre vertex. 2·around + 2 vertices; the rims are
/// creases of 90°. χ = 2.
TriMesh makeCappedCylinder(double radius, double height, int around);

/// Latitude-longitude sphere of the given radius: `longitudes` vertices per ring, `latitudes`
/// bands from pole to pole, each pole a vertex of valence `longitudes` with a fan of slivers
/// (graphics and CAD exporters write spheres so). χ = 2.
TriMesh makeUvSphere(double radius, int longitudes, int latitudes);

/// A unit latitude-longitude sphere whose latitudes θ_j = π (j / latitudes)² crowd at the north
/// pole (its triangles there are ~100 times smaller than at the south pole: a mesh refined in one
/// place); with `bump` the radius is 1 + bump · sin 3θ · cos 4φ, whose curvature lines run along
/// the meridians and parallels. χ = 2.
TriMesh makeGradedSphere(int longitudes, int latitudes, double bump = 0.0);

/// L-shaped bracket as CAD exporters write it: the outline (0,0), (arm,0), (arm,width),
/// (width,width), (width,arm), (0,arm) extruded by `thickness` along z, each cap a fan from the
/// inner corner, each side one quad of the full height. 12 vertices; 18 creases of 90° (270° at
/// the inner corner). χ = 2.
TriMesh makeLBracket(double arm, double width, double thickness);

/// Square plate of the given side and thickness with a round hole through its centre, as CAD
/// exporters write it: each cap fans the hole's segments (holeSegments, rounded down to a
/// multiple of 4) to the square's corners, the hole's wall and the sides are quads of the full
/// thickness. Genus 1 (χ = 0); the rims of the caps are creases of 90°.
TriMesh makePlateWithHole(double side, double holeRadius, double thickness, int holeSegments);

/// A cell of Schwarz's P minimal surface, cos x + cos y + cos z = 0, by marching tetrahedra on
/// an n³ grid of cubes 2π/n wide over [−π − π/n, π + π/n]³ (six tetrahedra per cube around its
/// diagonal): an open surface of genus 0 whose six boundary loops lie on the grid's faces
/// (χ = −4), facing towards positive cos x + cos y + cos z. About 11 n² vertices. n should not be
/// a multiple of 3: then grid points with coordinates 2π/3 apart lie on the surface exactly
/// (cos a + cos(a + 2π/3) + cos(a − 2π/3) = 0), and the cuts through them are degenerate.
TriMesh makeSchwarzPCell(int n);

}  // namespace hexcover
