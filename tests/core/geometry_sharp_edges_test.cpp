// Sharp edges: the creases of a box are found as whole lines; smooth shapes and the folds around
// a spike have none. Which creases a lattice can follow together.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/sharp_edges.h"
#include "core/mesh/primitives.h"
#include "core/mesh/topology.h"
#include "tests/common/mesh_measures.h"

namespace hexcover {
namespace {

int count(const std::vector<bool>& flags) {
  return static_cast<int>(std::count(flags.begin(), flags.end(), true));
}

TEST(GeometrySharpEdges, ABoxHasTwelveCreaseLinesOfNinetyDegrees) {
  constexpr int kDivisions = 10;
  const TriMesh box = makeBox(1.0, 0.8, 0.6, kDivisions);
  const std::vector<bool> sharp = sharpEdges(box, 60.0, 0.0);
  ASSERT_EQ(sharp.size(), box.n_edges());
  EXPECT_EQ(count(sharp), 12 * kDivisions);
  for (const auto e : box.edges()) {
    if (!sharp[e.idx()]) continue;
    // On a box edge: two coordinates at ± half the side.
    const auto p = box.point(e.v0()) + box.point(e.v1());
    const int onSides = (std::abs(std::abs(p[0]) - 1.0) < 1e-9) +
                        (std::abs(std::abs(p[1]) - 0.8) < 1e-9) +
                        (std::abs(std::abs(p[2]) - 0.6) < 1e-9);
    EXPECT_EQ(onSides, 2) << "edge " << e.idx();
  }
  EXPECT_EQ(count(sharpEdges(box, 100.0, 0.0)), 0) << "the creases are of 90°";
  EXPECT_EQ(count(sharpEdges(box, 0.0, 0.0)), 0) << "angle 0 turns detection off";
}

TEST(GeometrySharpEdges, LinesShorterThanTheMinimumLengthAreDropped) {
  const TriMesh box = makeBox(1.0, 0.8, 0.6, 10);
  // The four edges of length 0.6 go, the eight of 0.8 and 1.0 stay (lines end at corners).
  EXPECT_EQ(count(sharpEdges(box, 60.0, 0.7)), 8 * 10);
  EXPECT_EQ(count(sharpEdges(box, 60.0, 1.1)), 0);
}

TEST(GeometrySharpEdges, SmoothShapesAndTheFoldsOfASpikeHaveNone) {
  EXPECT_EQ(count(sharpEdges(makeIcosphere(3), 30.0, 0.0)), 0);
  EXPECT_EQ(count(sharpEdges(makeTorus(1.0, 0.4, 64, 24), 30.0, 0.0)), 0);
  // One vertex pulled out to three times the radius: the edges around the spike fold sharply,
  // but they meet at the tip, so no line is longer than two edges.
  TriMesh spiky = makeIcosphere(3);
  const auto tip = spiky.vertex_handle(0);
  spiky.set_point(tip, spiky.point(tip) * 3.0);
  const std::vector<bool> anyLength = sharpEdges(spiky, 60.0, 0.0);
  EXPECT_GT(count(anyLength), 0);
  const double edge = spiky.calc_edge_length(*spiky.edges_begin());
  EXPECT_EQ(count(sharpEdges(spiky, 60.0, 3.0 * edge)), 0);
}

// Of a box's creases, which meet at 90°, a hexagonal lattice can follow only parallel ones: the
// four longest lines, all along x. A square lattice follows all twelve.
TEST(GeometrySharpEdges, AHexagonalLatticeFollowsTheLongestParallelCreasesOfABox) {
  constexpr int kDivisions = 10;
  const TriMesh box = makeBox(1.0, 0.8, 0.6, kDivisions);
  const std::vector<bool> sharp = sharpEdges(box, 60.0, 0.0);
  const std::vector<bool> hexagonal = latticeCompatibleCreases(box, sharp, 6);
  EXPECT_EQ(count(hexagonal), 4 * kDivisions);
  for (const auto e : box.edges()) {
    if (!hexagonal[e.idx()]) continue;
    EXPECT_TRUE(sharp[e.idx()]);
    const auto d = box.point(e.v1()) - box.point(e.v0());
    EXPECT_NEAR(std::abs(d[0]), 1.0 / kDivisions, 1e-12) << "edge " << e.idx();
  }
  EXPECT_EQ(latticeCompatibleCreases(box, sharp, 4), sharp);
}

// A flat hexagonal prism: its rims turn by 120° at each corner, which a hexagonal lattice
// follows, so all 12 rim lines stay; the six shorter vertical lines meet them at 90° and go.
// The circular rims of a cylinder are closed lines, and stay.
TEST(GeometrySharpEdges, CreasesMeetingAtMultiplesOfSixtyDegreesAndClosedOnesAllStay) {
  const TriMesh prism = makeCappedCylinder(1.0, 0.5, 6);
  const std::vector<bool> sharp = sharpEdges(prism, 30.0, 0.0);
  const std::vector<bool> hexagonal = latticeCompatibleCreases(prism, sharp, 6);
  int rim = 0;
  for (const auto e : prism.edges()) {
    if (!sharp[e.idx()]) continue;
    const bool vertical = std::abs(prism.point(e.v1())[2] - prism.point(e.v0())[2]) > 1e-9;
    EXPECT_EQ(hexagonal[e.idx()], !vertical) << "edge " << e.idx();
    rim += vertical ? 0 : 1;
  }
  EXPECT_GE(rim, 12);
  const TriMesh cylinder = makeCappedCylinder(1.0, 2.0, 64);
  const std::vector<bool> rims = sharpEdges(cylinder, 30.0, 0.0);
  EXPECT_GE(count(rims), 128);
  EXPECT_EQ(latticeCompatibleCreases(cylinder, rims, 6), rims);
}

// The generated CAD parts are closed solids facing outward, with their creases as lines and flat
// fans that are not creases: the L-bracket's 18 edges of 90° and 270°, and the plate's rims
// (2 × 4 sides and 2 × 48 hole segments; its 4 vertical edges are of 90° too).
TEST(GeometrySharpEdges, GeneratedCadPartsHaveTheirCreasesAndNoneInTheirFans) {
  const TriMesh bracket = makeLBracket(2.0, 0.5, 0.4);
  EXPECT_EQ(computeTopology(bracket).eulerCharacteristic, 2);
  EXPECT_NEAR(test::signedVolume(bracket), (2.0 * 0.5 + 1.5 * 0.5) * 0.4, 1e-12);
  EXPECT_EQ(count(sharpEdges(bracket, 60.0, 0.0)), 18);

  const TriMesh plate = makePlateWithHole(2.0, 0.5, 0.2, 48);
  const MeshTopology topology = computeTopology(plate);
  EXPECT_EQ(topology.genus(), 1);
  EXPECT_EQ(topology.boundaryLoops, 0);
  const double hole = 0.5 * 48 * 0.25 * std::sin(2.0 * M_PI / 48);
  EXPECT_NEAR(test::signedVolume(plate), (4.0 - hole) * 0.2, 1e-12);
  EXPECT_EQ(count(sharpEdges(plate, 60.0, 0.0)), 2 * 4 + 2 * 48 + 4);
}

}  // namespace
}  // namespace hexcover
