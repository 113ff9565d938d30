// The strip between a lattice front and the samples of an input boundary loop
// (core/extract/boundary.h, stitchStrip), and the directed edges and boundary loops of a
// triangle set.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/extract/boundary.h"
#include "core/extract/fan_geometry.h"

namespace hexcover::extract_detail {
namespace {

// Every directed edge is found from its first vertex, the first occurrence (in triangle order)
// where a set reuses one, with the third vertex of that occurrence's triangle.
TEST(DirectedEdges, FindTheFirstTriangleOfEachEdge) {
  const std::vector<Triangle> triangles = {{0, 1, 2}, {2, 1, 3}, {5, 0, 1}};
  const DirectedEdges edges(triangles);
  ASSERT_EQ(edges.size(), 9u);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int e = edges.edgeOf(t, k);
      EXPECT_EQ(edges.to(e), triangles[t][(k + 1) % 3]);
      EXPECT_EQ(edges.apex(e), triangles[t][(k + 2) % 3]);
      EXPECT_GE(e, edges.begin(triangles[t][k]));
      EXPECT_LT(e, edges.end(triangles[t][k]));
    }
  EXPECT_EQ(edges.find(0, 1), edges.edgeOf(0, 0));  // not triangle 2's reuse of 0 → 1
  EXPECT_EQ(edges.apex(edges.find(0, 1)), 2);
  EXPECT_EQ(edges.apex(edges.find(1, 2)), 0);
  EXPECT_EQ(edges.find(1, 0), -1);
  EXPECT_EQ(edges.find(4, 0), -1);  // a vertex without edges
  EXPECT_EQ(edges.find(9, 0), -1);  // beyond the set's vertices
  EXPECT_EQ(edges.begin(-1), edges.end(-1));
}

// A closed fan of three triangles around vertex 0 and a fourth triangle (4, 0, 1) that reuses
// the fan's directed edge 0 → 1: the rotation about 0 from the boundary edge 4 → 0 enters the
// closed fan and never meets a boundary edge. The trace stops there (it used to loop forever: a remesh
// job that hung when the extraction's repair left such a triangle).
TEST(BoundaryLoops, EndWhereARotationCyclesInATriangleSetThatReusesADirectedEdge) {
  const std::vector<Triangle> triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {4, 0, 1}};
  const auto loops = traceBoundaryLoops(triangles);
  ASSERT_FALSE(loops.empty());
  for (const auto& loop : loops) {
    ASSERT_FALSE(loop.empty());
    std::vector<int> sorted = loop;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "repeated vertex";
  }
}

// Where every directed edge is used once, each boundary edge is in exactly one loop: a 2 × 1
// strip of squares split into four triangles has one loop through its six vertices.
TEST(BoundaryLoops, FollowTheBoundaryOfAStripOnce) {
  const std::vector<Triangle> triangles = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
  const auto loops = traceBoundaryLoops(triangles);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 6u);
}

// A flat disc of radius 10 bounded by a circle sampled about once per unit. The lattice front
// runs 1.35 spacings inside the circle for half the loop, then steps to 0.5 spacings within half
// a spacing along the loop (the way a lattice row ends next to the boundary) and back out at the
// end: right after the inward step, every sample ahead of the step lies behind the front edge.
TEST(BoundaryStitch, FrontSteppingTowardsTheLoopGivesNoFan) {
  constexpr double kRadius = 10.0;
  constexpr int kSamples = 63;
  const double length = 2.0 * M_PI * kRadius;
  const double spacing = length / kSamples;
  std::vector<Eigen::Vector3d> positions;
  const auto add = [&](double arc, double depth) {
    const double angle = arc / kRadius, r = kRadius - depth * spacing;
    positions.push_back({r * std::cos(angle), r * std::sin(angle), 0.0});
    return static_cast<int>(positions.size()) - 1;
  };
  std::vector<int> outer, front;
  std::vector<double> outerArc, frontArc;
  for (int k = 0; k < kSamples; ++k) {
    outerArc.push_back(k * spacing);
    outer.push_back(add(outerArc.back(), 0.0));
  }
  for (int j = 0; j < 30; ++j) {
    frontArc.push_back((j - 0.08) * spacing);
    front.push_back(add(frontArc.back(), 1.35));
  }
  for (int j = 0; j < 33; ++j) {
    frontArc.push_back((29.44 + j) * spacing);
    front.push_back(add(frontArc.back(), 0.5));
  }
  const std::vector<Eigen::Vector3d> normals(positions.size(), Eigen::Vector3d::UnitZ());

  std::vector<Triangle> strip;
  stitchStrip(positions, normals, outer, outerArc, front, frontArc, length, strip);

  EXPECT_EQ(strip.size(), outer.size() + front.size());
  std::vector<int> triangles(positions.size(), 0);
  for (const auto& t : strip) {
    const Eigen::Vector3d n =
        (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
    EXPECT_GT(n.z(), 0.0) << "triangle " << t[0] << " " << t[1] << " " << t[2] << " faces down";
    const double smallest = angleRange({positions[t[0]], positions[t[1]], positions[t[2]]})[0];
    EXPECT_GT(smallest, 20.0) << "sliver " << t[0] << " " << t[1] << " " << t[2];
    for (const int v : t) ++triangles[v];
  }
  // Each vertex of a zipped strip has a few triangles; a fan would give one many.
  EXPECT_LE(*std::max_element(triangles.begin(), triangles.end()), 5);
}

}  // namespace
}  // namespace hexcover::extract_detail
