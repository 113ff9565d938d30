// Shape, valence and edge statistics of measureQuality on generated meshes with known answers.

#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/mesh/primitives.h"
#include "core/metrics/metrics.h"

namespace hexcover {
namespace {

TEST(MetricsShape, EquilateralGridHasOnlySixtyDegreeAnglesAndUnitQuality) {
  const TriMesh grid = makeEquilateralGrid(12, 9, 0.5);
  const QualityReport q = measureQuality(grid);
  EXPECT_EQ(q.vertices, 12 * 9);
  EXPECT_EQ(q.faces, 2 * 11 * 8);
  EXPECT_NEAR(q.angleMin, 60.0, 1e-9);
  EXPECT_NEAR(q.angleMax, 60.0, 1e-9);
  EXPECT_NEAR(q.angleMean, 60.0, 1e-9);
  EXPECT_NEAR(q.angleSd, 0.0, 1e-9);
  EXPECT_NEAR(q.minAngleMean, 60.0, 1e-9);
  EXPECT_EQ(q.anglesBelow30Pct, 0.0);
  EXPECT_EQ(q.anglesAbove90Pct, 0.0);
  EXPECT_NEAR(q.qualityMin, 1.0, 1e-12);
  EXPECT_NEAR(q.qualityMean, 1.0, 1e-12);
  EXPECT_NEAR(q.edgeLengthMean, 0.5, 1e-12);
  EXPECT_NEAR(q.edgeLengthCv, 0.0, 1e-9);
  EXPECT_EQ(q.topology.boundaryLoops, 1);
  EXPECT_FALSE(q.distance.has_value());
  EXPECT_FALSE(q.topologyMatchesReference.has_value());
}

TEST(MetricsShape, RegularTorusGridHasNoIrregularVertex) {
  const TriMesh torus = makeTorus(3.0, 1.0, 30, 14);
  const QualityReport q = measureQuality(torus);
  EXPECT_EQ(q.irregularInterior, 0);
  EXPECT_EQ(q.irregularBoundary, 0);
  ASSERT_EQ(q.valenceInterior.size(), 1u);
  EXPECT_EQ(q.valenceInterior.at(6), 30 * 14);
  EXPECT_TRUE(q.valenceBoundary.empty());
  EXPECT_EQ(q.topology.eulerCharacteristic, 0);
  EXPECT_EQ(q.topology.genus(), 1);
}

TEST(MetricsShape, IcosphereHasTwelveIrregularVerticesOfValenceFive) {
  const QualityReport q = measureQuality(makeIcosphere(3));
  EXPECT_EQ(q.irregularInterior, 12);
  EXPECT_EQ(q.valenceInterior.at(5), 12);
  EXPECT_EQ(q.valenceInterior.at(6), q.vertices - 12);
}

TEST(MetricsShape, GridBoundaryValencesAreCounted) {
  // Equilateral grid boundary: valence 2 or 3 at corners, 4 along the straight sides, 3 or 5
  // along the zigzag sides.
  const QualityReport q = measureQuality(makeEquilateralGrid(6, 5));
  int boundary = 0;
  for (const auto& [valence, count] : q.valenceBoundary) {
    EXPECT_GE(valence, 2);
    EXPECT_LE(valence, 5);
    boundary += count;
  }
  EXPECT_EQ(boundary, 2 * 6 + 2 * 3);
  int irregular = 0;
  for (const auto& [valence, count] : q.valenceBoundary) irregular += valence != 4 ? count : 0;
  EXPECT_EQ(q.irregularBoundary, irregular);
  EXPECT_GT(q.irregularBoundary, 0);
  EXPECT_EQ(q.valenceInterior.at(6), 4 * 3);
}

TEST(MetricsShape, RightIsoscelesTriangleHasKnownAnglesAndQuality) {
  TriMesh mesh;
  const auto a = mesh.add_vertex({0, 0, 0});
  const auto b = mesh.add_vertex({1, 0, 0});
  const auto c = mesh.add_vertex({0, 1, 0});
  mesh.add_face(a, b, c);
  const QualityReport q = measureQuality(mesh);
  EXPECT_NEAR(q.angleMin, 45.0, 1e-12);
  EXPECT_NEAR(q.angleMax, 90.0, 1e-12);
  EXPECT_NEAR(q.angleMean, 60.0, 1e-12);
  EXPECT_NEAR(q.angleSd, std::sqrt((15.0 * 15.0 * 2 + 30.0 * 30.0) / 3.0), 1e-9);
  EXPECT_EQ(q.anglesAbove90Pct, 0.0);  // exactly 90° is not above
  EXPECT_NEAR(q.minAngleMean, 45.0, 1e-12);
  // Q = 6·(1/2) / (√3·(2 + √2)/2·√2)
  EXPECT_NEAR(q.qualityMin, 6.0 / (std::sqrt(3.0) * (2.0 + std::sqrt(2.0)) * std::sqrt(2.0)),
              1e-12);
  EXPECT_EQ(q.irregularBoundary, 3);
}

TEST(MetricsShape, RefusesAMeshWithoutFaces) {
  TriMesh empty;
  empty.add_vertex({0, 0, 0});
  try {
    measureQuality(empty);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidMesh);
  }
}

}  // namespace
}  // namespace hexcover
