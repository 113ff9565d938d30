// The glb writer: a file that tinygltf reads back with the same triangles, vertices, bounds and
// (for textured soups) texture coordinates.

#include "server/glb_writer.h"

#include <gtest/gtest.h>

#include "core/mesh/primitives.h"  // Eigen before httplib (see e2e_helpers.h)
#include "tests/server/e2e_helpers.h"
#include "tests/server/in_process_server.h"

namespace hexcover::server::test {
namespace {

TEST(GlbWriter, TriangleMeshRoundTripsThroughTinygltf) {
  TempDir dir;
  const PolygonSoup soup = toPolygonSoup(makeIcosphere(2));
  writeGlb(soup, dir.path() / "sphere.glb");
  const auto [triangles, vertices] = glbCounts(readFile(dir.path() / "sphere.glb"));
  EXPECT_EQ(triangles, 320);
  EXPECT_EQ(vertices, 162);
}

TEST(GlbWriter, PolygonsAreFanTriangulated) {
  TempDir dir;
  PolygonSoup hexagon;
  for (int k = 0; k < 6; ++k)
    hexagon.positions.emplace_back(std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0.0);
  hexagon.addFace(std::vector<int>{0, 1, 2, 3, 4, 5});
  writeGlb(hexagon, dir.path() / "hexagon.glb");
  EXPECT_EQ(glbCounts(readFile(dir.path() / "hexagon.glb")).first, 4);
}

TEST(GlbWriter, TexturedSoupSplitsVerticesAtTextureSeams) {
  TempDir dir;
  PolygonSoup quad;  // two triangles sharing an edge whose corners have different uvs
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.addFace(std::vector<int>{0, 1, 2});
  quad.addFace(std::vector<int>{0, 2, 3});
  quad.cornerTexcoords = {{0, 0}, {1, 0}, {1, 1}, {0.5, 0}, {1, 1}, {0, 1}};
  writeGlb(quad, dir.path() / "quad.glb");
  bool texcoords = false;
  const auto [triangles, vertices] = glbCounts(readFile(dir.path() / "quad.glb"), &texcoords);
  EXPECT_TRUE(texcoords);
  EXPECT_EQ(triangles, 2);
  EXPECT_EQ(vertices, 5) << "vertex 0 has two uvs, vertex 2 one";
}

}  // namespace
}  // namespace hexcover::server::test
