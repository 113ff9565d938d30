// splitLongEdges: the same surface, sampled more finely.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "core/common/error.h"
#include "core/mesh/primitives.h"
#include "core/mesh/refine.h"
#include "core/mesh/topology.h"

namespace hexcover {
namespace {

using Triangle = std::array<Eigen::Vector3d, 3>;

std::vector<Triangle> trianglesOf(const TriMesh& mesh) {
  std::vector<Triangle> triangles;
  for (const auto f : mesh.faces()) {
    Triangle t;
    int k = 0;
    for (const auto v : f.vertices()) t[k++] = toEigen(mesh.point(v));
    triangles.push_back(t);
  }
  return triangles;
}

double area(const Triangle& t) { return 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm(); }

/// Whether p lies in triangle t: in its plane and with barycentric coordinates ≥ 0 (to `eps`
/// relative to the triangle's size).
bool inTriangle(const Eigen::Vector3d& p, const Triangle& t, double eps) {
  const Eigen::Vector3d u = t[1] - t[0], w = t[2] - t[0], n = u.cross(w), q = p - t[0];
  const double scale = std::max(u.norm(), w.norm());
  if (std::abs(q.dot(n.normalized())) > eps * scale) return false;
  const double a = n.dot(u.cross(q)) / n.squaredNorm(), b = n.dot(q.cross(w)) / n.squaredNorm();
  return b >= -eps && a >= -eps && a + b <= 1.0 + eps;
}

TEST(MeshRefine, SplitsLongEdgesInsideTheOriginalTriangles) {
  const TriMesh original = makeCappedCylinder(1.0, 2.0, 32);
  TriMesh refined = original;
  const double longest = 0.3;
  const long long splits = splitLongEdges(refined, longest);
  EXPECT_GT(splits, 0);
  EXPECT_EQ(refined.n_vertices(), original.n_vertices() + static_cast<std::size_t>(splits));
  for (const auto e : refined.edges()) EXPECT_LE(refined.calc_edge_length(e), longest);
  // Every new triangle lies in one original triangle, and the areas add up: the same surface.
  const std::vector<Triangle> before = trianglesOf(original);
  double areaBefore = 0.0, areaAfter = 0.0;
  for (const auto& t : before) areaBefore += area(t);
  for (const auto& t : trianglesOf(refined)) {
    areaAfter += area(t);
    bool inside = false;
    for (const auto& s : before)
      inside = inside || (inTriangle(t[0], s, 1e-9) && inTriangle(t[1], s, 1e-9) &&
                          inTriangle(t[2], s, 1e-9));
    EXPECT_TRUE(inside) << "a refined triangle leaves the original surface";
  }
  EXPECT_NEAR(areaAfter, areaBefore, 1e-12 * areaBefore);
  const MeshTopology a = computeTopology(original), b = computeTopology(refined);
  EXPECT_TRUE(a.sameAs(b));
}

TEST(MeshRefine, StopsAtTheFaceLimit) {
  TriMesh cylinder = makeCappedCylinder(1.0, 2.0, 16);
  const std::size_t limit = cylinder.n_faces() + 40;
  EXPECT_GT(splitLongEdges(cylinder, 0.01, limit), 0);
  EXPECT_LE(cylinder.n_faces(), limit);
  EXPECT_GE(cylinder.n_faces() + 2, limit);
}

TEST(MeshRefine, LeavesAMeshOfShortEdgesAsItIsAndRefusesABadLength) {
  TriMesh sphere = makeIcosphere(2);
  const std::size_t vertices = sphere.n_vertices();
  EXPECT_EQ(splitLongEdges(sphere, 1.0), 0);
  EXPECT_EQ(sphere.n_vertices(), vertices);
  EXPECT_THROW(splitLongEdges(sphere, 0.0), Error);
  EXPECT_THROW(splitLongEdges(sphere, std::numeric_limits<double>::quiet_NaN()), Error);
}

}  // namespace
}  // namespace hexcover
