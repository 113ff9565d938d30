#pragma once
// Prescribed N-RoSy fields with known singularities, shared by the parameterization tests and
// its benchmark (header-only: the benchmark does not link GoogleTest).

#include <Eigen/Core>
#include <vector>

#include "core/field/rosy_field.h"
#include "core/mesh/primitives.h"

namespace hexcover::test {

inline Eigen::Vector3d faceCentroid(const TriMesh& mesh, OpenMesh::FaceHandle fh) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto vh : mesh.fv_range(fh)) c += toEigen(mesh.point(vh)) / 3.0;
  return c;
}

/// Icosphere: each face takes an edge direction of the icosahedron face it lies over; the
/// 6-RoSy field is smooth except at the 12 icosahedron vertices (index +1/6 each).
inline RosyField icosahedralField(const TriMesh& mesh) {
  const TriMesh ico = makeIcosphere(0);
  std::vector<Eigen::Vector3d> directions;
  for (const auto fh : mesh.faces()) {
    const Eigen::Vector3d c = faceCentroid(mesh, fh).normalized();
    double best = -2.0;
    Eigen::Vector3d direction;
    for (const auto gh : ico.faces()) {
      const double score = faceCentroid(ico, gh).normalized().dot(c);
      if (score <= best) continue;
      best = score;
      const auto h = ico.halfedge_handle(gh);
      direction = toEigen(ico.point(ico.to_vertex_handle(h))) -
                  toEigen(ico.point(ico.from_vertex_handle(h)));
    }
    directions.push_back(direction);
  }
  return rosyFieldFromDirections(mesh, directions, 6);
}

}  // namespace hexcover::test
