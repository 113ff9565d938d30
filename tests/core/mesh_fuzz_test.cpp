// Malformed input never crashes, hangs or allocates without bound: truncations and random byte
// changes of files in every format either parse (and then repair or are refused) or throw
// hexcover::Error. Deterministic (fixed seeds) and small, so it runs in well under a second.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "core/common/error.h"
#include "core/mesh/io.h"
#include "core/mesh/primitives.h"
#include "core/mesh/repair.h"

namespace hexcover {
namespace {

std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// The outcome of reading possibly broken bytes: parsed (and maybe repaired) or refused.
enum class Outcome { Parsed, Refused };

Outcome readAndRepair(const std::string& bytes) {
  ReadOptions limits;
  limits.maxFaces = 100'000;
  limits.maxVertices = 100'000;
  try {
    const PolygonSoup soup = parseMesh(bytes, limits);
    try {
      repairMesh(soup);
    } catch (const Error&) {
      // Refusing a damaged mesh is fine; crashing is not.
    }
    return Outcome::Parsed;
  } catch (const Error& e) {
    EXPECT_GT(std::string(e.what()).size(), 10u);
    return Outcome::Refused;
  }
}

// One small sample of each format and flavour, written by our writers or by hand.
std::vector<std::pair<std::string, std::string>> samples() {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("hexcover_fuzz_" + std::to_string(std::random_device{}()));
  std::filesystem::create_directories(dir);
  PolygonSoup soup = toPolygonSoup(makeIcosphere(1));
  soup.addFace(std::array<int, 4>{0, 1, 2, 3});
  std::vector<std::pair<std::string, std::string>> result;
  for (const std::string name : {"mesh.obj", "mesh.off", "mesh.ply", "mesh.stl"}) {
    writeMesh(soup, dir / name);
    result.emplace_back(name, fileBytes(dir / name));
  }
  std::filesystem::remove_all(dir);
  result.emplace_back(
      "ascii.ply",
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nelement face 2\nproperty list uchar int "
      "vertex_indices\n"
      "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
      "0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n3 0 1 2\n3 0 2 3\n6 0 1 2 -1 2 3\n");
  result.emplace_back(
      "ascii.stl",
      "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n"
      "endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nendsolid a\n");
  result.emplace_back("textured.obj",
                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nf 1/1/1 2/2/1 3/-1/1\n");
  return result;
}

TEST(MeshFuzz, SamplesParseBeforeTheyAreDamaged) {
  for (const auto& [name, bytes] : samples())
    EXPECT_EQ(readAndRepair(bytes), Outcome::Parsed) << name;
}

TEST(MeshFuzz, TruncationsParseOrThrowError) {
  for (const auto& [name, bytes] : samples()) {
    SCOPED_TRACE(name);
    const std::size_t step = std::max<std::size_t>(1, bytes.size() / 300);
    std::size_t refused = 0;
    for (std::size_t length = 0; length < bytes.size(); length += step)
      refused += readAndRepair(bytes.substr(0, length)) == Outcome::Refused;
    EXPECT_GT(refused, 0u);  // cutting a file short is noticed at least sometimes
  }
}

TEST(MeshFuzz, RandomByteChangesParseOrThrowError) {
  std::mt19937 random(12345);
  for (const auto& [name, bytes] : samples()) {
    SCOPED_TRACE(name);
    std::uniform_int_distribution<std::size_t> position(0, bytes.size() - 1);
    std::uniform_int_distribution<int> byte(0, 255);
    const char interesting[] = {'\0', '\n', '-', '9', ' ', '/', '#', '\\', 'e', '.', '\xff'};
    std::uniform_int_distribution<std::size_t> pick(0, sizeof interesting - 1);
    for (int trial = 0; trial < 150; ++trial) {
      std::string damaged = bytes;
      const int changes = 1 + trial % 4;
      for (int c = 0; c < changes; ++c)
        damaged[position(random)] =
            trial % 2 ? static_cast<char>(byte(random)) : interesting[pick(random)];
      readAndRepair(damaged);
    }
  }
}

TEST(MeshFuzz, HugeDeclaredSizesAreRefusedQuickly) {
  const std::string hugeStl = [] {
    std::string bytes(80, ' ');
    bytes += std::string("\xff\xff\xff\x7f", 4);  // 2^31 triangles, no data
    return bytes;
  }();
  for (const std::string& bytes :
       {std::string("OFF\n100000000000 1 0\n"), std::string("OFF\n3 99999999999999 0\n0 0 0\n"),
        std::string("ply\nformat binary_big_endian 1.0\nelement vertex 999999999999\nproperty "
                    "float x\nend_header\n"),
        std::string("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float "
                    "y\nproperty float z\n"
                    "element face 1\nproperty list uint int vertex_indices\nend_header\n0 0 "
                    "0\n4000000000 0 0 0\n"),
        hugeStl}) {
    EXPECT_EQ(readAndRepair(bytes), Outcome::Refused) << bytes.substr(0, 40);
  }
}

}  // namespace
}  // namespace hexcover
