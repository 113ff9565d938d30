#pragma once
// JSON form of the mesh validation and repair report (core/mesh/report.h). Keys are snake_case;
// every counter of the report appears, zero or not, so clients can rely on the keys.

#include <nlohmann/json.hpp>

#include "core/mesh/report.h"

namespace hexcover {

/// {"vertices", "faces", "non_triangle_faces", "triangles", "components", "boundary_loops",
///  "euler_characteristic", "component_topology": [{vertices, edges, faces, boundary_loops,
///  euler_characteristic, genus (null when undefined), manifold, orientable}], and the defect
///  counts "non_manifold_edges", "non_manifold_vertices", "degenerate_faces", "duplicate_faces",
///  "duplicate_vertices", "unreferenced_vertices", "inconsistently_oriented_edges",
///  "non_orientable_components", "non_finite_coordinates"}.
nlohmann::json toJson(const MeshStatistics& statistics);

/// One key per repair step (RepairCounts), e.g. "welded_vertices", "dropped_degenerate_faces".
nlohmann::json toJson(const RepairCounts& counts);

/// {"input": MeshStatistics, "repaired": bool, and when repaired "repairs": RepairCounts and
///  "result": MeshStatistics}.
nlohmann::json toJson(const MeshReport& report);

}  // namespace hexcover
