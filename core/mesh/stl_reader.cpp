// STL reader, ASCII (one or several solids, keywords in any case) and binary. STL stores every
// triangle with its own three points: corners are welded by exact position, so that a closed
// surface comes out connected.

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <string>
#include <unordered_map>

#include "core/mesh/mesh_readers.h"
#include "core/mesh/text_scanner.h"

namespace hexcover::detail {
namespace {

constexpr std::size_t kHeaderBytes = 80;
constexpr std::size_t kTriangleBytes = 50;

// Welds corners by exact position (bitwise equal coordinates; +0 and −0 are the same point).
class ExactWelder {
 public:
  explicit ExactWelder(PolygonSoup& soup) : soup_(soup) {}
  std::uint32_t index(const Eigen::Vector3d& p) {
    const Key key{bits(p.x()), bits(p.y()), bits(p.z())};
    const auto [it, inserted] =
        indices_.try_emplace(key, static_cast<std::uint32_t>(soup_.positions.size()));
    if (inserted) soup_.positions.push_back(p);
    return it->second;
  }

 private:
  using Key = std::array<std::uint64_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 1469598103934665603ull;
      for (const auto word : k) h = (h ^ word) * 1099511628211ull ^ (word >> 29);
      return static_cast<std::size_t>(h);
    }
  };
  static std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x == 0.0 ? 0.0 : x); }
  PolygonSoup& soup_;
  std::unordered_map<Key, std::uint32_t, KeyHash> indices_;
};

float readFloatLE(const char* p) {
  std::uint32_t word = 0;
  for (int i = 3; i >= 0; --i) word = word << 8 | static_cast<unsigned char>(p[i]);
  return std::bit_cast<float>(word);
}

std::uint32_t readUint32LE(const char* p) {
  std::uint32_t word = 0;
  for (int i = 3; i >= 0; --i) word = word << 8 | static_cast<unsigned char>(p[i]);
  return word;
}

PolygonSoup parseBinaryStl(std::string_view bytes, const ReadOptions& options) {
  if (bytes.size() < kHeaderBytes + 4)
    throw Error(ErrorCode::MalformedInput,
                "STL: truncated binary data: " + std::to_string(bytes.size()) +
                    " bytes, shorter than the 84-byte header");
  const std::uint64_t count = readUint32LE(bytes.data() + kHeaderBytes);
  if (count > options.maxFaces)
    throw Error(ErrorCode::LimitExceeded,
                "STL: header (byte offset 80) declares " + std::to_string(count) +
                    " triangles, over the limit of " + std::to_string(options.maxFaces));
  const std::uint64_t expected = kHeaderBytes + 4 + kTriangleBytes * count;
  if (bytes.size() < expected)
    throw Error(ErrorCode::MalformedInput,
                "STL: truncated binary data: the header declares " + std::to_string(count) +
                    " triangles (" + std::to_string(expected) +
                    " bytes) but the data ends at byte offset " + std::to_string(bytes.size()) +
                    ", inside triangle " +
                    std::to_string((bytes.size() - kHeaderBytes - 4) / kTriangleBytes));
  PolygonSoup soup;
  ExactWelder welder(soup);
  soup.cornerVertices.reserve(3 * count);
  soup.faceStarts.reserve(count + 1);
  for (std::uint64_t t = 0; t < count; ++t) {
    const std::size_t offset = kHeaderBytes + 4 + kTriangleBytes * t;
    const char* record = bytes.data() + offset + 12;  // after the facet normal
    for (int corner = 0; corner < 3; ++corner) {
      Eigen::Vector3d p;
      for (int i = 0; i < 3; ++i) p[i] = readFloatLE(record + 12 * corner + 4 * i);
      if (!p.allFinite())
        throw Error(ErrorCode::InvalidMesh, "STL: triangle " + std::to_string(t) +
                                                " (byte offset " + std::to_string(offset) +
                                                ") has a NaN or infinite coordinate");
      soup.cornerVertices.push_back(welder.index(p));
    }
    soup.faceStarts.push_back(static_cast<std::uint32_t>(soup.cornerVertices.size()));
  }
  return soup;
}

bool equalsIgnoringCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

// ASCII STL: solid <name> { facet normal n n n / outer loop / vertex x y z (3 or more) / endloop /
// endfacet } endsolid [name], repeated for several solids. Facets with more than three vertices
// are kept as polygons.
PolygonSoup parseAsciiStl(std::string_view text, const ReadOptions& options) {
  constexpr std::string_view kFormat = "STL";
  PolygonSoup soup;
  ExactWelder welder(soup);
  LineScanner lines(text);
  std::string_view line;
  bool inSolid = false, inLoop = false;
  std::size_t solids = 0;
  std::size_t loopCorners = 0;
  while (lines.next(line)) {
    LineTokens tokens(line);
    const std::string_view keyword = tokens.next();
    if (keyword.empty()) continue;
    const auto expect = [&](bool ok, const char* what) {
      if (!ok)
        failAtLine(ErrorCode::MalformedInput, kFormat, lines.lineNumber(),
                   std::string("unexpected ") + quoted(keyword) + " " + what);
    };
    if (equalsIgnoringCase(keyword, "solid")) {
      expect(!inSolid, "(a solid inside a solid)");
      inSolid = true;
      ++solids;
    } else if (equalsIgnoringCase(keyword, "endsolid")) {
      expect(inSolid && !inLoop, "(no open solid)");
      inSolid = false;
    } else if (equalsIgnoringCase(keyword, "facet")) {
      expect(inSolid && !inLoop, "outside a solid");
      if (soup.faceCount() >= options.maxFaces)
        failAtLine(ErrorCode::LimitExceeded, kFormat, lines.lineNumber(),
                   "more than " + std::to_string(options.maxFaces) + " facets");
    } else if (equalsIgnoringCase(keyword, "outer")) {
      expect(inSolid && !inLoop, "(a loop inside a loop)");
      inLoop = true;
      loopCorners = 0;
    } else if (equalsIgnoringCase(keyword, "vertex")) {
      expect(inLoop, "outside an outer loop");
      Eigen::Vector3d p;
      for (int i = 0; i < 3; ++i) {
        const std::string_view token = tokens.next();
        if (!parseDouble(token, p[i]))
          failAtLine(ErrorCode::MalformedInput, kFormat, lines.lineNumber(),
                     "vertex needs 3 numbers, got " +
                         (token.empty() ? std::string("end of line") : quoted(token)));
      }
      if (!p.allFinite())
        failAtLine(ErrorCode::InvalidMesh, kFormat, lines.lineNumber(),
                   "vertex has a NaN or infinite coordinate");
      if (soup.positions.size() >= options.maxVertices)
        failAtLine(ErrorCode::LimitExceeded, kFormat, lines.lineNumber(),
                   "more than " + std::to_string(options.maxVertices) + " vertices");
      soup.cornerVertices.push_back(welder.index(p));
      ++loopCorners;
    } else if (equalsIgnoringCase(keyword, "endloop")) {
      expect(inLoop, "(no open loop)");
      if (loopCorners < 3)
        failAtLine(ErrorCode::MalformedInput, kFormat, lines.lineNumber(),
                   "a facet needs at least 3 vertices, got " + std::to_string(loopCorners));
      inLoop = false;
      soup.faceStarts.push_back(static_cast<std::uint32_t>(soup.cornerVertices.size()));
    } else if (equalsIgnoringCase(keyword, "endfacet")) {
      expect(inSolid && !inLoop, "inside a loop");
    } else {
      failAtLine(ErrorCode::MalformedInput, kFormat, lines.lineNumber(),
                 "unknown keyword " + quoted(keyword));
    }
  }
  if (inLoop || inSolid)
    failAtLine(
        ErrorCode::MalformedInput, kFormat, lines.lineNumber(),
        inLoop ? "the file ends inside a facet" : "the file ends inside a solid (no endsolid)");
  if (solids == 0) throw Error(ErrorCode::MalformedInput, "STL: no solid in the file");
  return soup;
}

bool startsWithSolid(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && (isBlank(bytes[i]) || bytes[i] == '\n')) ++i;
  return bytes.size() - i >= 5 && equalsIgnoringCase(bytes.substr(i, 5), "solid");
}

}  // namespace

bool hasBinaryStlSize(std::string_view bytes) {
  if (bytes.size() < kHeaderBytes + 4) return false;
  const std::uint64_t count = readUint32LE(bytes.data() + kHeaderBytes);
  return bytes.size() == kHeaderBytes + 4 + kTriangleBytes * count;
}

PolygonSoup parseStl(std::string_view bytes, const ReadOptions& options) {
  // A binary file may have a header starting with "solid": the size decides, and a NUL byte
  // (never in text) marks a truncated binary file whose header starts with "solid".
  const bool looksBinary = bytes.substr(0, 1024).find('\0') != std::string_view::npos;
  if (hasBinaryStlSize(bytes) || looksBinary || !startsWithSolid(bytes))
    return parseBinaryStl(bytes, options);
  return parseAsciiStl(bytes, options);
}

}  // namespace hexcover::detail
