#pragma once
// The quality floors of issue 5, shared by the pipeline tests (CI) and the quality-floor suite:
// topology kept, min angle >= 20°, max angle <= 130°, angle SD <= 6°, irregular interior vertices
// <= 2% of the vertices and no more than the field's singularities, each at a singularity, and the
// two-sided Hausdorff distance <= 1% of the bounding-box diagonal.

#include <gtest/gtest.h>

#include <algorithm>
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

/// Every floor of the issue, each as its own expectation so that a report lists all misses.
inline void expectQualityFloors(const RemeshResult& result, const std::string& name) {
  const QualityReport& m = result.metrics;
  SCOPED_TRACE(name + ": " + std::to_string(m.vertices) + " vertices, h = " +
               std::to_string(result.edgeLength));
  EXPECT_TRUE(m.topologyMatchesReference.value_or(false)) << "topology differs from the input";
  EXPECT_TRUE(m.topology.manifold);
  EXPECT_EQ(result.remesh.report.nonManifoldFacesDropped, 0);
  EXPECT_GE(m.angleMin, 20.0);
  EXPECT_LE(m.angleMax, 130.0);
  EXPECT_LE(m.angleSd, 6.0);
  EXPECT_LE(m.irregularInterior, 0.02 * m.vertices);
  EXPECT_LE(m.irregularInterior, static_cast<int>(result.singularities.size()));
  // "At a singularity": within two edge lengths of the field's singular vertex (the lattice
  // point of a ±1/6 singularity is within a unit of the vertex it is attached to).
  EXPECT_EQ(irregularAwayFromSingularities(result, 2.0 * result.edgeLength), 0);
  ASSERT_TRUE(m.distance.has_value());
  EXPECT_LE(m.distance->hausdorffPct, 1.0);
}

}  // namespace hexcover::test
