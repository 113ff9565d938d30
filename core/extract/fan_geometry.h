#pragma once
// Angles and normals of a vertex's triangles with the vertex at a trial position (internal to
// core/extract): the acceptance tests of the surface fit.

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

#include "core/mesh/mesh.h"

namespace hexcover::extract_detail {

/// A moved triangle's normal must stay within acos(0.5) = 60° of its normal before the move.
inline constexpr double kMinNormalCosine = 0.5;

/// Angle at corner a of triangle (a, b, c), in degrees.
inline double angleAt(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      const Eigen::Vector3d& c) {
  const Eigen::Vector3d u = b - a, w = c - a;
  return std::atan2(u.cross(w).norm(), u.dot(w)) * 180.0 / M_PI;
}

/// Quad remeshes (N = 4) keep every polygon corner within this many degrees of its ideal angle.
inline constexpr double kQuadCornerWindow = 45.0;

/// The ideal angle of a corner of a remesh polygon: 90° in a quad (N = 4), 60° in a triangle.
inline double idealCornerAngle(std::size_t corners) { return corners == 4 ? 90.0 : 60.0; }

/// Angle at corner k of a polygon (corners counter-clockwise) minus its ideal angle, in degrees.
template <typename Corners>
double cornerDeviation(const Corners& corners, std::size_t k) {
  const std::size_t n = corners.size();
  return angleAt(corners[k], corners[(k + 1) % n], corners[(k + n - 1) % n]) - idealCornerAngle(n);
}

/// The largest |cornerDeviation| of a polygon's corners.
template <typename Corners>
double worstCornerDeviation(const Corners& corners) {
  double worst = 0.0;
  for (std::size_t k = 0; k < corners.size(); ++k)
    worst = std::max(worst, std::abs(cornerDeviation(corners, k)));
  return worst;
}

/// The smallest and largest angle of triangle (p0, p1, p2), in degrees.
inline std::array<double, 2> angleRange(const std::array<Eigen::Vector3d, 3>& p) {
  std::array<double, 2> range{180.0, 0.0};
  for (int j = 0; j < 3; ++j) {
    const double a = angleAt(p[j], p[(j + 1) % 3], p[(j + 2) % 3]);
    range = {std::min(range[0], a), std::max(range[1], a)};
  }
  return range;
}

/// Σ (α − 60°)² over the angles α of triangle (p0, p1, p2), in degrees².
inline double squaredAngleDeviation(const std::array<Eigen::Vector3d, 3>& p) {
  double sum = 0.0;
  for (int j = 0; j < 3; ++j) {
    const double a = angleAt(p[j], p[(j + 1) % 3], p[(j + 2) % 3]) - 60.0;
    sum += a * a;
  }
  return sum;
}

/// Unit normal of triangle (p0, p1, p2) (zero for a degenerate one).
inline Eigen::Vector3d triangleNormal(const std::array<Eigen::Vector3d, 3>& p) {
  return (p[1] - p[0]).cross(p[2] - p[0]).normalized();
}

/// Whether both triangles of the edge a–b of (a, b, c) and (b, a, d) flipped to c–d, (a, d, c)
/// and (d, b, c), face within 60° of the pair's area-weighted normal (a sliver's own normal is
/// noise).
inline bool flippedPairFacesAlike(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                  const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  const Eigen::Vector3d mean = ((b - a).cross(c - a) + (a - b).cross(d - b)).normalized();
  return mean.dot(triangleNormal({a, d, c})) > kMinNormalCosine &&
         mean.dot(triangleNormal({d, b, c})) > kMinNormalCosine;
}

/// Whether flipping the edge a–b of triangles (a, b, c) and (b, a, d) to c–d raises the pair's
/// smallest angle, when that is below `belowDegrees`, and the new triangles face alike
/// (flippedPairFacesAlike).
inline bool flipRaisesSmallestAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                                    double belowDegrees = 180.0) {
  const double before = std::min(angleRange({a, b, c})[0], angleRange({b, a, d})[0]);
  if (!(before < belowDegrees)) return false;
  const double after = std::min(angleRange({a, d, c})[0], angleRange({d, b, c})[0]);
  return after > before + 1e-9 && flippedPairFacesAlike(a, b, c, d);
}

/// Whether flipping the edge a–b of triangles (a, b, c) and (b, a, d) to c–d lowers the pair's
/// largest angle, when that is above `aboveDegrees`, without lowering its smallest, and the new
/// triangles face alike (flippedPairFacesAlike).
inline bool flipLowersLargestAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                   const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                                   double aboveDegrees) {
  const auto before = std::array{angleRange({a, b, c}), angleRange({b, a, d})};
  const double largest = std::max(before[0][1], before[1][1]);
  if (!(largest > aboveDegrees)) return false;
  const auto after = std::array{angleRange({a, d, c}), angleRange({d, b, c})};
  return std::max(after[0][1], after[1][1]) < largest - 1e-9 &&
         std::min(after[0][0], after[1][0]) >= std::min(before[0][0], before[1][0]) &&
         flippedPairFacesAlike(a, b, c, d);
}

/// The corners of face f, with vertex `moved` (if valid) at `movedTo`.
inline std::array<Eigen::Vector3d, 3> facePositions(const TriMesh& mesh,
                                                    OpenMesh::SmartFaceHandle f,
                                                    OpenMesh::VertexHandle moved,
                                                    const Eigen::Vector3d& movedTo) {
  std::array<Eigen::Vector3d, 3> p;
  int k = 0;
  for (const auto w : f.vertices()) p[k++] = w == moved ? movedTo : toEigen(mesh.point(w));
  return p;
}

/// Smallest and largest angle of v's triangles with v at p; {0, 180} when a triangle turns by
/// more than 60° (or degenerates). Triangles that also have the corner `vanishing` (valid when v
/// collapses onto that neighbour, p its position) are left out: the collapse removes them.
inline std::array<double, 2> fanAngleRange(
    const TriMesh& mesh, OpenMesh::SmartVertexHandle v, const Eigen::Vector3d& p,
    OpenMesh::VertexHandle vanishing = OpenMesh::VertexHandle()) {
  std::array<double, 2> range{180.0, 0.0};
  for (const auto f : v.faces()) {
    if (vanishing.is_valid() &&
        std::any_of(f.vertices().begin(), f.vertices().end(),
                    [&](OpenMesh::VertexHandle w) { return w == vanishing; }))
      continue;
    const auto after = facePositions(mesh, f, v, p);
    const Eigen::Vector3d before =
        triangleNormal(facePositions(mesh, f, OpenMesh::VertexHandle(), p));
    if (!(before.dot(triangleNormal(after)) > kMinNormalCosine)) return {0.0, 180.0};
    const auto r = angleRange(after);
    range = {std::min(range[0], r[0]), std::max(range[1], r[1])};
  }
  return range;
}

/// How far an angle range strays from 60°, relative to the room the quality floors leave on each
/// side (down to 20°, up to 130°): max((60 − min) / 40, (max − 60) / 70). 0 for equilateral
/// triangles, 1 at a floor; a small angle and a large one weigh alike when equally near theirs.
inline double angleBadness(const std::array<double, 2>& range) {
  return std::max((60.0 - range[0]) / 40.0, (range[1] - 60.0) / 70.0);
}

/// angleBadness of v's triangles with v at p (≥ 1.5 when one turns by more than 60°).
inline double fanAngleBadness(const TriMesh& mesh, OpenMesh::SmartVertexHandle v,
                              const Eigen::Vector3d& p) {
  return angleBadness(fanAngleRange(mesh, v, p));
}

}  // namespace hexcover::extract_detail
