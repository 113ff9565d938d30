// The pipeline with rosy 4 (quads from the Gauss lattice) on generated meshes: a sphere, whose
// eight +1/4 cones are its only irregular vertices, and a tube, which needs none.

#include <gtest/gtest.h>

#include <map>
#include <utility>
#include <vector>

#include "core/mesh/primitives.h"
#include "core/pipeline/pipeline.h"
#include "tests/common/lattice_parameterizations.h"

namespace hexcover {
namespace {

using test::facesOfSize;
using test::polygonValences;
using test::PolygonValences;

/// Σ (4 − valence) over the interior vertices of a closed quad mesh is 4χ (Poincaré–Hopf for the
/// Gauss lattice).
int interiorIndexSum(const PolygonSoup& quads) {
  const PolygonValences valences = polygonValences(quads);
  int sum = 0;
  for (std::size_t v = 0; v < quads.vertexCount(); ++v)
    if (!valences.onBoundary[v] && valences.valence[v] > 0) sum += 4 - valences.valence[v];
  return sum;
}

TEST(PipelineQuads, SphereBecomesQuadsWithItsEightConesAsTheOnlyIrregularVertices) {
  const TriMesh sphere = makeIcosphere(4);  // 2562 vertices
  RemeshOptions options;
  options.rosy = 4;
  options.targetVertices = 640;
  const RemeshResult result = remesh(toPolygonSoup(sphere), options);
  const PolygonSoup& quads = result.remesh.quads;
  ASSERT_GT(quads.faceCount(), 0u);
  EXPECT_EQ(facesOfSize(quads, 4), static_cast<int>(quads.faceCount())) << "a closed surface";
  EXPECT_NEAR(static_cast<double>(quads.vertexCount()), 640.0, 64.0);
  EXPECT_EQ(interiorIndexSum(quads), 8);
  // The field's singularities are eight +1/4 cones; they are the irregular vertices.
  EXPECT_EQ(result.singularities.size(), 8u);
  EXPECT_EQ(result.metrics.irregularInterior, 8);
  EXPECT_EQ(result.metrics.valenceInterior.at(3), 8);
  EXPECT_EQ(result.metrics.quads, static_cast<int>(quads.faceCount()));
  EXPECT_TRUE(result.metrics.topologyMatchesReference.value());
  EXPECT_GT(result.metrics.angleMin, 45.0);
  EXPECT_LT(result.metrics.angleMax, 135.0);
  EXPECT_LT(result.metrics.distance->hausdorffPct, 1.0);
  EXPECT_TRUE(result.remesh.hexDual.positions.empty());
}

TEST(PipelineQuads, TubeKeepsItsBoundaryLoopsWithQuadsInside) {
  const TriMesh tube = makeTube(0.5, 2.0, 64, 38);
  RemeshOptions options;
  options.rosy = 4;
  options.targetVertices = static_cast<long long>(tube.n_vertices() / 4);
  const RemeshResult result = remesh(toPolygonSoup(tube), options);
  const PolygonSoup& quads = result.remesh.quads;
  EXPECT_TRUE(result.metrics.topologyMatchesReference.value());
  EXPECT_EQ(result.metrics.topology.boundaryLoops, 2);
  // A cylinder needs no cone. Each lattice front is a ring of straight front vertices, each
  // joined to the sample at its own place on the rim: the strips become rows of rectangles, and
  // every vertex is regular (before the strips were stitched for quads: 4 triangles, 2 interior
  // vertices of valence 5, corners of 47.6-124.6°).
  EXPECT_EQ(facesOfSize(quads, 4), static_cast<int>(quads.faceCount()));
  EXPECT_GT(result.metrics.angleMin, 80.0);
  EXPECT_LT(result.metrics.angleMax, 100.0);
  EXPECT_EQ(result.metrics.irregularInterior, 0);
  EXPECT_EQ(result.metrics.irregularBoundary, 0);
  const PolygonValences valences = polygonValences(quads);
  for (std::size_t v = 0; v < quads.vertexCount(); ++v)
    EXPECT_EQ(valences.valence[v], valences.onBoundary[v] ? 3 : 4) << "vertex " << v;
  EXPECT_LT(result.metrics.distance->hausdorffPct, 1.0);
}

}  // namespace
}  // namespace hexcover
