#pragma once
// Texture output of a parameterization (paper sec. 5.1, Fig. 9 and 12): the mesh with per-corner
// texture coordinates, and a hexagonal pattern image that tiles seamlessly under them.

#include <filesystem>

#include "core/mesh/mesh.h"
#include "core/param/parameterization.h"

namespace hexcover {

/// The mesh as a polygon soup (vertex and face order kept) with one texture coordinate per
/// corner: vt = (u, v/√3) for N = 6, where (u, v) = a·e1 + b·e2 are the Cartesian parameter
/// coordinates in units of h, so that an image covering vt ∈ [0,1]² holds one 1 : √3 period of
/// the hexagonal pattern and repeats seamlessly across every cut (the transitions are lattice
/// symmetries of the pattern). For N = 4, vt = (u, v): one unit square per lattice cell.
PolygonSoup texturedSoup(const TriMesh& mesh, const Parameterization& parameterization);

struct HexPatternOptions {
  int width = 512;              ///< pixels; the height is round(width·√3) for N = 6, width for N = 4
  double lineWidth = 0.03;      ///< line half-width in lattice units
  bool triangles = true;        ///< draw the lattice's triangles (the remesh's edges)
  bool hexagons = true;         ///< draw the dual hexagons around lattice points
};

/// Writes the pattern tile for `texturedSoup` as an 8-bit RGB PNG: light background, dark
/// hexagon edges (Voronoi cells of the lattice points), thin blue lattice edges. Throws
/// Error(InvalidOption) for a width below 8 or n ∉ {4, 6}, Error(Io) when the file cannot be written.
void writeLatticePatternPng(const std::filesystem::path& path, int n,
                            const HexPatternOptions& options = {});

}  // namespace hexcover
