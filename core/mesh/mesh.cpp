#include "core/mesh/mesh.h"

#include <array>

namespace hexcover {

double boundingBoxDiagonal(const TriMesh& mesh) {
  if (mesh.n_vertices() == 0) return 0.0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto vh : mesh.vertices()) {
    const Eigen::Vector3d p = toEigen(mesh.point(vh));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

PolygonSoup toPolygonSoup(const TriMesh& mesh) {
  PolygonSoup soup;
  soup.positions.reserve(mesh.n_vertices());
  for (const auto vh : mesh.vertices()) soup.positions.push_back(toEigen(mesh.point(vh)));
  soup.faceStarts.reserve(mesh.n_faces() + 1);
  soup.cornerVertices.reserve(3 * mesh.n_faces());
  for (const auto fh : mesh.faces()) {
    std::array<int, 3> corners{};
    int i = 0;
    for (const auto vh : fh.vertices()) corners[i++] = vh.idx();
    soup.addFace(corners);
  }
  return soup;
}

}  // namespace hexcover
