// The repairs of the output under construction (core/extract/assembly.h): collapsing the short
// edge between two copies of one lattice point; keeping one fan where the lattice touches itself.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/extract/assembly.h"

namespace hexcover::extract_detail {
namespace {

constexpr int kGridSize = 7;

int gridVertex(int i, int j) { return j * kGridSize + i; }

// A patch of the equilateral lattice (unit edges): every vertex off the patch's rim has
// valence 6.
Assembly equilateralPatch() {
  Assembly out;
  for (int j = 0; j < kGridSize; ++j)
    for (int i = 0; i < kGridSize; ++i)
      out.addVertex({i + 0.5 * j, j * std::sqrt(3.0) / 2.0, 0.0}, 0);
  for (int j = 0; j + 1 < kGridSize; ++j)
    for (int i = 0; i + 1 < kGridSize; ++i) {
      out.triangles.push_back({gridVertex(i, j), gridVertex(i + 1, j), gridVertex(i, j + 1)});
      out.triangles.push_back(
          {gridVertex(i + 1, j), gridVertex(i + 1, j + 1), gridVertex(i, j + 1)});
    }
  return out;
}

// The centre vertex x split in two copies `gap` apart across the line through its neighbours
// n0 = x + (1, 0) and n3 = x − (1, 0): the copies get valence 5, n0 and n3 valence 7, the
// pattern that two singularities rounded onto one lattice point leave. Returns the new copy.
int splitCentre(Assembly& out, double gap) {
  const int x = gridVertex(3, 3);
  const Eigen::Vector3d centre = out.positions[x];
  const int copy = out.addVertex(centre - Eigen::Vector3d(0, gap / 2, 0), 0);
  out.positions[x] = centre + Eigen::Vector3d(0, gap / 2, 0);
  for (auto& t : out.triangles) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const int v : t) mean += out.positions[v] / 3.0;
    if (mean.y() < centre.y())
      for (int& v : t) v = v == x ? copy : v;
  }
  out.triangles.push_back({gridVertex(4, 3), x, copy});
  out.triangles.push_back({gridVertex(2, 3), copy, x});
  return copy;
}

int irregularInterior(const Assembly& out) {
  const std::vector<int> valence = vertexValences(out);
  int irregular = 0;
  for (int j = 1; j + 1 < kGridSize; ++j)
    for (int i = 1; i + 1 < kGridSize; ++i) irregular += valence[gridVertex(i, j)] != 6 ? 1 : 0;
  return irregular;
}

TEST(LatticePointCopies, AreMergedIntoOneRegularVertex) {
  Assembly out = equilateralPatch();
  const Eigen::Vector3d centre = out.positions[gridVertex(3, 3)];
  const std::size_t triangles = out.triangles.size();
  const int copy = splitCentre(out, 0.1);
  EXPECT_EQ(vertexValences(out)[copy], 5);
  EXPECT_EQ(vertexValences(out)[gridVertex(4, 3)], 7);
  EXPECT_EQ(irregularInterior(out), 3);  // the copy is not a grid vertex

  EXPECT_EQ(collapseLatticePointCopies(out), 1);
  EXPECT_EQ(out.triangles.size(), triangles);
  EXPECT_EQ(irregularInterior(out), 0);
  EXPECT_EQ(vertexValences(out)[copy], 0) << "the copy is merged away";
  EXPECT_LT((out.positions[gridVertex(3, 3)] - centre).norm(), 1e-12);
  for (const auto& t : out.triangles) {
    const Eigen::Vector3d n = (out.positions[t[1]] - out.positions[t[0]])
                                  .cross(out.positions[t[2]] - out.positions[t[0]]);
    EXPECT_GT(n.z(), 0.0) << "every triangle keeps its orientation";
  }
  EXPECT_EQ(collapseLatticePointCopies(out), 0) << "nothing left to merge";
}

TEST(LatticePointCopies, StayApartWhenTheirEdgeIsNotFarShorterThanItsNeighbours) {
  Assembly out = equilateralPatch();
  splitCentre(out, 0.4);
  EXPECT_EQ(collapseLatticePointCopies(out), 0);
  EXPECT_EQ(irregularInterior(out), 3);
}

TEST(LatticePointCopies, StayApartOnTheOutputBoundary) {
  Assembly out = equilateralPatch();
  const int copy = splitCentre(out, 0.1);
  out.onBoundary[copy] = true;
  EXPECT_EQ(collapseLatticePointCopies(out), 0);
}

TEST(LatticePointCopies, ShortEdgesOfARegularPatchStayWhereACollapseWouldMakeValencesIrregular) {
  Assembly out = equilateralPatch();
  // Vertex (3, 3) pushed to 0.1 from its neighbour (4, 3): a short edge, all valences 6.
  out.positions[gridVertex(3, 3)] = out.positions[gridVertex(4, 3)] - Eigen::Vector3d(0.1, 0, 0);
  EXPECT_EQ(collapseLatticePointCopies(out), 0);
  EXPECT_EQ(irregularInterior(out), 0);
}

/// The patch's triangles at `v`, in the patch's order (counter-clockwise from (i+1, j)).
std::vector<Triangle> star(const Assembly& out, int v) {
  std::vector<Triangle> around;
  for (const auto& t : out.triangles)
    if (std::find(t.begin(), t.end(), v) != t.end()) around.push_back(t);
  return around;
}

bool contains(const std::vector<Triangle>& triangles, const Triangle& t) {
  return std::find(triangles.begin(), triangles.end(), t) != triangles.end();
}

// The star of an interior vertex without two of its six triangles that share no edge: a fan of
// one triangle and a fan of three, touching at the vertex (a bowtie, as where the lattice is
// squeezed between two nearby boundary loops).
TEST(PinchedFans, OnlyTheLargestFanStays) {
  Assembly out = equilateralPatch();
  const int v = gridVertex(3, 3);
  const std::vector<Triangle> around = star(out, v);
  ASSERT_EQ(around.size(), 6u);
  // Triangles sharing an edge at v: the star's cycle, found by the shared corners.
  const auto adjacent = [&](const Triangle& a, const Triangle& b) {
    int shared = 0;
    for (const int x : a) shared += std::find(b.begin(), b.end(), x) != b.end() ? 1 : 0;
    return shared == 2;
  };
  std::vector<Triangle> cycle{around[0]};
  while (cycle.size() < around.size())
    for (const auto& t : around)
      if (!contains(cycle, t) && adjacent(cycle.back(), t)) {
        cycle.push_back(t);
        break;
      }
  ASSERT_EQ(cycle.size(), 6u);
  std::erase_if(out.triangles, [&](const Triangle& t) { return t == cycle[1] || t == cycle[3]; });
  const std::size_t before = out.triangles.size();

  std::vector<bool> eligible(out.positions.size(), false);
  std::vector<Triangle> untouched = out.triangles;
  EXPECT_EQ(keepLargestFans(untouched, out.positions.size(), eligible), 0);
  EXPECT_EQ(untouched, out.triangles) << "only eligible vertices lose fans";

  eligible[v] = true;
  EXPECT_EQ(keepLargestFans(out.triangles, out.positions.size(), eligible), 1);
  EXPECT_EQ(out.triangles.size(), before - 1);
  EXPECT_FALSE(contains(out.triangles, cycle[2])) << "the fan of one triangle goes";
  for (const int k : {4, 5, 0}) EXPECT_TRUE(contains(out.triangles, cycle[k]));
  EXPECT_EQ(keepLargestFans(out.triangles, out.positions.size(), eligible), 0) << "one fan is left";
}

}  // namespace
}  // namespace hexcover::extract_detail
