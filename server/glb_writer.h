#pragma once
// Binary glTF 2.0 (.glb) output of a polygon soup through tinygltf (Debian libtinygltf-dev).

#include <filesystem>

#include "core/mesh/mesh.h"

namespace hexcover::server {

/// Writes `soup` as one triangle primitive: polygons fan-triangulated, float32 POSITION, and
/// TEXCOORD_0 when soup.cornerTexcoords is set (then vertices are split per distinct
/// (vertex, uv) pair, since glTF has one index per vertex). glTF's v axis points down: v is
/// stored as 1 − v. Throws Error(Io) when the file cannot be written, Error(InvalidMesh) when
/// the soup has more than 2^32 − 1 corners.
void writeGlb(const PolygonSoup& soup, const std::filesystem::path& path);

}  // namespace hexcover::server
