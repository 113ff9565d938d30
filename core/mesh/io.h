#pragma once
// Mesh file input and output: OBJ, OFF, PLY and STL, read from bytes or files into a
// PolygonSoup and written from one.
//
// The readers are this project's own (see docs/DEPENDENCIES.md, "Mesh input"): they detect the
// format from the bytes, enforce size limits while parsing (a header that claims 10^12 faces is
// refused before anything is allocated), and fail with an Error that names the problem and its
// line number (text) or byte offset (binary). Reading does not repair: polygons stay polygons,
// vertices are not welded (except STL, whose corners are welded by exact position because the
// format stores no shared vertices). See repair.h and load.h for the cleaned triangle mesh.

#include <cstddef>
#include <filesystem>
#include <string_view>

#include "core/mesh/mesh.h"

namespace hexcover {

enum class MeshFormat { Obj, Off, Ply, Stl };

/// Lower-case name of a format ("obj", "off", "ply", "stl").
const char* meshFormatName(MeshFormat format);

/// Limits enforced while parsing. Exceeding one throws Error(LimitExceeded) before the
/// corresponding arrays are allocated.
struct ReadOptions {
  std::size_t maxFaces = 5'000'000;      ///< polygons (STL: triangles; PLY strips: triangles)
  std::size_t maxVertices = 15'000'000;  ///< vertex records in the file
};

/// The format of a mesh file, from its content (not its name). STL is binary when the file size
/// is exactly 84 + 50·n for the n stored at byte 80, even if the header starts with "solid".
/// Throws Error(UnknownFormat) when the bytes are none of the four formats.
MeshFormat detectFormat(std::string_view bytes);

/// The format that a file name's extension stands for (case-insensitive .obj/.off/.ply/.stl).
/// Throws Error(UnknownFormat) naming the extension otherwise.
MeshFormat formatFromExtension(const std::filesystem::path& path);

/// Parses a mesh from its bytes (format detected with detectFormat). Throws Error with code
/// UnknownFormat, MalformedInput (truncated data, bad token, index out of range; the message
/// names the line or byte offset), InvalidMesh (NaN/Inf coordinate) or LimitExceeded.
PolygonSoup parseMesh(std::string_view bytes, const ReadOptions& options = {});

/// Reads a whole file and parses it with parseMesh. Throws Error(Io) if it cannot be read.
PolygonSoup readMesh(const std::filesystem::path& path, const ReadOptions& options = {});

/// Writes `soup` in the format given by the extension of `path` (formatFromExtension):
/// .obj (ASCII; one `vt` per corner when soup.cornerTexcoords is non-empty), .off (ASCII),
/// .ply (binary little endian, double coordinates, int indices), .stl (binary, float
/// coordinates; polygons fan-triangulated). Streams to the file. Throws Error(Io) when the file
/// cannot be written, Error(InvalidMesh) for an inconsistent soup or an out-of-range index.
void writeMesh(const PolygonSoup& soup, const std::filesystem::path& path);

}  // namespace hexcover
