// Readers, writers and format detection (core/mesh/io.h) on small byte strings written in the test.

#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/mesh/io.h"
#include "core/mesh/primitives.h"

namespace hexcover {
namespace {

using namespace std::string_literals;

// Runs `parse` and returns the Error it throws; fails the test when it does not throw.
template <typename F>
Error expectError(F parse, ErrorCode code) {
  try {
    parse();
  } catch (const Error& e) {
    EXPECT_EQ(errorCodeName(e.code()), std::string(errorCodeName(code))) << e.what();
    return e;
  }
  ADD_FAILURE() << "expected an Error(" << errorCodeName(code) << ")";
  return Error(code, "");
}

std::vector<std::uint32_t> faceCorners(const PolygonSoup& soup, std::size_t f) {
  return {soup.cornerVertices.begin() + soup.faceStarts[f],
          soup.cornerVertices.begin() + soup.faceStarts[f + 1]};
}

// --- little helpers that write binary data -------------------------------------------------

template <typename T>
void append(std::string& out, T value, bool bigEndian = false) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (bigEndian == (std::endian::native == std::endian::little))
    std::reverse(bytes, bytes + sizeof(T));
  out.append(bytes, sizeof(T));
}

// Binary STL of the given triangles (9 floats each) with a chosen 80-byte header text.
std::string binaryStl(const std::vector<std::array<float, 9>>& triangles,
                      const std::string& header) {
  std::string out = header;
  out.resize(80, ' ');
  append(out, static_cast<std::uint32_t>(triangles.size()));
  for (const auto& t : triangles) {
    for (int i = 0; i < 3; ++i) append(out, 0.0f);
    for (const float x : t) append(out, x);
    append(out, std::uint16_t{0});
  }
  return out;
}

// Unit square as two triangles sharing the diagonal (0,0,0)-(1,1,0).
const std::vector<std::array<float, 9>> kSquare = {{0, 0, 0, 1, 0, 0, 1, 1, 0},
                                                   {0, 0, 0, 1, 1, 0, 0, 1, 0}};

// Binary PLY (either byte order) of a square with extra vertex properties of several types, a
// per-face property before the index list and a uint16 list count with uint32 indices.
std::string binaryPly(bool bigEndian) {
  std::string out =
      "ply\nformat "s + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
      " 1.0\ncomment test\nelement vertex 4\nproperty uchar red\nproperty float x\n"
      "property double y\nproperty short s\nproperty float z\nproperty list uchar int extra\n"
      "element face 2\nproperty int flags\nproperty list ushort uint vertex_indices\n"
      "element material 3\nproperty float shininess\nend_header\n";
  const double xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const auto& p : xy) {
    append(out, std::uint8_t{200}, bigEndian);
    append(out, static_cast<float>(p[0]), bigEndian);
    append(out, p[1], bigEndian);
    append(out, std::int16_t{-7}, bigEndian);
    append(out, 0.5f, bigEndian);
    append(out, std::uint8_t{2}, bigEndian);
    append(out, std::int32_t{1}, bigEndian);
    append(out, std::int32_t{2}, bigEndian);
  }
  for (const auto& face :
       {std::array<std::uint32_t, 3>{0, 1, 2}, std::array<std::uint32_t, 3>{0, 2, 3}}) {
    append(out, std::int32_t{5}, bigEndian);
    append(out, std::uint16_t{3}, bigEndian);
    for (const auto v : face) append(out, v, bigEndian);
  }
  for (int i = 0; i < 3; ++i) append(out, 1.0f, bigEndian);
  return out;
}

// --- format detection ------------------------------------------------------------------------

TEST(MeshFormatDetection, RecognisesEachFormatFromItsBytes) {
  EXPECT_EQ(detectFormat("# comment\nv 0 0 0\n"), MeshFormat::Obj);
  EXPECT_EQ(detectFormat("\n\nOFF\n3 1 0\n"), MeshFormat::Off);
  EXPECT_EQ(detectFormat("COFF\n"), MeshFormat::Off);
  EXPECT_EQ(detectFormat("ply\r\nformat ascii 1.0\r\n"), MeshFormat::Ply);
  EXPECT_EQ(detectFormat("solid x\nendsolid x\n"), MeshFormat::Stl);
  EXPECT_EQ(detectFormat(binaryStl(kSquare, "made by a tool")), MeshFormat::Stl);
  EXPECT_EQ(detectFormat(binaryStl(kSquare, "solid binary in disguise")), MeshFormat::Stl);
}

TEST(MeshFormatDetection, RefusesUnknownAndEmptyData) {
  const Error e = expectError([] { detectFormat("hello world\nthis is not a mesh\n"); },
                              ErrorCode::UnknownFormat);
  EXPECT_NE(std::string(e.what()).find("hello world"), std::string::npos) << e.what();
  expectError([] { detectFormat(""); }, ErrorCode::UnknownFormat);
  expectError([] { detectFormat("\x89PNG\r\n\x1a\n"); }, ErrorCode::UnknownFormat);
}

TEST(MeshFormatDetection, ExtensionsAreCaseInsensitiveAndUnknownOnesRefused) {
  EXPECT_EQ(formatFromExtension("a/b/Mesh.OBJ"), MeshFormat::Obj);
  EXPECT_EQ(formatFromExtension("x.off"), MeshFormat::Off);
  EXPECT_EQ(formatFromExtension("x.Ply"), MeshFormat::Ply);
  EXPECT_EQ(formatFromExtension("x.stl"), MeshFormat::Stl);
  const Error e = expectError([] { formatFromExtension("x.glb"); }, ErrorCode::UnknownFormat);
  EXPECT_NE(std::string(e.what()).find(".glb"), std::string::npos);
}

// --- OBJ -------------------------------------------------------------------------------------

TEST(ObjReader, KeepsPolygonsAndResolvesNegativeIndices) {
  const PolygonSoup soup =
      parseMesh("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\nv 2 0 0\nf 2 5 3\n");
  ASSERT_EQ(soup.vertexCount(), 5u);
  ASSERT_EQ(soup.faceCount(), 2u);
  EXPECT_EQ(faceCorners(soup, 0), (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(faceCorners(soup, 1), (std::vector<std::uint32_t>{1, 4, 2}));
  EXPECT_EQ(soup.positions[4], Eigen::Vector3d(2, 0, 0));
}

TEST(ObjReader, ReadsCornerTriplesWithTextureCoordinates) {
  const PolygonSoup soup = parseMesh(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nvt 1 0\nvn 0 0 1\nf 1/2/1 2/1/1 3/-1/1\nf 1//1 2//1 "
      "3//1\n");
  ASSERT_EQ(soup.faceCount(), 2u);
  EXPECT_EQ(faceCorners(soup, 1), (std::vector<std::uint32_t>{0, 1, 2}));
  // One face lacks texture coordinates: corner texcoords are all-or-nothing.
  EXPECT_TRUE(soup.cornerTexcoords.empty());
  const PolygonSoup textured =
      parseMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nvt 1 0\nf 1/2/1 2/1/1 3/-1/1\n");
  ASSERT_EQ(textured.cornerTexcoords.size(), 3u);
  EXPECT_EQ(textured.cornerTexcoords[0], Eigen::Vector2d(1, 0));
  EXPECT_EQ(textured.cornerTexcoords[1], Eigen::Vector2d(0.25, 0.5));
  EXPECT_EQ(textured.cornerTexcoords[2], Eigen::Vector2d(1, 0));
}

TEST(ObjReader, HandlesCommentsContinuationsCrlfAndIgnoredStatements) {
  const PolygonSoup soup = parseMesh(
      "# header comment\r\nmtllib a.mtl\r\no object\r\ng group\r\nusemtl red\r\ns off\r\n"
      "v 0 0 0 # trailing comment\r\nv 1 \\\r\n 0 0\r\nv +0 1e0 0\r\nf 1 2 \\\n 3\r\nl 1 2\r\n");
  ASSERT_EQ(soup.vertexCount(), 3u);
  ASSERT_EQ(soup.faceCount(), 1u);
  EXPECT_EQ(soup.positions[1], Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(soup.positions[2], Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(faceCorners(soup, 0), (std::vector<std::uint32_t>{0, 1, 2}));
}

TEST(ObjReader, OutOfRangeIndexNamesTheLine) {
  const Error e = expectError([] { parseMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"); },
                              ErrorCode::MalformedInput);
  EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  const Error negative =
      expectError([] { parseMesh("v 0 0 0\nf -1 -2 -3\n"); }, ErrorCode::MalformedInput);
  EXPECT_NE(std::string(negative.what()).find("line 2"), std::string::npos) << negative.what();
}

TEST(ObjReader, NonFiniteCoordinateIsRefusedWithItsLine) {
  const Error e = expectError([] { parseMesh("v 0 0 0\nv 1 nan 0\n"); }, ErrorCode::InvalidMesh);
  EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos) << e.what();
  expectError([] { parseMesh("v inf 0 0\n"); }, ErrorCode::InvalidMesh);
}

TEST(ObjReader, BadTokensAndLimitsAreReported) {
  const Error e = expectError([] { parseMesh("v 0 0 0\nv 1 x 0\n"); }, ErrorCode::MalformedInput);
  EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  expectError([] { parseMesh("v 0 0 0\nf 1/a 1 1\n"); }, ErrorCode::MalformedInput);
  ReadOptions options;
  options.maxFaces = 1;
  expectError([&] { parseMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 3 2 1\n", options); },
              ErrorCode::LimitExceeded);
}

// --- OFF -------------------------------------------------------------------------------------

TEST(OffReader, ReadsCommentsColoursAndCountsOnTheHeaderLine) {
  const PolygonSoup soup = parseMesh(
      "COFF 4 2 0 # counts on the header line\n# a comment line\n\n"
      "0 0 0 255 0 0 255\n1 0 0 255 0 0 255 # colour\n1 1 0 0 255 0 255\n0 1 0 0 0 255 255\n"
      "4 0 1 2 3 0.5 0.5 0.5 1\n3 0 2 3\n");
  ASSERT_EQ(soup.vertexCount(), 4u);
  ASSERT_EQ(soup.faceCount(), 2u);
  EXPECT_EQ(faceCorners(soup, 0), (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(soup.positions[2], Eigen::Vector3d(1, 1, 0));
  const PolygonSoup normals =
      parseMesh("NOFF\n3 1 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
  EXPECT_EQ(normals.faceCount(), 1u);
}

TEST(OffReader, OutOfRangeIndexAndTruncationNameTheLine) {
  const Error range = expectError([] { parseMesh("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"); },
                                  ErrorCode::MalformedInput);
  EXPECT_NE(std::string(range.what()).find("line 6"), std::string::npos) << range.what();
  EXPECT_NE(std::string(range.what()).find("out of range"), std::string::npos) << range.what();
  const Error truncated =
      expectError([] { parseMesh("OFF\n3 1 0\n0 0 0\n1 0 0\n"); }, ErrorCode::MalformedInput);
  EXPECT_NE(std::string(truncated.what()).find("end of file"), std::string::npos)
      << truncated.what();
  expectError([] { parseMesh("4OFF\n1 0 0\n0 0 0 0\n"); }, ErrorCode::MalformedInput);
}

TEST(OffReader, HugeDeclaredCountsAreRefusedBeforeAllocating) {
  const auto start = std::chrono::steady_clock::now();
  const Error e =
      expectError([] { parseMesh("OFF\n3 1000000000000 0\n0 0 0\n"); }, ErrorCode::LimitExceeded);
  EXPECT_NE(std::string(e.what()).find("1000000000000"), std::string::npos) << e.what();
  // Under the limit but far more than the text holds: the reader runs out of text, quickly.
  expectError([] { parseMesh("OFF\n4000000 0 0\n0 0 0\n"); }, ErrorCode::MalformedInput);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

// --- PLY -------------------------------------------------------------------------------------

TEST(PlyReader, ReadsAsciiWithExtraPropertiesCrlfAndOtherElements) {
  const PolygonSoup soup = parseMesh(
      "ply\r\nformat ascii 1.0\r\ncomment c\r\nobj_info i\r\nelement vertex 4\r\nproperty float "
      "x\r\n"
      "property float y\r\nproperty float z\r\nproperty uchar red\r\nelement face 2\r\n"
      "property uchar intensity\r\nproperty list uchar int vertex_indices\r\nelement edge 1\r\n"
      "property int vertex1\r\nproperty int vertex2\r\nend_header\r\n"
      "0 0 0 255\r\n1 0 0 255\r\n1 1 0 255\r\n0 1 0 255\r\n7 4 0 1 2 3\r\n7 3 0 2 3\r\n0 2\r\n");
  ASSERT_EQ(soup.vertexCount(), 4u);
  ASSERT_EQ(soup.faceCount(), 2u);
  EXPECT_EQ(faceCorners(soup, 0), (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(faceCorners(soup, 1), (std::vector<std::uint32_t>{0, 2, 3}));
}

TEST(PlyReader, BinaryLittleAndBigEndianGiveTheSameMesh) {
  for (const bool bigEndian : {false, true}) {
    SCOPED_TRACE(bigEndian ? "big endian" : "little endian");
    const PolygonSoup soup = parseMesh(binaryPly(bigEndian));
    ASSERT_EQ(soup.vertexCount(), 4u);
    ASSERT_EQ(soup.faceCount(), 2u);
    EXPECT_EQ(soup.positions[2], Eigen::Vector3d(1, 1, 0.5));
    EXPECT_EQ(faceCorners(soup, 1), (std::vector<std::uint32_t>{0, 2, 3}));
  }
}

TEST(PlyReader, TriangleStripsRestartAtMinusOneAndKeepOrientation) {
  // Strip 0 1 2 3 gives (0,1,2) and (2,1,3); after -1, strip 4 5 6 gives (4,5,6).
  const PolygonSoup soup = parseMesh(
      "ply\nformat ascii 1.0\nelement vertex 7\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n1 1 0\n5 5 0\n6 5 0\n5 6 0\n8 0 1 2 3 -1 4 5 6\n");
  ASSERT_EQ(soup.faceCount(), 3u);
  EXPECT_EQ(faceCorners(soup, 0), (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(faceCorners(soup, 1), (std::vector<std::uint32_t>{2, 1, 3}));
  EXPECT_EQ(faceCorners(soup, 2), (std::vector<std::uint32_t>{4, 5, 6}));
}

TEST(PlyReader, TruncatedBinaryDataNamesTheByteOffset) {
  const std::string full = binaryPly(false);
  // Cut inside the vertex records, inside a face's index list, and inside the last element.
  for (const std::size_t cut : {full.size() - 100, full.size() - 20, full.size() - 1}) {
    const Error e = expectError([&] { parseMesh(full.substr(0, cut)); }, ErrorCode::MalformedInput);
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << e.what();
  }
}

TEST(PlyReader, NonFiniteCoordinateNamesTheLineOrOffset) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n";
  const Error ascii =
      expectError([&] { parseMesh(header + "0 0 0\n1 inf 0\n"); }, ErrorCode::InvalidMesh);
  EXPECT_NE(std::string(ascii.what()).find("line 9"), std::string::npos) << ascii.what();
  std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n";
  const std::size_t second = binary.size() + 24;
  for (const double x : {0.0, 0.0, 0.0, std::nan(""), 0.0, 0.0}) append(binary, x);
  const Error e = expectError([&] { parseMesh(binary); }, ErrorCode::InvalidMesh);
  EXPECT_NE(std::string(e.what()).find("byte offset " + std::to_string(second)), std::string::npos)
      << e.what();
}

TEST(PlyReader, HeaderWithoutDataIsTruncatedNotOverread) {
  // The file ends right after "end_header" (no newline): the data offset lies past the end.
  for (const std::string format : {"binary_little_endian", "ascii"}) {
    const Error e = expectError(
        [&] {
          parseMesh("ply\nformat " + format +
                    " 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                    "property float z\nend_header");
        },
        ErrorCode::MalformedInput);
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
}

TEST(PlyReader, HugeCountsAreRefusedWithoutAllocating) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face ";
  expectError(
      [&] {
        parseMesh(header + "1000000000000\nproperty list uchar int vertex_indices\nend_header\n");
      },
      ErrorCode::LimitExceeded);
  // A list that claims 4·10^9 indices in a file of a few bytes.
  std::string body = header + "1\nproperty list uint int vertex_indices\nend_header\n";
  for (int i = 0; i < 9; ++i) append(body, 0.0f);
  append(body, std::uint32_t{4'000'000'000u});
  const Error e = expectError([&] { parseMesh(body); }, ErrorCode::MalformedInput);
  EXPECT_NE(std::string(e.what()).find("list length"), std::string::npos) << e.what();
  // An element of 10^12 records with a property: truncated, not a 10^12-step loop.
  expectError(
      [] {
        parseMesh(
            "ply\nformat binary_little_endian 1.0\nelement junk 1000000000000\nproperty int "
            "a\nend_header\n");
      },
      ErrorCode::MalformedInput);
}

TEST(PlyReader, BadIndicesAndHeadersAreReported) {
  const Error e = expectError(
      [] {
        parseMesh(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
            "float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 "
            "0\n3 0 1 3\n");
      },
      ErrorCode::MalformedInput);
  EXPECT_NE(std::string(e.what()).find("line 13"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  expectError([] { parseMesh("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"); },
              ErrorCode::MalformedInput);  // no end_header
  expectError(
      [] {
        parseMesh("ply\nformat ascii 1.0\nelement vertex 1\nproperty quaternion q\nend_header\n");
      },
      ErrorCode::MalformedInput);
}

// --- STL -------------------------------------------------------------------------------------

TEST(StlReader, AsciiWithSeveralSolidsAndMixedCaseIsWeldedByPosition) {
  const std::string facet =
      "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 1 1 0\n"
      " endloop\nendfacet\n";
  const PolygonSoup soup = parseMesh("solid first part\n" + facet +
                                     "FACET NORMAL 0 0 1\n OUTER LOOP\n  VERTEX 0 0 0\n  VERTEX 1 "
                                     "1 0\n  VERTEX 0 1 0\n ENDLOOP\nENDFACET\n"
                                     "endsolid first part\nSolid second\n" +
                                     facet + "EndSolid second\n");
  EXPECT_EQ(soup.faceCount(), 3u);
  EXPECT_EQ(soup.vertexCount(), 4u);  // corners at the same position share a vertex
  EXPECT_EQ(faceCorners(soup, 1), (std::vector<std::uint32_t>{0, 2, 3}));
}

TEST(StlReader, BinaryIsWeldedAndAHeaderStartingWithSolidIsStillBinary) {
  for (const std::string header : {"plain header", "solid but binary"}) {
    const PolygonSoup soup = parseMesh(binaryStl(kSquare, header));
    EXPECT_EQ(soup.faceCount(), 2u);
    EXPECT_EQ(soup.vertexCount(), 4u);
    EXPECT_EQ(faceCorners(soup, 1), (std::vector<std::uint32_t>{0, 2, 3}));
  }
}

TEST(StlReader, TruncatedBinaryAndBrokenAsciiAreReported) {
  std::string bytes = binaryStl(kSquare, "header");
  bytes[80] = 3;  // claims 3 triangles, holds 2
  const Error e = expectError([&] { parseMesh(bytes); }, ErrorCode::MalformedInput);
  EXPECT_NE(std::string(e.what()).find("truncated binary data"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << e.what();
  const Error ascii =
      expectError([] { parseMesh("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n"); },
                  ErrorCode::MalformedInput);
  EXPECT_NE(std::string(ascii.what()).find("line 4"), std::string::npos) << ascii.what();
  expectError(
      [] {
        parseMesh(
            "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
            "vertex 0 1 0\nendloop\nendfacet\n");
      },
      ErrorCode::MalformedInput);  // no endsolid
}

// --- writers and round trips ----------------------------------------------------------------

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("hexcover_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// A soup with a quad, a pentagon and triangles, to check that writers keep polygons.
PolygonSoup polygonSample() {
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0.5, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 2, 0.25}};
  soup.addFace(std::vector<int>{0, 1, 3, 4});
  soup.addFace(std::vector<int>{1, 2, 3});
  soup.addFace(std::vector<int>{4, 3, 2, 5, 0});
  return soup;
}

// A soup of two parts: the second mesh's vertices follow the first's, moved by the offset, and
// its triangles refer to them.
TEST(PolygonSoupParts, AppendedMeshFollowsTheSoupMovedByItsOffset) {
  const TriMesh torus = makeTorus(3, 1, 12, 8);
  PolygonSoup soup = polygonSample();
  const PolygonSoup before = soup;
  const Eigen::Vector3d offset(10.0, -2.0, 0.5);
  appendToPolygonSoup(soup, torus, offset);
  const PolygonSoup alone = toPolygonSoup(torus);
  ASSERT_EQ(soup.vertexCount(), before.vertexCount() + alone.vertexCount());
  ASSERT_EQ(soup.faceCount(), before.faceCount() + alone.faceCount());
  for (std::size_t v = 0; v < alone.vertexCount(); ++v)
    EXPECT_EQ(soup.positions[before.vertexCount() + v], alone.positions[v] + offset);
  for (std::size_t f = 0; f < alone.faceCount(); ++f) {
    ASSERT_EQ(soup.faceSize(before.faceCount() + f), 3u);
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_EQ(soup.cornerVertices[soup.faceStarts[before.faceCount() + f] + k],
                alone.cornerVertices[alone.faceStarts[f] + k] + before.vertexCount());
  }
  EXPECT_EQ(std::vector<std::uint32_t>(soup.cornerVertices.begin(),
                                       soup.cornerVertices.begin() + before.cornerVertices.size()),
            before.cornerVertices)
      << "the first part stays as it was";
}

TEST(MeshWriters, ObjOffAndPlyRoundTripsAreExact) {
  const TempDir dir;
  for (const PolygonSoup& original : {toPolygonSoup(makeIcosphere(2, 1.7)),
                                      toPolygonSoup(makeTorus(3, 1, 12, 8)), polygonSample()}) {
    for (const std::string name : {"mesh.obj", "mesh.off", "mesh.ply"}) {
      SCOPED_TRACE(name);
      writeMesh(original, dir / name);
      const PolygonSoup back = readMesh(dir / name);
      EXPECT_EQ(back.positions, original.positions);  // shortest round-trip text / binary doubles
      EXPECT_EQ(back.faceStarts, original.faceStarts);
      EXPECT_EQ(back.cornerVertices, original.cornerVertices);
    }
  }
}

TEST(MeshWriters, StlRoundTripKeepsTrianglesToFloatPrecisionAndFansPolygons) {
  const TempDir dir;
  const PolygonSoup original = toPolygonSoup(makeIcosphere(2));
  writeMesh(original, dir / "mesh.stl");
  const PolygonSoup back = readMesh(dir / "mesh.stl");
  ASSERT_EQ(back.faceCount(), original.faceCount());
  EXPECT_EQ(back.vertexCount(), original.vertexCount());  // welded back by exact position
  for (std::size_t f = 0; f < original.faceCount(); ++f)
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d a = original.positions[original.cornerVertices[3 * f + i]];
      const Eigen::Vector3d b = back.positions[back.cornerVertices[3 * f + i]];
      EXPECT_LT((a - b).norm(), 1e-6);
    }
  writeMesh(polygonSample(), dir / "poly.stl");
  EXPECT_EQ(readMesh(dir / "poly.stl").faceCount(), 2u + 1u + 3u);
}

TEST(MeshWriters, ObjWritesOneTextureCoordinatePerCorner) {
  const TempDir dir;
  PolygonSoup soup = polygonSample();
  for (std::size_t c = 0; c < soup.cornerVertices.size(); ++c)
    soup.cornerTexcoords.emplace_back(0.125 * static_cast<double>(c),
                                      1.0 - 0.0625 * static_cast<double>(c));
  writeMesh(soup, dir / "textured.obj");
  const PolygonSoup back = readMesh(dir / "textured.obj");
  EXPECT_EQ(back.cornerVertices, soup.cornerVertices);
  EXPECT_EQ(back.cornerTexcoords, soup.cornerTexcoords);
}

TEST(MeshWriters, UnknownExtensionAndUnwritablePathAreErrors) {
  const TempDir dir;
  expectError([&] { writeMesh(polygonSample(), dir / "mesh.xyz"); }, ErrorCode::UnknownFormat);
  expectError([&] { writeMesh(polygonSample(), dir / "no/such/folder/mesh.obj"); }, ErrorCode::Io);
  expectError([&] { readMesh(dir / "missing.obj"); }, ErrorCode::Io);
  PolygonSoup outOfRange = polygonSample();
  outOfRange.cornerVertices[2] = 42;
  const Error e =
      expectError([&] { writeMesh(outOfRange, dir / "bad.stl"); }, ErrorCode::InvalidMesh);
  EXPECT_NE(std::string(e.what()).find("vertex 42"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace hexcover
