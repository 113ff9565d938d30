#pragma once
// The quality floors of issue 5, shared by the pipeline tests (CI) and the quality-floor suite:
// topology kept, min angle >= 20°, max angle <= 130°, angle SD <= 6°, irregular interior vertices
// <= 2% of the vertices and no more than the field's singularities, each at a singularity, and the
// two-sided Hausdorff distance <= 1% of the bounding-box diagonal. Besides the floors: the remesh
// does not intersect itself (the surface fit moves vertices off the input).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/pipeline/pipeline.h"

namespace hexcover::test {

inline RemeshOptions quarterOf(long long vertices) {
  RemeshOptions options;
  options.targetVertices = std::max<long long>(4, vertices / 4);
  return options;
}

inline long long referencedVertices(const PolygonSoup& soup) {
  std::vector<bool> used(soup.vertexCount(), false);
  for (const auto v : soup.cornerVertices) used[v] = true;
  return std::count(used.begin(), used.end(), true);
}

/// Interior vertices of valence ≠ 6 farther than `radius` from every singularity.
inline int irregularAwayFromSingularities(const RemeshResult& result, double radius) {
  const TriMesh& out = result.remesh.triangles;
  int count = 0;
  for (const auto v : out.vertices()) {
    if (out.is_boundary(v) || out.is_isolated(v) || out.valence(v) == 6) continue;
    const Eigen::Vector3d p = toEigen(out.point(v));
    const bool near = std::any_of(result.singularities.begin(), result.singularities.end(),
                                  [&](const Singularity& s) { return (s.position - p).norm() <= radius; });
    count += near ? 0 : 1;
  }
  return count;
}

/// Whether the open segment p–q crosses triangle (a, b, c) (Möller–Trumbore; touching and
/// coplanar cases count as no crossing).
inline bool segmentCrossesTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                   const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                   const Eigen::Vector3d& c) {
  const Eigen::Vector3d d = q - p, e1 = b - a, e2 = c - a, n = d.cross(e2);
  const double det = e1.dot(n);
  if (std::abs(det) < 1e-14 * d.squaredNorm() * e1.norm()) return false;
  const Eigen::Vector3d s = p - a, m = s.cross(e1);
  const double u = s.dot(n) / det, v = d.dot(m) / det, t = e2.dot(m) / det;
  return u > 0.0 && v > 0.0 && u + v < 1.0 && t > 0.0 && t < 1.0;
}

/// Edges of `mesh` that cross a triangle they do not share a vertex with (self-intersections),
/// found through a uniform grid of cells one mean edge length wide.
inline int edgeTriangleCrossings(const TriMesh& mesh) {
  if (mesh.n_edges() == 0) return 0;
  double cell = 0.0;
  for (const auto e : mesh.edges()) cell += mesh.calc_edge_length(e);
  cell /= static_cast<double>(mesh.n_edges());
  using Key = std::array<long long, 3>;
  const auto keyOf = [&](const Eigen::Vector3d& x) {
    return Key{static_cast<long long>(std::floor(x[0] / cell)),
               static_cast<long long>(std::floor(x[1] / cell)),
               static_cast<long long>(std::floor(x[2] / cell))};
  };
  const auto forCells = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, auto&& visit) {
    const Key a = keyOf(lo), b = keyOf(hi);
    for (long long i = a[0]; i <= b[0]; ++i)
      for (long long j = a[1]; j <= b[1]; ++j)
        for (long long k = a[2]; k <= b[2]; ++k) visit(Key{i, j, k});
  };
  std::map<Key, std::vector<int>> grid;
  for (const auto f : mesh.faces()) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    for (const auto v : f.vertices())
      lo = lo.cwiseMin(toEigen(mesh.point(v))), hi = hi.cwiseMax(toEigen(mesh.point(v)));
    forCells(lo, hi, [&](const Key& key) { grid[key].push_back(f.idx()); });
  }
  int crossings = 0;
  for (const auto e : mesh.edges()) {
    const auto v0 = e.v0(), v1 = e.v1();
    const Eigen::Vector3d p = toEigen(mesh.point(v0)), q = toEigen(mesh.point(v1));
    std::set<int> tested;
    forCells(p.cwiseMin(q), p.cwiseMax(q), [&](const Key& key) {
      const auto found = grid.find(key);
      if (found == grid.end()) return;
      for (const int face : found->second) {
        if (!tested.insert(face).second) continue;
        std::array<Eigen::Vector3d, 3> corner;
        bool shares = false;
        int i = 0;
        for (const auto v : mesh.fv_range(mesh.face_handle(face))) {
          corner[i++] = toEigen(mesh.point(v));
          shares = shares || v == v0 || v == v1;
        }
        if (!shares && segmentCrossesTriangle(p, q, corner[0], corner[1], corner[2])) ++crossings;
      }
    });
  }
  return crossings;
}

/// What a floor's failure names: the mesh, its vertex count and h.
inline std::string floorTrace(const RemeshResult& result, const std::string& name) {
  return name + ": " + std::to_string(result.metrics.vertices) +
         " vertices, h = " + std::to_string(result.edgeLength);
}

/// The floors that do not depend on how many vertices the remesh has for its shape: topology
/// kept, manifold, angles within [20°, 130°], irregular interior vertices no more than the
/// field's singularities and each at one, and no self-intersection. Each is its own expectation
/// so that a report lists all misses.
inline void expectTopologyAndAngleFloors(const RemeshResult& result, const std::string& name) {
  const QualityReport& m = result.metrics;
  SCOPED_TRACE(floorTrace(result, name));
  EXPECT_TRUE(m.topologyMatchesReference.value_or(false)) << "topology differs from the input";
  EXPECT_TRUE(m.topology.manifold);
  EXPECT_EQ(result.remesh.report.nonManifoldFacesDropped, 0);
  EXPECT_GE(m.angleMin, 20.0);
  EXPECT_LE(m.angleMax, 130.0);
  EXPECT_LE(m.irregularInterior, static_cast<int>(result.singularities.size()));
  // "At a singularity": within two edge lengths of the field's singular vertex (the lattice
  // point of a ±1/6 singularity is within a unit of the vertex it is attached to).
  EXPECT_EQ(irregularAwayFromSingularities(result, 2.0 * result.edgeLength), 0);
  EXPECT_EQ(edgeTriangleCrossings(result.remesh.triangles), 0) << "the remesh intersects itself";
}

/// Every floor of the issue: expectTopologyAndAngleFloors, and angle SD <= 6°, irregular
/// interior vertices <= 2% of the vertices, Hausdorff distance <= 1% of the diagonal.
inline void expectQualityFloors(const RemeshResult& result, const std::string& name) {
  expectTopologyAndAngleFloors(result, name);
  const QualityReport& m = result.metrics;
  SCOPED_TRACE(floorTrace(result, name));
  EXPECT_LE(m.angleSd, 6.0);
  EXPECT_LE(m.irregularInterior, 0.02 * m.vertices);
  ASSERT_TRUE(m.distance.has_value());
  EXPECT_LE(m.distance->hausdorffPct, 1.0);
}

}  // namespace hexcover::test
