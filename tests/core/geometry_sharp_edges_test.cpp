// Sharp edges: the creases of a box are found as whole lines; smooth shapes and the folds around
// a spike have none.

#include <gtest/gtest.h>

#include <algorithm>

#include "core/geometry/sharp_edges.h"
#include "core/mesh/primitives.h"

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

}  // namespace
}  // namespace hexcover
