#pragma once
// Measures of meshes that several tests check.

#include <algorithm>
#include <array>
#include <limits>

#include "core/mesh/mesh.h"

namespace hexcover::test {

/// Signed volume enclosed by a closed mesh (positive when its faces turn outward).
inline double signedVolume(const TriMesh& mesh) {
  double volume = 0.0;
  for (const auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int i = 0;
    for (const auto v : f.vertices()) p[i++] = toEigen(mesh.point(v));
    volume += p[0].dot(p[1].cross(p[2])) / 6.0;
  }
  return volume;
}

/// Distance from p to the nearest vertex of the mesh (infinity for a mesh without vertices).
inline double distanceToNearestVertex(const TriMesh& mesh, const Eigen::Vector3d& p) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto v : mesh.vertices())
    nearest = std::min(nearest, (toEigen(mesh.point(v)) - p).norm());
  return nearest;
}

}  // namespace hexcover::test
