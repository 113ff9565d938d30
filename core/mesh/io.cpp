#include "core/mesh/io.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <string>

#include "core/common/error.h"
#include "core/mesh/mesh_readers.h"

namespace hexcover {
namespace {

bool startsWithWord(std::string_view text, std::string_view word) {
  return text.size() >= word.size() &&
         std::equal(word.begin(), word.end(), text.begin(), [](char a, char b) {
           return std::tolower(static_cast<unsigned char>(a)) ==
                  std::tolower(static_cast<unsigned char>(b));
         });
}

std::string_view firstToken(std::string_view text) {
  const std::size_t end = text.find_first_of(" \t\r\n#");
  return text.substr(0, end);
}

// An OFF header keyword: [ST][C][N][4][n]OFF.
bool isOffKeyword(std::string_view token) {
  if (token.size() < 3 || token.substr(token.size() - 3) != "OFF") return false;
  const std::string_view prefix = token.substr(0, token.size() - 3);
  return prefix.find_first_not_of("STCN4n") == std::string_view::npos && prefix.size() <= 6;
}

// The first statement of an OBJ file, skipping blank and comment lines.
bool looksLikeObj(std::string_view text) {
  static constexpr std::string_view kKeywords[] = {
      "v", "vt", "vn",     "vp",     "f",      "fo",  "l",    "p",   "o",
      "g", "s",  "usemtl", "mtllib", "cstype", "deg", "curv", "surf"};
  std::size_t pos = 0;
  constexpr std::size_t kScanLimit = 64 * 1024;
  while (pos < text.size() && pos < kScanLimit) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    const std::size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string_view::npos || line[start] == '#') continue;
    const std::string_view keyword = firstToken(line.substr(start));
    return std::find(std::begin(kKeywords), std::end(kKeywords), keyword) != std::end(kKeywords);
  }
  return false;
}

std::string preview(std::string_view bytes) {
  std::string shown(bytes.substr(0, 16));
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '.';
  return "'" + shown + "'";
}

}  // namespace

const char* meshFormatName(MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj:
      return "obj";
    case MeshFormat::Off:
      return "off";
    case MeshFormat::Ply:
      return "ply";
    case MeshFormat::Stl:
      return "stl";
  }
  return "unknown";
}

MeshFormat detectFormat(std::string_view bytes) {
  if (bytes.empty()) throw Error(ErrorCode::UnknownFormat, "empty input: no mesh data");
  std::string_view text = bytes;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte order mark
  const std::size_t start = text.find_first_not_of(" \t\r\n");
  const std::string_view trimmed =
      start == std::string_view::npos ? std::string_view{} : text.substr(start);
  if (bytes.substr(0, 3) == "ply" && bytes.size() > 3 && (bytes[3] == '\n' || bytes[3] == '\r'))
    return MeshFormat::Ply;
  if (isOffKeyword(firstToken(trimmed))) return MeshFormat::Off;
  // Binary STL is decided by its size (84 + 50·n), whatever its 80-byte header says.
  if (detail::hasBinaryStlSize(bytes)) return MeshFormat::Stl;
  if (startsWithWord(trimmed, "solid")) return MeshFormat::Stl;
  if (looksLikeObj(text)) return MeshFormat::Obj;
  // Not text: the only binary format without a magic number is STL (a truncated one is refused
  // by the STL reader with the missing byte count).
  const bool binary = bytes.substr(0, 84).find('\0') != std::string_view::npos;
  if (binary && bytes.size() >= 84) return MeshFormat::Stl;
  throw Error(ErrorCode::UnknownFormat, "unknown mesh format: the data (starting with " +
                                            preview(bytes) + ") is not OBJ, OFF, PLY or STL");
}

MeshFormat formatFromExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".off") return MeshFormat::Off;
  if (extension == ".ply") return MeshFormat::Ply;
  if (extension == ".stl") return MeshFormat::Stl;
  throw Error(ErrorCode::UnknownFormat, "unknown mesh file extension '" +
                                            path.extension().string() + "' of '" + path.string() +
                                            "' (use .obj, .off, .ply or .stl)");
}

PolygonSoup parseMesh(std::string_view bytes, const ReadOptions& options) {
  switch (detectFormat(bytes)) {
    case MeshFormat::Obj:
      return detail::parseObj(bytes, options);
    case MeshFormat::Off:
      return detail::parseOff(bytes, options);
    case MeshFormat::Ply:
      return detail::parsePly(bytes, options);
    case MeshFormat::Stl:
      return detail::parseStl(bytes, options);
  }
  throw Error(ErrorCode::UnknownFormat, "unknown mesh format");
}

PolygonSoup readMesh(const std::filesystem::path& path, const ReadOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw Error(ErrorCode::Io, "cannot open '" + path.string() + "': " + std::strerror(errno));
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw Error(ErrorCode::Io, "cannot read '" + path.string() + "': " + ec.message());
  std::string bytes(size, '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size)))
    throw Error(ErrorCode::Io, "cannot read '" + path.string() + "'");
  try {
    return parseMesh(bytes, options);
  } catch (const Error& e) {
    throw Error(e.code(), path.filename().string() + ": " + e.what());
  }
}

}  // namespace hexcover
