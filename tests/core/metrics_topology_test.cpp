// Topology invariants (core/mesh/topology.h) on generated meshes with known χ, genus, boundary.

#include <gtest/gtest.h>

#include "core/mesh/primitives.h"
#include "core/mesh/topology.h"

namespace hexcover {
namespace {

TEST(Topology, IcosphereIsOneClosedGenusZeroSurface) {
  const MeshTopology t = computeTopology(makeIcosphere(2));
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundaryLoops, 0);
  EXPECT_EQ(t.eulerCharacteristic, 2);
  EXPECT_EQ(t.genus(), 0);
  EXPECT_TRUE(t.manifold);
  ASSERT_EQ(t.perComponent.size(), 1u);
  EXPECT_EQ(t.perComponent[0].vertices, 162u);
  EXPECT_EQ(t.perComponent[0].faces, 320u);
  EXPECT_EQ(t.perComponent[0].edges, 480u);
}

TEST(Topology, TorusHasGenusOne) {
  const MeshTopology t = computeTopology(makeTorus(2.0, 0.5, 24, 12));
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundaryLoops, 0);
  EXPECT_EQ(t.eulerCharacteristic, 0);
  EXPECT_EQ(t.genus(), 1);
}

TEST(Topology, TubeHasTwoBoundaryLoopsAndGenusZero) {
  const MeshTopology t = computeTopology(makeTube(1.0, 2.0, 16, 6));
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundaryLoops, 2);
  EXPECT_EQ(t.eulerCharacteristic, 0);
  EXPECT_EQ(t.genus(), 0);
}

TEST(Topology, GridIsADisk) {
  const MeshTopology t = computeTopology(makeEquilateralGrid(7, 5));
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundaryLoops, 1);
  EXPECT_EQ(t.eulerCharacteristic, 1);
  EXPECT_EQ(t.genus(), 0);
}

TriMesh twoDisjointShapes() {
  TriMesh mesh = makeTorus(2.0, 0.5, 12, 8);
  const TriMesh sphere = makeIcosphere(1);
  std::vector<TriMesh::VertexHandle> map;
  for (const auto vh : sphere.vertices()) map.push_back(mesh.add_vertex(sphere.point(vh)));
  for (const auto fh : sphere.faces()) {
    std::vector<TriMesh::VertexHandle> corners;
    for (const auto vh : fh.vertices()) corners.push_back(map[vh.idx()]);
    mesh.add_face(corners);
  }
  mesh.add_vertex({10.0, 0.0, 0.0});  // isolated
  return mesh;
}

TEST(Topology, CountsComponentsSeparatelyAndIgnoresIsolatedVertices) {
  const MeshTopology t = computeTopology(twoDisjointShapes());
  EXPECT_EQ(t.components, 2);
  EXPECT_EQ(t.isolatedVertices, 1);
  EXPECT_EQ(t.eulerCharacteristic, 2);
  EXPECT_EQ(t.genus(), 1);
  ASSERT_EQ(t.perComponent.size(), 2u);
  EXPECT_EQ(t.perComponent[0].genus, 1);  // the torus holds face 0
  EXPECT_EQ(t.perComponent[1].genus, 0);
}

TEST(Topology, TwoFansJoinedAtOneVertexAreNotManifold) {
  // Two triangles sharing only vertex 0: OpenMesh stores this, but vertex 0 has two fans.
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> v;
  for (const auto& p : {TriMesh::Point(0, 0, 0), TriMesh::Point(1, 0, 0), TriMesh::Point(0, 1, 0),
                        TriMesh::Point(-1, 0, 0), TriMesh::Point(0, -1, 0)})
    v.push_back(mesh.add_vertex(p));
  mesh.add_face(v[0], v[1], v[2]);
  mesh.add_face(v[0], v[3], v[4]);
  const MeshTopology t = computeTopology(mesh);
  EXPECT_FALSE(t.manifold);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus(), -1);
}

TEST(Topology, ComparisonIgnoresComponentOrderButNotInvariants) {
  const MeshTopology torus = computeTopology(makeTorus(2.0, 0.5, 12, 8));
  const MeshTopology finerTorus = computeTopology(makeTorus(2.0, 0.5, 30, 10));
  const MeshTopology sphere = computeTopology(makeIcosphere(1));
  EXPECT_TRUE(torus.sameAs(finerTorus));
  EXPECT_FALSE(torus.sameAs(sphere));
}

}  // namespace
}  // namespace hexcover
