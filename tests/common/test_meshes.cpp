#include "tests/common/test_meshes.h"

#include <algorithm>

namespace hexcover::test {

std::filesystem::path sharedMeshDir() { return HEXCOVER_SHARED_MESHES; }

std::filesystem::path sharedMesh(const std::string& relativePath) {
  const auto path = sharedMeshDir() / relativePath;
  return std::filesystem::exists(path) ? path : std::filesystem::path{};
}

std::vector<std::filesystem::path> sharedMeshGroup(const std::string& group) {
  std::vector<std::filesystem::path> files;
  const auto dir = sharedMeshDir() / group;
  if (!std::filesystem::is_directory(dir)) return files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() != ".md") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace hexcover::test
