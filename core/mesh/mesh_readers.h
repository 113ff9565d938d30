#pragma once
// Internal to core/mesh: the per-format parsers behind parseMesh (io.h). Each throws Error with
// the line number (text) or byte offset (binary) of the problem.

#include <string_view>

#include "core/mesh/io.h"

namespace hexcover::detail {

PolygonSoup parseObj(std::string_view text, const ReadOptions& options);
PolygonSoup parseOff(std::string_view text, const ReadOptions& options);
PolygonSoup parsePly(std::string_view bytes, const ReadOptions& options);
PolygonSoup parseStl(std::string_view bytes, const ReadOptions& options);

/// Whether the bytes are a binary STL: at least 84 bytes and, for the n at byte 80, exactly
/// 84 + 50·n bytes.
bool hasBinaryStlSize(std::string_view bytes);

}  // namespace hexcover::detail
