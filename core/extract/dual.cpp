// The hexagonal dual of the remesh (paper section 5.1: hexagonal patterns; algorithm notes,
// "Hex dual"): one polygon per vertex through the centroids of its triangles.

#include "core/extract/extract.h"

namespace hexcover {

PolygonSoup hexagonalDual(const TriMesh& triangles) {
  using HH = TriMesh::HalfedgeHandle;
  PolygonSoup dual;
  // Dual vertices: one centroid per triangle (at the triangle's index), then on demand the
  // midpoints of boundary edges and the boundary vertices themselves.
  dual.positions.reserve(triangles.n_faces());
  for (const auto f : triangles.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto v : triangles.fv_range(f)) c += toEigen(triangles.point(v));
    dual.positions.push_back(c / 3.0);
  }
  std::vector<int> edgeMidpoint(triangles.n_edges(), -1);
  const auto midpoint = [&](HH h) {
    const auto e = triangles.edge_handle(h);
    if (edgeMidpoint[e.idx()] < 0) {
      edgeMidpoint[e.idx()] = static_cast<int>(dual.positions.size());
      dual.positions.push_back(0.5 * (toEigen(triangles.point(triangles.from_vertex_handle(h))) +
                                      toEigen(triangles.point(triangles.to_vertex_handle(h)))));
    }
    return edgeMidpoint[e.idx()];
  };

  std::vector<int> polygon;
  for (const auto v : triangles.vertices()) {
    if (triangles.is_isolated(v)) continue;
    polygon.clear();
    if (!triangles.is_boundary(v)) {
      // Outgoing halfedges counter-clockwise; the face of each lies between it and the next.
      for (const auto h : triangles.voh_ccw_range(v)) polygon.push_back(triangles.face_handle(h).idx());
    } else {
      // OpenMesh keeps a boundary vertex's halfedge on the boundary: v -> w with no face. The
      // first face counter-clockwise follows the incoming boundary edge x -> v.
      const HH outgoing = triangles.halfedge_handle(v);
      HH h = triangles.opposite_halfedge_handle(triangles.prev_halfedge_handle(outgoing));
      polygon.push_back(midpoint(h));
      while (!triangles.is_boundary(h)) {
        polygon.push_back(triangles.face_handle(h).idx());
        h = triangles.opposite_halfedge_handle(triangles.prev_halfedge_handle(h));
      }
      polygon.push_back(midpoint(h));
      polygon.push_back(static_cast<int>(dual.positions.size()));
      dual.positions.push_back(toEigen(triangles.point(v)));
    }
    dual.addFace(polygon);
  }
  return dual;
}

}  // namespace hexcover
