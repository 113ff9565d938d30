// The pieces of the clustering re-solve: matchings read relative to a corrected connection, the
// merge rule of clusterSingularities and the split of high-order singularities.

#include <gtest/gtest.h>

#include <algorithm>
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

// A flat patch whose centre carries +6/6 (the smoothest field's zero at the centre of a cap): six
// +1/6 around it, about half-way to the boundary; with an angle defect of 180° at the centre (3
// units of 60°), the centre keeps +3/6 and three go around; +1/6 stays as it is.
TEST(FieldClustering, SplitsAHighOrderNodeIntoFirstOrderOnesAroundIt) {
  const TriMesh grid = makeEquilateralGrid(25, 25, 1.0);
  const field::EdgeGraph graph(grid);
  std::vector<bool> boundary(grid.n_vertices(), false);
  for (const auto v : grid.vertices()) boundary[v.idx()] = grid.is_boundary(v);
  const int centre = 12 * 25 + 12;
  const std::vector<double> flat(grid.n_vertices(), 0.0);
  const auto distance = [&](int a, int b) {
    return (toEigen(grid.point(grid.vertex_handle(a))) - toEigen(grid.point(grid.vertex_handle(b))))
        .norm();
  };

  const field::ClusteringResult six =
      field::splitHighOrderNodes(grid, graph, {{centre, 6}}, flat, boundary, 6, 1, 100.0);
  EXPECT_EQ(six.collapses, 1);
  ASSERT_EQ(six.nodes.size(), 6u);
  double closest = 1e9;
  for (std::size_t i = 0; i < six.nodes.size(); ++i) {
    EXPECT_EQ(six.nodes[i].index, 1);
    EXPECT_FALSE(boundary[six.nodes[i].vertex]);
    const double r = distance(six.nodes[i].vertex, centre);
    EXPECT_GT(r, 2.0);  // the boundary is 10.4-12 away: ρ ≈ 5.2-6, ring ρ ± ρ/2
    EXPECT_LT(r, 9.5);
    for (std::size_t j = 0; j < i; ++j)
      closest = std::min(closest, distance(six.nodes[i].vertex, six.nodes[j].vertex));
  }
  EXPECT_GT(closest, 3.0) << "farthest-point sampling spreads them around the centre";
  EXPECT_TRUE(
      std::binary_search(six.collapsedVertices.begin(), six.collapsedVertices.end(), centre));

  std::vector<double> apex = flat;
  apex[centre] = M_PI;  // 180°: three units of 60°
  const field::ClusteringResult kept =
      field::splitHighOrderNodes(grid, graph, {{centre, 6}}, apex, boundary, 6, 1, 100.0);
  int atCentre = 0, around = 0;
  for (const auto& node : kept.nodes) (node.vertex == centre ? atCentre : around) += node.index;
  EXPECT_EQ(atCentre, 3);
  EXPECT_EQ(around, 3);

  const field::ClusteringResult first =
      field::splitHighOrderNodes(grid, graph, {{centre, 1}}, flat, boundary, 6, 1, 100.0);
  EXPECT_EQ(first.collapses, 0);
  ASSERT_EQ(first.nodes.size(), 1u);
  EXPECT_EQ(first.nodes[0].index, 1);
  // No limit (maxIndex 0, the paper's clustering): nothing is split.
  EXPECT_EQ(
      field::splitHighOrderNodes(grid, graph, {{centre, 6}}, flat, boundary, 6, 0, 100.0).collapses,
      0);
}

TEST(SplitHighOrderNodes, LeavesLikeSignedNodesAloneWhereTheMeshIsAsFineAsElsewhere) {
  // Three +1/6 two edges apart, well within d_sing / 12, on a grid of equal edges: features of
  // the surface that a coarse lattice meets, not one zero that a locally finer mesh resolved as
  // several (merged and split around, feline's at K = V/64 folded its parameterization). They
  // stay where they are.
  const TriMesh grid = makeEquilateralGrid(25, 25, 1.0);
  const field::EdgeGraph graph(grid);
  std::vector<bool> boundary(grid.n_vertices(), false);
  for (const auto v : grid.vertices()) boundary[v.idx()] = grid.is_boundary(v);
  const std::vector<double> flat(grid.n_vertices(), 0.0);
  const int centre = 12 * 25 + 12;
  const std::vector<field::ClusterNode> nodes{{centre - 2, 1}, {centre, 1}, {centre + 2, 1}};
  const field::ClusteringResult result =
      field::splitHighOrderNodes(grid, graph, nodes, flat, boundary, 6, 1, 100.0);
  EXPECT_EQ(result.collapses, 0);
  ASSERT_EQ(result.nodes.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(result.nodes[k].vertex, nodes[k].vertex);
    EXPECT_EQ(result.nodes[k].index, 1);
  }
  EXPECT_TRUE(result.collapsedVertices.empty());
}

}  // namespace
}  // namespace hexcover
