// Object File Format reader: the OFF, COFF, NOFF, CNOFF, STOFF... headers (extra per-vertex
// values such as colours, normals or texture coordinates are skipped), face colours, `#` comments
// anywhere. The 4D and n-dimensional variants and binary OFF are refused.

#include <algorithm>
#include <string>

#include "core/mesh/mesh_readers.h"
#include "core/mesh/text_scanner.h"

namespace hexcover::detail {
namespace {

constexpr std::string_view kFormat = "OFF";

// Tokens across lines with comments removed, remembering the line of the last token.
class OffTokens {
 public:
  explicit OffTokens(std::string_view text) : lines_(text) {}
  /// The next token, or empty at the end of the file.
  std::string_view next() {
    for (;;) {
      const std::string_view token = tokens_.next();
      if (!token.empty()) return token;
      if (!advanceLine()) return {};
    }
  }
  /// Drops what is left of the current line (extra values after the ones we need).
  void skipRestOfLine() { tokens_ = LineTokens({}); }
  std::size_t line() const { return lines_.lineNumber(); }

 private:
  bool advanceLine() {
    std::string_view line;
    if (!lines_.next(line)) return false;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    tokens_ = LineTokens(line);
    return true;
  }
  LineScanner lines_;
  LineTokens tokens_{{}};
};

std::int64_t parseCount(std::string_view token, std::size_t line, const char* what) {
  std::int64_t value = 0;
  if (!parseInteger(token, value) || value < 0)
    failAtLine(ErrorCode::MalformedInput, kFormat, line,
               std::string("expected the ") + what + ", got " +
                   (token.empty() ? "end of file" : quoted(token)));
  return value;
}

std::int64_t readCount(OffTokens& tokens, const char* what) {
  const std::string_view token = tokens.next();
  return parseCount(token, tokens.line(), what);
}

}  // namespace

PolygonSoup parseOff(std::string_view text, const ReadOptions& options) {
  OffTokens tokens(text);
  const std::string_view header = tokens.next();
  const std::size_t at = header.rfind("OFF");
  if (at == std::string_view::npos || at + 3 != header.size())
    failAtLine(ErrorCode::MalformedInput, kFormat, tokens.line(),
               "expected an OFF header, got " + quoted(header));
  const std::string_view prefix = header.substr(0, at);
  if (prefix.find('4') != std::string_view::npos || prefix.find('n') != std::string_view::npos)
    failAtLine(ErrorCode::MalformedInput, kFormat, tokens.line(),
               "4D and n-dimensional OFF (" + quoted(header) + ") are not supported");
  const std::string_view first = tokens.next();
  if (first == "BINARY")
    failAtLine(ErrorCode::MalformedInput, kFormat, tokens.line(), "binary OFF is not supported");
  const std::int64_t vertexCount = parseCount(first, tokens.line(), "vertex count");
  const std::int64_t faceCount = readCount(tokens, "face count");
  tokens.skipRestOfLine();  // the edge count, unused
  if (static_cast<std::uint64_t>(vertexCount) > options.maxVertices)
    failAtLine(ErrorCode::LimitExceeded, kFormat, tokens.line(),
               "header declares " + std::to_string(vertexCount) + " vertices, over the limit of " +
                   std::to_string(options.maxVertices));
  if (static_cast<std::uint64_t>(faceCount) > options.maxFaces)
    failAtLine(ErrorCode::LimitExceeded, kFormat, tokens.line(),
               "header declares " + std::to_string(faceCount) + " faces, over the limit of " +
                   std::to_string(options.maxFaces));

  PolygonSoup soup;
  // Every record takes at least a few bytes: never reserve more than the text can hold.
  soup.positions.reserve(
      std::min<std::size_t>(static_cast<std::size_t>(vertexCount), text.size() / 6));
  soup.faceStarts.reserve(
      std::min<std::size_t>(static_cast<std::size_t>(faceCount), text.size() / 8) + 1);
  for (std::int64_t v = 0; v < vertexCount; ++v) {
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i) {
      const std::string_view token = tokens.next();
      if (!parseDouble(token, p[i]))
        failAtLine(ErrorCode::MalformedInput, kFormat, tokens.line(),
                   "vertex " + std::to_string(v) + " needs 3 numbers, got " +
                       (token.empty() ? std::string("end of file") : quoted(token)));
    }
    if (!p.allFinite())
      failAtLine(ErrorCode::InvalidMesh, kFormat, tokens.line(),
                 "vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
    tokens.skipRestOfLine();  // colour, normal or texture coordinates
    soup.positions.push_back(p);
  }
  for (std::int64_t f = 0; f < faceCount; ++f) {
    const std::int64_t n = readCount(tokens, "number of corners of a face");
    for (std::int64_t i = 0; i < n; ++i) {
      const std::string_view token = tokens.next();
      std::int64_t index = 0;
      if (!parseInteger(token, index))
        failAtLine(ErrorCode::MalformedInput, kFormat, tokens.line(),
                   "face " + std::to_string(f) + " needs " + std::to_string(n) +
                       " vertex indices, got " +
                       (token.empty() ? std::string("end of file") : quoted(token)));
      if (index < 0 || index >= vertexCount)
        failAtLine(ErrorCode::MalformedInput, kFormat, tokens.line(),
                   "face " + std::to_string(f) + " refers to vertex " + std::to_string(index) +
                       ", out of range (the file has " + std::to_string(vertexCount) +
                       " vertices)");
      soup.cornerVertices.push_back(static_cast<std::uint32_t>(index));
    }
    tokens.skipRestOfLine();  // face colour
    soup.faceStarts.push_back(static_cast<std::uint32_t>(soup.cornerVertices.size()));
  }
  return soup;
}

}  // namespace hexcover::detail
