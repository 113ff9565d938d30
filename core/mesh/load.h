#pragma once
// One call from a file to the clean triangle mesh: read, triangulate, validate, repair.

#include <filesystem>

#include "core/mesh/io.h"
#include "core/mesh/repair.h"

namespace hexcover {

/// readMesh + repairMesh, with the report. Throws hexcover::Error on unreadable input or on a
/// mesh that repair refuses (see io.h and repair.h).
RepairedMesh loadRepairedMesh(const std::filesystem::path& path, const ReadOptions& read = {},
                              const RepairOptions& repair = {});

/// The repaired triangle mesh of a file (loadRepairedMesh without the report).
TriMesh loadMesh(const std::filesystem::path& path);

}  // namespace hexcover
