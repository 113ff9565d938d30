#include "core/param/texture.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/param/lattice.h"

namespace hexcover {
namespace {

// Texture coordinates of Cartesian parameter coordinates p: (u, v/√3) for N = 6, (u, v) for N = 4.
Eigen::Vector2d texcoordOf(const Eigen::Vector2d& p, int n) {
  return n == 6 ? Eigen::Vector2d(p.x(), p.y() / std::sqrt(3.0)) : p;
}

double distanceToInteger(double x) { return std::abs(x - std::round(x)); }

}  // namespace

PolygonSoup texturedSoup(const TriMesh& mesh, const Parameterization& parameterization) {
  if (parameterization.cornerCoords.size() != mesh.n_halfedges())
    throw Error(ErrorCode::InvalidOption, "the parameterization does not belong to this mesh");
  const Eigen::Matrix2d basis = latticeBasis(parameterization.n);
  PolygonSoup soup;
  soup.positions.reserve(mesh.n_vertices());
  for (const auto vh : mesh.vertices()) soup.positions.push_back(toEigen(mesh.point(vh)));
  soup.cornerTexcoords.reserve(3 * mesh.n_faces());
  for (const auto fh : mesh.faces()) {
    std::array<int, 3> corners{};
    int c = 0;
    for (const auto h : mesh.fh_range(fh)) {
      corners[c++] = mesh.to_vertex_handle(h).idx();
      soup.cornerTexcoords.push_back(
          texcoordOf(basis * parameterization.cornerCoords[h.idx()], parameterization.n));
    }
    soup.addFace(corners);
  }
  return soup;
}

void writeLatticePatternPng(const std::filesystem::path& path, int n,
                            const HexPatternOptions& options) {
  if (!isLatticeOrder(n))
    throw Error(ErrorCode::InvalidOption, "pattern images exist for N = 4 and N = 6 only");
  if (options.width < 8 || options.width > 16384)
    throw Error(ErrorCode::InvalidOption, "pattern width must be between 8 and 16384 pixels");
  const int width = options.width;
  const int height = n == 6 ? static_cast<int>(std::lround(width * std::sqrt(3.0))) : width;
  const Eigen::Matrix2d basis = latticeBasis(n);
  const Eigen::Matrix2d toLattice = basis.inverse();
  const double halfWidth = options.lineWidth;
  const double rowHeight = n == 6 ? std::sqrt(3.0) / 2.0 : 1.0;  // spacing of parallel lattice lines

  const std::array<std::uint8_t, 3> background{246, 241, 230}, hexagon{40, 42, 60},
      triangle{70, 110, 200};
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height * 3);
  for (int py = 0; py < height; ++py) {
    for (int px = 0; px < width; ++px) {
      // Image rows run downwards, texture v upwards.
      const Eigen::Vector2d vt((px + 0.5) / width, 1.0 - (py + 0.5) / height);
      const Eigen::Vector2d p = n == 6 ? Eigen::Vector2d(vt.x(), vt.y() * std::sqrt(3.0)) : vt;
      const Eigen::Vector2d z = toLattice * p;
      auto color = background;
      if (options.triangles) {
        double d = std::min(distanceToInteger(z.x()), distanceToInteger(z.y()));
        if (n == 6) d = std::min(d, distanceToInteger(z.x() + z.y()));
        if (d * rowHeight < 0.5 * halfWidth) color = triangle;
      }
      if (options.hexagons) {
        // Dual cell edges: points about equidistant from the two nearest lattice points.
        double d1 = 1e9, d2 = 1e9;
        for (int da = -1; da <= 2; ++da)
          for (int db = -1; db <= 2; ++db) {
            const Eigen::Vector2d q(std::floor(z.x()) + da, std::floor(z.y()) + db);
            const double d = (basis * q - p).squaredNorm();
            if (d < d1) {
              d2 = d1;
              d1 = d;
            } else if (d < d2) {
              d2 = d;
            }
          }
        // Distance to the bisector of two neighbours at unit distance: (d2² − d1²) / 2.
        if (0.5 * (d2 - d1) < halfWidth) color = hexagon;
      }
      std::copy(color.begin(), color.end(),
                pixels.begin() + (static_cast<std::size_t>(py) * width + px) * 3);
    }
  }
  if (stbi_write_png(path.string().c_str(), width, height, 3, pixels.data(), width * 3) == 0)
    throw Error(ErrorCode::Io, "cannot write the pattern image " + path.string());
}

}  // namespace hexcover
