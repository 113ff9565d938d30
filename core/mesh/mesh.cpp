#include "core/mesh/mesh.h"

#include <array>
#include <map>
#include <utility>

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
  appendToPolygonSoup(soup, mesh);
  return soup;
}

void appendToPolygonSoup(PolygonSoup& soup, const TriMesh& mesh, const Eigen::Vector3d& offset) {
  const auto first = static_cast<int>(soup.vertexCount());
  soup.positions.reserve(soup.positions.size() + mesh.n_vertices());
  for (const auto vh : mesh.vertices()) soup.positions.push_back(toEigen(mesh.point(vh)) + offset);
  soup.faceStarts.reserve(soup.faceStarts.size() + mesh.n_faces());
  soup.cornerVertices.reserve(soup.cornerVertices.size() + 3 * mesh.n_faces());
  for (const auto fh : mesh.faces()) {
    std::array<int, 3> corners{};
    int i = 0;
    for (const auto vh : fh.vertices()) corners[i++] = first + vh.idx();
    soup.addFace(corners);
  }
}

SoupEdges soupEdges(const PolygonSoup& soup) {
  SoupEdges result;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> index;  // (min, max) -> edge
  for (std::size_t f = 0; f < soup.faceCount(); ++f) {
    const std::size_t start = soup.faceStarts[f], size = soup.faceSize(f);
    for (std::size_t k = 0; k < size; ++k) {
      const std::uint32_t a = soup.cornerVertices[start + k];
      const std::uint32_t b = soup.cornerVertices[start + (k + 1) % size];
      const auto [it, added] = index.try_emplace(std::minmax(a, b), result.edges.size());
      if (added) {
        result.edges.push_back({a, b});
        result.uses.push_back(0);
      }
      ++result.uses[it->second];
    }
  }
  return result;
}

}  // namespace hexcover
