#pragma once
// Repair of a polygon soup into the clean triangle mesh every later stage works on.
//
// Steps, in order, each counted in MeshReport::repairs (algorithm-notes "Input hygiene"):
//  1. refuse what cannot be repaired: no faces, over the face limit, indices out of range,
//     NaN/Inf coordinates;
//  2. triangulate polygons (ear clipping in the polygon's Newell plane);
//  3. weld vertices closer than weldTolerance · bounding-box diagonal;
//  4. drop degenerate triangles (repeated vertex, zero area) and duplicates (same vertex set);
//  5. split non-manifold edges (keep one consistently oriented pair of triangles together) and
//     non-manifold vertices (one vertex copy per fan of triangles);
//  6. orient each component consistently by breadth-first search over its edges (closed
//     components outward, open ones toward the majority of their triangles); a component where
//     this is impossible is non-orientable and refused;
//  7. drop unreferenced vertices, build the OpenMesh mesh and check every add_face.

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/report.h"

namespace hexcover {

struct RepairOptions {
  /// When false, nothing is changed except that polygons are triangulated: the soup must already
  /// be clean, manifold and consistently oriented, or repairMesh refuses it (listing the repairs
  /// it would need). Orientation is then left as it is (no outward flip of closed components).
  bool repair = true;
  /// Weld distance relative to the bounding-box diagonal of the referenced vertices; 0 welds
  /// only exactly coincident vertices.
  double weldTolerance = 1e-7;
  /// Refuse (Error(LimitExceeded)) soups with more triangles than this.
  std::size_t maxFaces = 5'000'000;
  /// With 2 or more, the input is measured beside its repair; the result is the same.
  int threads = 2;
};

struct RepairedMesh {
  TriMesh mesh;
  MeshReport report;
};

/// Validates `soup` (report.input), repairs it (report.repairs) and builds the triangle mesh
/// (report.result). Vertex order of the result follows the first occurrence in the input.
/// Throws Error(InvalidMesh) naming the problem and where (vertex, face or component index) for
/// an empty mesh, NaN/Inf coordinates, out-of-range indices or a non-orientable component;
/// Error(LimitExceeded) over options.maxFaces; Error(InvalidOption) for a bad option.
RepairedMesh repairMesh(const PolygonSoup& soup, const RepairOptions& options = {});

}  // namespace hexcover
