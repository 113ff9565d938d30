#pragma once
// Access to the shared test meshes (../shared/meshes beside the checkout).
// A user's clone has no ../shared: tests that need those files skip with a clear message, and
// every invariant is also tested on meshes that the tests generate (core/mesh/primitives.h).

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace hexcover::test {

/// Folder of the shared meshes (may not exist).
std::filesystem::path sharedMeshDir();

/// Path of a shared mesh, e.g. sharedMesh("clean/spot.obj"); empty path when it is absent.
std::filesystem::path sharedMesh(const std::string& relativePath);

/// Every file in shared/meshes/<group> ("clean" or "nasty"), sorted; empty when absent.
std::vector<std::filesystem::path> sharedMeshGroup(const std::string& group);

}  // namespace hexcover::test

/// Declares `var` as the path of a shared mesh, or skips the test when it is not there.
#define HEXCOVER_SHARED_MESH_OR_SKIP(var, relative)                                          \
  const std::filesystem::path var = ::hexcover::test::sharedMesh(relative);                 \
  if (var.empty())                                                                           \
  GTEST_SKIP() << "shared test mesh " << (relative) << " not found under "                  \
               << ::hexcover::test::sharedMeshDir() << " (a clone without ../shared skips this)"
