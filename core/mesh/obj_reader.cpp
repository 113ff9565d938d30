// Wavefront OBJ reader: v, vt and f lines (v/vt/vn corners, negative indices, `\` line
// continuations, comments); every other statement (vn, o, g, s, usemtl, mtllib, l, ...) is ignored.

#include <string>
#include <vector>

#include "core/mesh/mesh_readers.h"
#include "core/mesh/text_scanner.h"

namespace hexcover::detail {
namespace {

constexpr std::string_view kFormat = "OBJ";

// Resolves a 1-based (or negative, relative) OBJ index against the `count` elements read so far.
// Positive indices may refer forward; they are checked against the final count at the end.
std::int64_t resolveIndex(std::int64_t index, std::size_t count, std::size_t line,
                          const char* what) {
  if (index > 0) return index - 1;
  if (index < 0 && -index <= static_cast<std::int64_t>(count))
    return static_cast<std::int64_t>(count) + index;
  failAtLine(ErrorCode::MalformedInput, kFormat, line,
             std::string(what) + " index " + std::to_string(index) + " is out of range (" +
                 std::to_string(count) + " defined so far)");
}

}  // namespace

PolygonSoup parseObj(std::string_view text, const ReadOptions& options) {
  PolygonSoup soup;
  std::vector<Eigen::Vector2d> texcoords;
  std::vector<std::int64_t> cornerTexcoord;  // index into texcoords, or -1 when absent
  std::vector<std::uint32_t> faceLine;       // for range errors after the last vertex is known
  std::vector<std::int64_t> corners;         // resolved vertex indices of the current face
  bool everyCornerTextured = true;
  LineScanner lines(text);
  std::string joined;  // a logical line assembled from `\` continuations
  std::string_view line;
  while (lines.next(line)) {
    const std::size_t lineNumber = lines.lineNumber();
    if (!line.empty() && line.back() == '\\') {
      joined.assign(line.substr(0, line.size() - 1));
      std::string_view more;
      while (lines.next(more)) {
        const bool continues = !more.empty() && more.back() == '\\';
        joined += ' ';
        joined += continues ? more.substr(0, more.size() - 1) : more;
        if (!continues) break;
      }
      line = joined;
    }
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    LineTokens tokens(line);
    const std::string_view keyword = tokens.next();
    if (keyword == "v") {
      if (soup.positions.size() >= options.maxVertices)
        failAtLine(ErrorCode::LimitExceeded, kFormat, lineNumber,
                   "more than " + std::to_string(options.maxVertices) + " vertices");
      Eigen::Vector3d p;
      for (int i = 0; i < 3; ++i) {
        const std::string_view token = tokens.next();
        if (!parseDouble(token, p[i]))
          failAtLine(ErrorCode::MalformedInput, kFormat, lineNumber,
                     "vertex needs 3 numbers, got " +
                         (token.empty() ? std::string("end of line") : quoted(token)));
      }
      if (!p.allFinite())
        failAtLine(ErrorCode::InvalidMesh, kFormat, lineNumber,
                   "vertex " + std::to_string(soup.positions.size() + 1) +
                       " has a NaN or infinite coordinate");
      soup.positions.push_back(p);
    } else if (keyword == "vt") {
      Eigen::Vector2d uv(0.0, 0.0);
      const std::string_view u = tokens.next(), v = tokens.next();
      if (!parseDouble(u, uv[0]) || (!v.empty() && !parseDouble(v, uv[1])))
        failAtLine(ErrorCode::MalformedInput, kFormat, lineNumber,
                   "texture coordinate is not a number");
      if (texcoords.size() >= options.maxVertices * 4)
        failAtLine(ErrorCode::LimitExceeded, kFormat, lineNumber, "too many texture coordinates");
      texcoords.push_back(uv);
    } else if (keyword == "f" || keyword == "fo") {
      if (soup.faceCount() >= options.maxFaces)
        failAtLine(ErrorCode::LimitExceeded, kFormat, lineNumber,
                   "more than " + std::to_string(options.maxFaces) + " faces");
      corners.clear();
      for (std::string_view corner = tokens.next(); !corner.empty(); corner = tokens.next()) {
        // v, v/vt, v//vn or v/vt/vn
        const std::size_t slash = corner.find('/');
        std::int64_t vertex = 0;
        if (!parseInteger(corner.substr(0, slash), vertex) || vertex == 0)
          failAtLine(ErrorCode::MalformedInput, kFormat, lineNumber,
                     "bad face corner " + quoted(corner));
        corners.push_back(resolveIndex(vertex, soup.positions.size(), lineNumber, "vertex"));
        std::int64_t texcoord = -1;
        if (slash != std::string_view::npos) {
          std::string_view rest = corner.substr(slash + 1);
          rest = rest.substr(0, rest.find('/'));
          std::int64_t raw = 0;
          if (!rest.empty()) {
            if (!parseInteger(rest, raw) || raw == 0)
              failAtLine(ErrorCode::MalformedInput, kFormat, lineNumber,
                         "bad face corner " + quoted(corner));
            texcoord = resolveIndex(raw, texcoords.size(), lineNumber, "texture coordinate");
          }
        }
        if (texcoord < 0) everyCornerTextured = false;
        if (everyCornerTextured) cornerTexcoord.push_back(texcoord);
      }
      if (corners.empty())
        failAtLine(ErrorCode::MalformedInput, kFormat, lineNumber, "face without vertices");
      for (const auto v : corners) {
        if (v > static_cast<std::int64_t>(UINT32_MAX) - 1)
          failAtLine(ErrorCode::MalformedInput, kFormat, lineNumber,
                     "vertex index " + std::to_string(v + 1) + " is out of range");
        soup.cornerVertices.push_back(static_cast<std::uint32_t>(v));
      }
      soup.faceStarts.push_back(static_cast<std::uint32_t>(soup.cornerVertices.size()));
      faceLine.push_back(static_cast<std::uint32_t>(lineNumber));
    }
    // Any other statement carries nothing we keep.
  }
  for (std::size_t f = 0; f < soup.faceCount(); ++f)
    for (std::size_t c = soup.faceStarts[f]; c < soup.faceStarts[f + 1]; ++c)
      if (soup.cornerVertices[c] >= soup.positions.size())
        failAtLine(ErrorCode::MalformedInput, kFormat, faceLine[f],
                   "vertex index " + std::to_string(soup.cornerVertices[c] + 1ull) +
                       " is out of range (the file has " + std::to_string(soup.positions.size()) +
                       " vertices)");
  if (everyCornerTextured && !soup.cornerVertices.empty()) {
    soup.cornerTexcoords.reserve(cornerTexcoord.size());
    for (std::size_t c = 0; c < cornerTexcoord.size(); ++c) {
      if (cornerTexcoord[c] >= static_cast<std::int64_t>(texcoords.size())) {
        std::size_t f = 0;
        while (soup.faceStarts[f + 1] <= c) ++f;
        failAtLine(ErrorCode::MalformedInput, kFormat, faceLine[f],
                   "texture coordinate index " + std::to_string(cornerTexcoord[c] + 1) +
                       " is out of range");
      }
      soup.cornerTexcoords.push_back(texcoords[static_cast<std::size_t>(cornerTexcoord[c])]);
    }
  }
  return soup;
}

}  // namespace hexcover::detail
