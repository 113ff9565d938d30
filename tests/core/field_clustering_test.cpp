// The pieces of the clustering re-solve: matchings read relative to a corrected connection, and
// the merge rule of clusterSingularities.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/field/clustering.h"
#include "core/field/singularities.h"
#include "core/mesh/primitives.h"

namespace hexcover {
namespace {

/// Representative angles of the field along the major circle of a torus (no singularities).
std::vector<double> majorCircleAngles(const TriMesh& torus, const field::FieldGeometry& geometry) {
  std::vector<double> angles;
  for (const auto fh : torus.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto vh : torus.fv_range(fh)) c += toEigen(torus.point(vh));
    angles.push_back(geometry.frames.angleOf(fh.idx(), Eigen::Vector3d(-c.y(), c.x(), 0.0)));
  }
  return angles;
}

TEST(FieldMatchingShift, OnePeriodOnOneEdgeMovesOneUnitOfIndexAcrossIt) {
  const TriMesh torus = makeTorus(2.0, 0.7, 48, 20);
  const field::FieldGeometry geometry(torus);
  const std::vector<double> angles = majorCircleAngles(torus, geometry);
  for (const int n : {4, 6}) {
    const RosyField plain = field::rosyFieldFromAngles(torus, geometry, angles, n);
    ASSERT_TRUE(plain.singularities.empty());
    // The field turns by δ across edge e; a connection that turns by δ + 2π/N there intends the
    // next matching, and the two ends of e then have indices +1 and −1.
    const auto eh = torus.edge_handle(123);
    const int head0 = torus.to_vertex_handle(torus.halfedge_handle(eh, 0)).idx();
    const int head1 = torus.to_vertex_handle(torus.halfedge_handle(eh, 1)).idx();
    std::vector<double> shift(torus.n_edges(), 0.0);
    shift[eh.idx()] = 2.0 * M_PI / n;
    const RosyField shifted = field::rosyFieldFromAngles(torus, geometry, angles, n, shift);
    ASSERT_EQ(shifted.singularities.size(), 2u);
    for (const auto& s : shifted.singularities) {
      ASSERT_TRUE(s.vertex == head0 || s.vertex == head1) << "singularity at vertex " << s.vertex;
      EXPECT_EQ(s.index, s.vertex == head0 ? 1 : -1);
    }
    EXPECT_EQ((shifted.edgeMatching[eh.idx()] - plain.edgeMatching[eh.idx()] + n) % n, 1);
    // A shift below half a period changes nothing.
    shift[eh.idx()] = 0.4 * M_PI / n;
    EXPECT_TRUE(
        field::rosyFieldFromAngles(torus, geometry, angles, n, shift).singularities.empty());
  }
}

TEST(FieldClustering, MergesThatLowerTheLargerIndexAreAllowedAndPairsAboveTheLimitAreNot) {
  const TriMesh sphere = makeIcosphere(4);
  const field::EdgeGraph graph(sphere);
  const std::vector<double> density(sphere.n_vertices(), 1.0);
  const int a = 0;
  const int b = sphere.to_vertex_handle(sphere.halfedge_handle(sphere.vertex_handle(a))).idx();
  // +4/6 next to −1/6: the merge lowers |I| to 3, above maxIndex = 1 but below 4.
  const field::ClusteringResult lowered =
      field::clusterSingularities(sphere, graph, {{a, 4}, {b, -1}}, density, 0.5, 1);
  EXPECT_EQ(lowered.collapses, 1);
  ASSERT_EQ(lowered.nodes.size(), 1u);
  EXPECT_EQ(lowered.nodes[0].index, 3);
  // +1/6 next to +1/6 would make +2/6: kept apart.
  const field::ClusteringResult apart =
      field::clusterSingularities(sphere, graph, {{a, 1}, {b, 1}}, density, 0.5, 1);
  EXPECT_EQ(apart.collapses, 0);
  EXPECT_EQ(apart.forbiddenPairs, 1);
  EXPECT_EQ(apart.nodes.size(), 2u);
}

}  // namespace
}  // namespace hexcover
