#include "core/mesh/load.h"

#include "core/common/error.h"

namespace hexcover {

RepairedMesh loadRepairedMesh(const std::filesystem::path& path, const ReadOptions& read,
                              const RepairOptions& repair) {
  const PolygonSoup soup = readMesh(path, read);
  try {
    return repairMesh(soup, repair);
  } catch (const Error& e) {
    throw Error(e.code(), path.filename().string() + ": " + e.what());
  }
}

TriMesh loadMesh(const std::filesystem::path& path) {
  return std::move(loadRepairedMesh(path).mesh);
}

}  // namespace hexcover
