#pragma once
// Measures of meshes that several tests check.

#include <array>

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

}  // namespace hexcover::test
