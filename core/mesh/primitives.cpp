#include "core/mesh/primitives.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace hexcover {
namespace {

using VH = TriMesh::VertexHandle;

TriMesh::Point point(double x, double y, double z) { return {x, y, z}; }

/// Adds the triangle (a, b, c), turned so that its normal points along `outward`.
void addFaceFacing(TriMesh& mesh, VH a, VH b, VH c, const TriMesh::Point& outward) {
  const TriMesh::Point normal = (mesh.point(b) - mesh.point(a)) % (mesh.point(c) - mesh.point(a));
  if ((normal | outward) >= 0.0)
    mesh.add_face(a, b, c);
  else
    mesh.add_face(a, c, b);
}

/// Adds the planar quad a-b-c-d as two triangles facing `outward`.
void addQuadFacing(TriMesh& mesh, VH a, VH b, VH c, VH d, const TriMesh::Point& outward) {
  addFaceFacing(mesh, a, b, c, outward);
  addFaceFacing(mesh, a, c, d, outward);
}

}  // namespace

TriMesh makeIcosphere(int subdivisions, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> positions = {
      {-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
      {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
      {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& p : positions) p.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = midpoints.try_emplace(key, static_cast<int>(positions.size()));
      if (inserted) positions.push_back((positions[a] + positions[b]).normalized());
      return it->second;
    };
    std::vector<std::array<int, 3>> refined;
    refined.reserve(4 * faces.size());
    for (const auto& [a, b, c] : faces) {
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      refined.push_back({a, ab, ca});
      refined.push_back({b, bc, ab});
      refined.push_back({c, ca, bc});
      refined.push_back({ab, bc, ca});
    }
    faces = std::move(refined);
  }
  TriMesh mesh;
  std::vector<VH> handles;
  handles.reserve(positions.size());
  for (const auto& p : positions) handles.push_back(mesh.add_vertex(toOpenMesh(radius * p)));
  for (const auto& [a, b, c] : faces) mesh.add_face(handles[a], handles[b], handles[c]);
  return mesh;
}

TriMesh makeTorus(double majorRadius, double minorRadius, int around, int tube) {
  TriMesh mesh;
  std::vector<VH> handles;
  handles.reserve(static_cast<std::size_t>(around) * tube);
  for (int i = 0; i < around; ++i) {
    const double a = 2.0 * M_PI * i / around;
    for (int j = 0; j < tube; ++j) {
      const double b = 2.0 * M_PI * j / tube;
      const double ring = majorRadius + minorRadius * std::cos(b);
      handles.push_back(
          mesh.add_vertex(point(ring * std::cos(a), ring * std::sin(a), minorRadius * std::sin(b))));
    }
  }
  const auto at = [&](int i, int j) { return handles[(i % around) * tube + (j % tube)]; };
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < tube; ++j) {
      // (i, j) -> (i+1, j) runs along the major circle, (i, j) -> (i, j+1) around the tube;
      // this winding gives outward normals.
      mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  return mesh;
}

TriMesh makeTube(double radius, double height, int around, int rings) {
  TriMesh mesh;
  std::vector<VH> handles;
  handles.reserve(static_cast<std::size_t>(around) * rings);
  for (int k = 0; k < rings; ++k) {
    const double z = rings > 1 ? height * k / (rings - 1) : 0.0;
    const double offset = (k % 2) * 0.5;
    for (int i = 0; i < around; ++i) {
      const double a = 2.0 * M_PI * (i + offset) / around;
      handles.push_back(mesh.add_vertex(point(radius * std::cos(a), radius * std::sin(a), z)));
    }
  }
  const auto at = [&](int k, int i) { return handles[k * around + (i % around)]; };
  for (int k = 0; k + 1 < rings; ++k) {
    for (int i = 0; i < around; ++i) {
      if (k % 2 == 0) {  // the upper ring is shifted forward by half a step
        mesh.add_face(at(k, i), at(k, i + 1), at(k + 1, i));
        mesh.add_face(at(k, i + 1), at(k + 1, i + 1), at(k + 1, i));
      } else {  // the lower ring is shifted forward
        mesh.add_face(at(k, i), at(k + 1, i + 1), at(k + 1, i));
        mesh.add_face(at(k, i), at(k, i + 1), at(k + 1, i + 1));
      }
    }
  }
  return mesh;
}

TriMesh makeEquilateralGrid(int columns, int rows, double edge) {
  TriMesh mesh;
  std::vector<VH> handles;
  handles.reserve(static_cast<std::size_t>(columns) * rows);
  const double rowHeight = edge * std::sqrt(3.0) / 2.0;
  for (int r = 0; r < rows; ++r) {
    const double offset = (r % 2) * 0.5 * edge;
    for (int c = 0; c < columns; ++c)
      handles.push_back(mesh.add_vertex(point(offset + c * edge, r * rowHeight, 0.0)));
  }
  const auto at = [&](int r, int c) { return handles[r * columns + c]; };
  for (int r = 0; r + 1 < rows; ++r) {
    for (int c = 0; c + 1 < columns; ++c) {
      if (r % 2 == 0) {  // the row above is shifted right
        mesh.add_face(at(r, c), at(r, c + 1), at(r + 1, c));
        mesh.add_face(at(r, c + 1), at(r + 1, c + 1), at(r + 1, c));
      } else {  // this row is shifted right
        mesh.add_face(at(r, c), at(r + 1, c + 1), at(r + 1, c));
        mesh.add_face(at(r, c), at(r, c + 1), at(r + 1, c + 1));
      }
    }
  }
  return mesh;
}

TriMesh makeBox(double sx, double sy, double sz, int divisions) {
  TriMesh mesh;
  const int d = divisions;
  // Surface grid points (i, j, k) ∈ [0, d]³ with a coordinate at 0 or d, shared by the sides.
  std::map<std::array<int, 3>, VH> handles;
  const auto at = [&](std::array<int, 3> g) {
    const auto [it, inserted] = handles.try_emplace(g);
    if (inserted)
      it->second = mesh.add_vertex(point(sx * (static_cast<double>(g[0]) / d - 0.5),
                                         sy * (static_cast<double>(g[1]) / d - 0.5),
                                         sz * (static_cast<double>(g[2]) / d - 0.5)));
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;  // (u, w, axis) is right-handed
    for (const int side : {0, d}) {
      for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b) {
          std::array<std::array<int, 3>, 4> q;  // counter-clockwise seen from +axis
          for (int c = 0; c < 4; ++c) {
            q[c][axis] = side;
            q[c][u] = a + (c == 1 || c == 2);
            q[c][w] = b + (c >= 2);
          }
          std::array<VH, 4> v{at(q[0]), at(q[1]), at(q[2]), at(q[3])};
          if (side == 0) std::swap(v[1], v[3]);  // outward: −axis
          if ((a + b) % 2 == 0) {
            mesh.add_face(v[0], v[1], v[2]);
            mesh.add_face(v[0], v[2], v[3]);
          } else {
            mesh.add_face(v[0], v[1], v[3]);
            mesh.add_face(v[1], v[2], v[3]);
          }
        }
    }
  }
  return mesh;
}

TriMesh makeCappedCylinder(double radius, double height, int around) {
  TriMesh mesh;
  std::vector<VH> bottom, top;
  for (int i = 0; i < around; ++i) {
    const double angle = 2.0 * M_PI * i / around;
    const double x = radius * std::cos(angle), y = radius * std::sin(angle);
    bottom.push_back(mesh.add_vertex(point(x, y, 0.0)));
    top.push_back(mesh.add_vertex(point(x, y, height)));
  }
  const VH bottomCentre = mesh.add_vertex(point(0.0, 0.0, 0.0));
  const VH topCentre = mesh.add_vertex(point(0.0, 0.0, height));
  for (int i = 0; i < around; ++i) {
    const int j = (i + 1) % around;
    mesh.add_face(bottom[i], bottom[j], top[j]);
    mesh.add_face(bottom[i], top[j], top[i]);
    mesh.add_face(bottomCentre, bottom[j], bottom[i]);
    mesh.add_face(topCentre, top[i], top[j]);
  }
  return mesh;
}

namespace {

/// Latitude-longitude sphere: ring j (1 ≤ j < latitudes) at polar angle latitude(j), each point at
/// distance radius(θ, φ) from the origin; the poles are vertices with fans of `longitudes` faces.
template <typename Latitude, typename Radius>
TriMesh latitudeLongitudeSphere(int longitudes, int latitudes, const Latitude& latitude,
                                const Radius& radius) {
  const auto at = [&](double theta, double phi) {
    const double r = radius(theta, phi);
    return point(r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                 r * std::cos(theta));
  };
  TriMesh mesh;
  const VH north = mesh.add_vertex(point(0.0, 0.0, radius(0.0, 0.0)));
  std::vector<std::vector<VH>> rings;
  for (int j = 1; j < latitudes; ++j) {
    std::vector<VH> ring;
    for (int i = 0; i < longitudes; ++i)
      ring.push_back(mesh.add_vertex(at(latitude(j), 2.0 * M_PI * i / longitudes)));
    rings.push_back(std::move(ring));
  }
  const VH south = mesh.add_vertex(point(0.0, 0.0, -radius(M_PI, 0.0)));
  for (int i = 0; i < longitudes; ++i) {
    const int k = (i + 1) % longitudes;
    mesh.add_face(north, rings.front()[i], rings.front()[k]);
    mesh.add_face(south, rings.back()[k], rings.back()[i]);
    for (std::size_t j = 0; j + 1 < rings.size(); ++j) {
      mesh.add_face(rings[j][i], rings[j + 1][i], rings[j + 1][k]);
      mesh.add_face(rings[j][i], rings[j + 1][k], rings[j][k]);
    }
  }
  return mesh;
}

}  // namespace

TriMesh makeUvSphere(double radius, int longitudes, int latitudes) {
  return latitudeLongitudeSphere(
      longitudes, latitudes, [&](int j) { return M_PI * j / latitudes; },
      [&](double, double) { return radius; });
}

TriMesh makeGradedSphere(int longitudes, int latitudes, double bump) {
  return latitudeLongitudeSphere(
      longitudes, latitudes,
      [&](int j) {
        const double t = static_cast<double>(j) / latitudes;
        return M_PI * t * t;
      },
      [&](double theta, double phi) {
        return 1.0 + bump * std::sin(3.0 * theta) * std::cos(4.0 * phi);
      });
}

TriMesh makeLBracket(double arm, double width, double thickness) {
  TriMesh mesh;
  const std::array<std::array<double, 2>, 6> outline{
      {{0.0, 0.0}, {arm, 0.0}, {arm, width}, {width, width}, {width, arm}, {0.0, arm}}};
  std::array<VH, 6> bottom, top;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    bottom[i] = mesh.add_vertex(point(outline[i][0], outline[i][1], 0.0));
    top[i] = mesh.add_vertex(point(outline[i][0], outline[i][1], thickness));
  }
  constexpr std::size_t kInnerCorner = 3;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const std::size_t j = (i + 1) % outline.size();
    const TriMesh::Point side = mesh.point(bottom[j]) - mesh.point(bottom[i]);
    addQuadFacing(mesh, bottom[i], bottom[j], top[j], top[i], point(side[1], -side[0], 0.0));
    if (i != kInnerCorner && j != kInnerCorner) {
      addFaceFacing(mesh, bottom[kInnerCorner], bottom[i], bottom[j], point(0.0, 0.0, -1.0));
      addFaceFacing(mesh, top[kInnerCorner], top[i], top[j], point(0.0, 0.0, 1.0));
    }
  }
  return mesh;
}

TriMesh makePlateWithHole(double side, double holeRadius, double thickness, int holeSegments) {
  TriMesh mesh;
  const int quarter = std::max(1, holeSegments / 4), n = 4 * quarter;
  const double half = 0.5 * side;
  // Corner k at 45° + 90°·k; hole point i at 360°·i / n.
  std::array<std::array<VH, 4>, 2> corner;
  std::array<std::vector<VH>, 2> hole;
  for (int level = 0; level < 2; ++level) {
    const double z = level * thickness;
    for (int k = 0; k < 4; ++k) {
      const double angle = M_PI / 4.0 + M_PI / 2.0 * k;
      corner[level][k] = mesh.add_vertex(
          point(std::copysign(half, std::cos(angle)), std::copysign(half, std::sin(angle)), z));
    }
    for (int i = 0; i < n; ++i) {
      const double angle = 2.0 * M_PI * i / n;
      hole[level].push_back(
          mesh.add_vertex(point(holeRadius * std::cos(angle), holeRadius * std::sin(angle), z)));
    }
  }
  for (int level = 0; level < 2; ++level) {
    const TriMesh::Point up = point(0.0, 0.0, level == 0 ? -1.0 : 1.0);
    // Each hole segment fanned to the corner of its quarter, and between two quarters the
    // triangle of their corners and the hole point on the boundary.
    for (int i = 0; i < n; ++i)
      addFaceFacing(mesh, hole[level][i], hole[level][(i + 1) % n], corner[level][i / quarter], up);
    for (int k = 0; k < 4; ++k)
      addFaceFacing(mesh, corner[level][(k + 3) % 4], corner[level][k], hole[level][k * quarter],
                    up);
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    const TriMesh::Point inward = -(mesh.point(hole[0][i]) + mesh.point(hole[0][j]));
    addQuadFacing(mesh, hole[0][i], hole[0][j], hole[1][j], hole[1][i], inward);
  }
  for (int k = 0; k < 4; ++k) {
    const int l = (k + 1) % 4;
    const TriMesh::Point outward = mesh.point(corner[0][k]) + mesh.point(corner[0][l]);
    addQuadFacing(mesh, corner[0][k], corner[0][l], corner[1][l], corner[1][k], outward);
  }
  return mesh;
}

TriMesh makeSchwarzPCell(int n) {
  const auto value = [](const Eigen::Vector3d& p) {
    return std::cos(p.x()) + std::cos(p.y()) + std::cos(p.z());
  };
  // (n + 1)³ grid points 2π/n apart, half a spacing off the lattice of multiples of 2π/n: on
  // that lattice cos x = 0 and cos y = −cos z meet, and cuts through grid points would give
  // degenerate triangles.
  const auto gridPoint = [n](int i, int j, int k) {
    const auto at = [n](int g) { return -M_PI + 2.0 * M_PI * (g - 0.5) / n; };
    return Eigen::Vector3d(at(i), at(j), at(k));
  };
  const auto gridIndex = [n](int i, int j, int k) {
    return (static_cast<std::int64_t>(i) * (n + 1) + j) * (n + 1) + k;
  };
  // The function at every grid point, once (each is a corner of up to 24 tetrahedra).
  std::vector<double> values(static_cast<std::size_t>(n + 1) * (n + 1) * (n + 1));
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      for (int k = 0; k <= n; ++k) values[gridIndex(i, j, k)] = value(gridPoint(i, j, k));
  const auto valueAt = [&](const std::array<int, 3>& g) {
    return values[gridIndex(g[0], g[1], g[2])];
  };
  TriMesh mesh;
  // One vertex per grid edge that the surface crosses, where the linear interpolant is zero.
  std::map<std::pair<std::int64_t, std::int64_t>, VH> crossing;
  const auto vertexOn = [&](const std::array<int, 3>& a, const std::array<int, 3>& b) {
    const std::int64_t ia = gridIndex(a[0], a[1], a[2]), ib = gridIndex(b[0], b[1], b[2]);
    const auto key = std::make_pair(std::min(ia, ib), std::max(ia, ib));
    if (const auto it = crossing.find(key); it != crossing.end()) return it->second;
    const Eigen::Vector3d pa = gridPoint(a[0], a[1], a[2]), pb = gridPoint(b[0], b[1], b[2]);
    const double fa = valueAt(a), fb = valueAt(b);
    const VH v = mesh.add_vertex(toOpenMesh(pa + fa / (fa - fb) * (pb - pa)));
    crossing.emplace(key, v);
    return v;
  };
  constexpr std::array<std::array<int, 3>, 8> kCorner = {
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
  constexpr std::array<std::array<int, 4>, 6> kTetrahedra = {
      {{0, 5, 1, 6}, {0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}}};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        for (const auto& tetrahedron : kTetrahedra) {
          std::vector<std::array<int, 3>> inside, outside;
          for (const int c : tetrahedron) {
            const std::array<int, 3> g{i + kCorner[c][0], j + kCorner[c][1], k + kCorner[c][2]};
            (valueAt(g) < 0.0 ? inside : outside).push_back(g);
          }
          if (inside.empty() || outside.empty()) continue;
          // The triangle or quad where the surface cuts the tetrahedron (a, b, c, d) = (inside
          // corners, then outside ones), ordered by the sign of det(b − a, c − a, d − a) on the
          // grid's integers so that it faces the outside corners, towards positive values. (The
          // cut's own normal is noise where it passes next to a grid point.)
          std::vector<std::array<int, 3>> corners = inside;
          corners.insert(corners.end(), outside.begin(), outside.end());
          const auto along = [&](int e, int axis) { return corners[e][axis] - corners[0][axis]; };
          const int det = along(1, 0) * (along(2, 1) * along(3, 2) - along(2, 2) * along(3, 1)) -
                          along(1, 1) * (along(2, 0) * along(3, 2) - along(2, 2) * along(3, 0)) +
                          along(1, 2) * (along(2, 0) * along(3, 1) - along(2, 1) * along(3, 0));
          // With det > 0 the cuts (ab, ac, ad) around a and (da, db, dc) around d face a's way
          // out and d's way in (det(a − d, b − d, c − d) = −det), and the quad (ac, ad, bd, bc)
          // faces from {a, b} to {c, d}: all towards the outside corners.
          const auto add = [&](VH x, VH y, VH z) {
            det > 0 ? mesh.add_face(x, y, z) : mesh.add_face(x, z, y);
          };
          if (inside.size() == 2) {
            const VH q0 = vertexOn(inside[0], outside[0]), q1 = vertexOn(inside[0], outside[1]),
                     q2 = vertexOn(inside[1], outside[1]), q3 = vertexOn(inside[1], outside[0]);
            add(q0, q1, q2);
            add(q0, q2, q3);
          } else {
            const auto& apex = corners[inside.size() == 1 ? 0 : 3];
            std::vector<VH> cut;
            for (const auto& other : corners)
              if (&other != &apex) cut.push_back(vertexOn(apex, other));
            add(cut[0], cut[1], cut[2]);
          }
        }
  return mesh;
}

}  // namespace hexcover
