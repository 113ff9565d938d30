// Reference figures for the quality floors of bench_remesh: what an error-driven simplifier
// reaches at the same vertex count. Every clean/ mesh is decimated to K = V/4 vertices by
// quadric-error edge collapses (Garland–Heckbert, OpenMesh's Decimater with normal-flip
// prevention), and the result is measured by core/metrics against the input, like a remesh.
//
// Quadric decimation spends its vertices where they lower the distance most and lets triangles
// take any shape, so its Hausdorff distance is a practical floor for a remesher with near-uniform,
// near-equilateral triangles at the same K (not a proven bound: the collapses are greedy).
//
// Prints a markdown table. Usage: bench_reference [--only NAME]

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/mesh/load.h"
#include "core/metrics/metrics.h"

namespace {

using namespace hexcover;

/// `mesh` decimated to at most `vertices` vertices by quadric-error collapses.
TriMesh decimateByQuadrics(TriMesh mesh, std::size_t vertices) {
  mesh.request_face_normals();
  mesh.update_face_normals();
  OpenMesh::Decimater::DecimaterT<TriMesh> decimater(mesh);
  OpenMesh::Decimater::ModQuadricT<TriMesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<TriMesh>::Handle normalFlipping;
  decimater.add(quadric);
  decimater.add(normalFlipping);
  decimater.initialize();
  decimater.decimate_to(vertices);
  mesh.garbage_collection();
  return mesh;
}

}  // namespace

int main(int argc, char** argv) {
  std::string only;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
      only = argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_reference [--only NAME]\n");
      return 2;
    }
  }
  const std::filesystem::path clean = std::filesystem::path(HEXCOVER_SHARED_MESHES) / "clean";
  if (!std::filesystem::is_directory(clean)) {
    std::printf("skipped: %s not found (the shared test meshes are not on this machine)\n",
                clean.c_str());
    return 0;
  }
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(clean))
    if (only.empty() || entry.path().filename().string().find(only) != std::string::npos)
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());

  std::printf("| mesh | K | V out | Hausdorff %% | min° | max° | SD° | irregular |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const auto& file : files) {
    const TriMesh input = loadMesh(file);
    std::size_t used = 0;
    for (const auto v : input.vertices()) used += input.is_isolated(v) ? 0 : 1;
    const std::size_t target = std::max<std::size_t>(4, used / 4);
    const TriMesh decimated = decimateByQuadrics(input, target);
    const QualityReport q = measureQuality(decimated, &input);
    std::printf("| %s | %zu | %d | %.3f | %.1f | %.1f | %.2f | %d |\n",
                file.filename().string().c_str(), target, q.vertices,
                q.distance ? q.distance->hausdorffPct : 0.0, q.angleMin, q.angleMax, q.angleSd,
                q.irregularInterior);
    std::fflush(stdout);
  }
  return 0;
}
