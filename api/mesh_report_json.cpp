#include "api/mesh_report_json.h"

namespace hexcover {

nlohmann::json toJson(const MeshStatistics& s) {
  nlohmann::json components = nlohmann::json::array();
  for (const auto& c : s.componentTopology)
    components.push_back(
        {{"vertices", c.vertices},
         {"edges", c.edges},
         {"faces", c.faces},
         {"boundary_loops", c.boundaryLoops},
         {"euler_characteristic", c.eulerCharacteristic},
         {"genus", c.genus >= 0 ? nlohmann::json(c.genus) : nlohmann::json(nullptr)},
         {"manifold", c.manifold},
         {"orientable", c.orientable}});
  return {{"vertices", s.vertices},
          {"faces", s.faces},
          {"non_triangle_faces", s.nonTriangleFaces},
          {"triangles", s.triangles},
          {"components", s.components},
          {"boundary_loops", s.boundaryLoops},
          {"euler_characteristic", s.eulerCharacteristic},
          {"component_topology", std::move(components)},
          {"non_manifold_edges", s.nonManifoldEdges},
          {"non_manifold_vertices", s.nonManifoldVertices},
          {"degenerate_faces", s.degenerateFaces},
          {"duplicate_faces", s.duplicateFaces},
          {"duplicate_vertices", s.duplicateVertices},
          {"unreferenced_vertices", s.unreferencedVertices},
          {"inconsistently_oriented_edges", s.inconsistentlyOrientedEdges},
          {"non_orientable_components", s.nonOrientableComponents},
          {"non_finite_coordinates", s.nonFiniteCoordinates}};
}

nlohmann::json toJson(const RepairCounts& c) {
  return {{"polygons_triangulated", c.polygonsTriangulated},
          {"welded_vertices", c.weldedVertices},
          {"dropped_degenerate_faces", c.droppedDegenerateFaces},
          {"dropped_duplicate_faces", c.droppedDuplicateFaces},
          {"dropped_unreferenced_vertices", c.droppedUnreferencedVertices},
          {"split_non_manifold_edges", c.splitNonManifoldEdges},
          {"split_non_manifold_vertices", c.splitNonManifoldVertices},
          {"added_vertices", c.addedVertices},
          {"flipped_faces", c.flippedFaces},
          {"faces_refused_by_mesh", c.facesRefusedByMesh},
          {"dropped_faces", c.droppedFaces}};
}

nlohmann::json toJson(const MeshReport& report) {
  nlohmann::json json = {{"input", toJson(report.input)}, {"repaired", report.repaired}};
  if (report.repaired) {
    json["repairs"] = toJson(report.repairs);
    json["result"] = toJson(report.result);
  }
  return json;
}

}  // namespace hexcover
