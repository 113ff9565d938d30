#pragma once
// The validation and repair report of an input mesh: what was found in the input, what repair
// did (every step counted), and the topology of the result. A plain struct; api/mesh_report_json.h
// turns it into JSON.

#include <cstddef>
#include <vector>

namespace hexcover {

/// Topology of one connected component (faces connected through shared vertices).
/// χ = V − E + F over the component's referenced vertices, edges and triangles. The genus
/// g = (2 − χ − b)/2 is defined only when the component is manifold and orientable; else −1.
struct ComponentTopology {
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t faces = 0;  ///< triangles
  std::size_t boundaryLoops = 0;
  long long eulerCharacteristic = 0;
  int genus = -1;
  bool manifold = true;
  bool orientable = true;
};

/// What one mesh looks like: sizes, topology and defects. Topology is measured on the polygons
/// fan-triangulated, without welding (as the file stores it).
struct MeshStatistics {
  std::size_t vertices = 0;           ///< vertex records, referenced or not
  std::size_t faces = 0;              ///< polygons as stored
  std::size_t nonTriangleFaces = 0;   ///< polygons with more than 3 corners
  std::size_t triangles = 0;          ///< after triangulating polygons (Σ (corners − 2))
  std::size_t components = 0;         ///< connected components of faces
  std::size_t boundaryLoops = 0;      ///< loops of edges with exactly one incident triangle
  long long eulerCharacteristic = 0;  ///< Σ over components
  std::vector<ComponentTopology> componentTopology;  ///< one entry per component, largest first

  std::size_t nonManifoldEdges = 0;      ///< edges with more than two incident triangles
  std::size_t nonManifoldVertices = 0;   ///< vertices whose incident faces form several fans
  std::size_t degenerateFaces = 0;       ///< repeated corner, fewer than 3 corners, or zero area
  std::size_t duplicateFaces = 0;        ///< faces with the same vertex set as an earlier face
  std::size_t duplicateVertices = 0;     ///< vertices at exactly the position of an earlier one
  std::size_t unreferencedVertices = 0;  ///< vertices used by no face
  std::size_t inconsistentlyOrientedEdges = 0;  ///< two-face edges traversed in the same direction
  std::size_t nonOrientableComponents = 0;
  std::size_t nonFiniteCoordinates = 0;  ///< vertices with a NaN or infinite coordinate
};

/// What repair did, one counter per step (repair.h). Face counts are in triangles (after
/// triangulation); every input triangle is either in the result or in exactly one drop counter:
/// triangles − droppedDegenerateFaces − droppedDuplicateFaces − facesRefusedByMesh = result faces.
struct RepairCounts {
  std::size_t polygonsTriangulated = 0;         ///< polygons split into triangles
  std::size_t weldedVertices = 0;               ///< vertices merged into another (within tolerance)
  std::size_t droppedDegenerateFaces = 0;       ///< triangles with a repeated vertex or zero area
  std::size_t droppedDuplicateFaces = 0;        ///< triangles with the vertex set of an earlier one
  std::size_t droppedUnreferencedVertices = 0;  ///< vertices used by no remaining triangle
  std::size_t splitNonManifoldEdges = 0;        ///< edges with > 2 triangles that were separated
  std::size_t splitNonManifoldVertices = 0;     ///< vertices with several fans (not on such edges)
  std::size_t addedVertices = 0;                ///< vertex copies created by the two splits
  std::size_t flippedFaces = 0;                 ///< triangles reversed to orient components
  std::size_t facesRefusedByMesh = 0;           ///< triangles OpenMesh's add_face refused
  std::size_t droppedFaces = 0;                 ///< total triangles dropped, for any reason
};

/// The full report: the input as found, what repair did, and the result.
struct MeshReport {
  MeshStatistics input;   ///< as found (validateMesh)
  bool repaired = false;  ///< whether repair ran (then `repairs` and `result` are filled)
  RepairCounts repairs;
  MeshStatistics result;  ///< the repaired triangle mesh
};

}  // namespace hexcover
