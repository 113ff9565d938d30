// Texture output of the parameterization (core/param/texture.h): texture coordinates that follow
// the lattice and a pattern tile that repeats with the lattice's periods.

#include <gtest/gtest.h>

#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include <cmath>
#include <filesystem>

#include "core/common/error.h"
#include "core/field/rosy_field.h"
#include "core/mesh/primitives.h"
#include "core/param/hexcover.h"
#include "core/param/lattice.h"
#include "core/param/texture.h"

namespace hexcover {
namespace {

TEST(Texture, TexcoordsAreCartesianParameterCoordinatesWithVScaledByOneOverSqrt3) {
  const TriMesh mesh = makeTorus(6.0, 1.0, 96, 16);
  std::vector<Eigen::Vector3d> directions;
  for (const auto fh : mesh.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto vh : mesh.fv_range(fh)) c += toEigen(mesh.point(vh));
    directions.emplace_back(-c.y(), c.x(), 0.0);
  }
  const RosyField field = rosyFieldFromDirections(mesh, directions, 6);
  ParamOptions options;
  options.edgeLength = 0.3;
  const Parameterization p = computeParameterization(mesh, field, options);
  const PolygonSoup soup = texturedSoup(mesh, p);
  ASSERT_EQ(soup.faceCount(), mesh.n_faces());
  ASSERT_EQ(soup.cornerTexcoords.size(), 3 * mesh.n_faces());
  std::size_t corner = 0;
  for (const auto fh : mesh.faces())
    for (const auto h : mesh.fh_range(fh)) {
      EXPECT_EQ(soup.cornerVertices[corner], static_cast<std::uint32_t>(mesh.to_vertex_handle(h).idx()));
      const Eigen::Vector2d z = p.cornerCoords[h.idx()];
      const Eigen::Vector2d vt = soup.cornerTexcoords[corner++];
      EXPECT_NEAR(vt.x(), z.x() + 0.5 * z.y(), 1e-12);
      EXPECT_NEAR(vt.y(), 0.5 * z.y(), 1e-12);  // (√3/2 · b) / √3
    }
  // Across every cut edge the two sides differ by a lattice symmetry; in texture space the lattice
  // vectors e1 and e2 are (1, 0) and (1/2, 1/2), so the unit square is one period.
  const Eigen::Vector2d e1(1.0, 0.0), e2(0.5, 0.5);
  EXPECT_NEAR((2.0 * e2 - e1 - Eigen::Vector2d(0.0, 1.0)).norm(), 0.0, 1e-15);
}

TEST(Texture, PatternTileRepeatsWithTheLatticePeriods) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "hexcover_param_texture_test.png";
  HexPatternOptions options;
  options.width = 200;
  writeLatticePatternPng(path, 6, options);
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels = stbi_load(path.string().c_str(), &width, &height, &channels, 3);
  ASSERT_NE(pixels, nullptr);
  EXPECT_EQ(width, 200);
  EXPECT_EQ(height, static_cast<int>(std::lround(200 * std::sqrt(3.0))));
  // The lattice vector e2 is half the tile in both directions: the image equals itself shifted
  // by (width/2, height/2) up to pixels on line edges (height is rounded).
  int different = 0, dark = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const unsigned char* a = pixels + 3 * (y * width + x);
      const unsigned char* b = pixels + 3 * (((y + height / 2) % height) * width + (x + width / 2) % width);
      different += (a[0] != b[0] || a[1] != b[1] || a[2] != b[2]) ? 1 : 0;
      dark += a[0] < 100 ? 1 : 0;
    }
  stbi_image_free(pixels);
  std::filesystem::remove(path);
  EXPECT_LT(different, width * height / 50);
  EXPECT_GT(dark, width * height / 50);  // the hexagons are drawn
}

TEST(Texture, BadPatternRequestsAreRefused) {
  HexPatternOptions options;
  options.width = 2;
  EXPECT_THROW(writeLatticePatternPng("unused.png", 6, options), Error);
  EXPECT_THROW(writeLatticePatternPng("unused.png", 5, HexPatternOptions{}), Error);
}

}  // namespace
}  // namespace hexcover
