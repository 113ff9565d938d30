// Benchmark of mesh input (core/mesh): for each clean shared mesh, the median of R runs of
//   read    readMesh (file read in one piece + parse),
//   repair  repairMesh (validation of the input, triangulation, weld, drops, splits, orientation,
//           OpenMesh build, validation of the result),
//   write   writeMesh of the repaired mesh as binary PLY and as OBJ.
// Wall-clock and process CPU seconds are both printed: on a shared machine, CPU time is the
// steadier figure. One JSON line per mesh ("mesh_bench {...}") and a table for people.
// Usage: bench_mesh [--runs R] [file...]   (default: every file in shared/meshes/clean)

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/mesh/io.h"
#include "core/mesh/repair.h"

namespace {

using namespace hexcover;

struct Timing {
  double wall = 0.0;
  double cpu = 0.0;
};

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// Median wall and CPU seconds of `runs` calls of `step`.
Timing timeRuns(int runs, const std::function<void()>& step) {
  std::vector<double> wall, cpu;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpuStart = std::clock();
    step();
    cpu.push_back(static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return {median(wall), median(cpu)};
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5;
  std::vector<std::filesystem::path> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--runs" && i + 1 < argc) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else if (arg.starts_with("-")) {
      std::fprintf(stderr, "usage: bench_mesh [--runs R] [file...]\n");
      return 2;
    } else {
      files.emplace_back(arg);
    }
  }
  if (files.empty()) {
    const std::filesystem::path clean = std::filesystem::path(HEXCOVER_SHARED_MESHES) / "clean";
    if (!std::filesystem::is_directory(clean)) {
      std::fprintf(stderr, "bench_mesh: no meshes given and %s not found\n", clean.c_str());
      return 1;
    }
    for (const auto& entry : std::filesystem::directory_iterator(clean))
      files.push_back(entry.path());
    std::sort(files.begin(), files.end());
  }
  const auto scratch =
      std::filesystem::temp_directory_path() / ("hexcover_bench_mesh_" + std::to_string(getpid()));
  std::filesystem::create_directories(scratch);

  std::printf("%-28s %9s %9s | %17s | %17s | %17s\n", "mesh", "vertices", "faces",
              "read wall/cpu ms", "repair wall/cpu ms", "write wall/cpu ms");
  for (const auto& path : files) {
    PolygonSoup soup;
    RepairedMesh repaired;
    const Timing read = timeRuns(runs, [&] { soup = readMesh(path); });
    const Timing repair = timeRuns(runs, [&] { repaired = repairMesh(soup); });
    const PolygonSoup result = toPolygonSoup(repaired.mesh);
    const Timing write = timeRuns(runs, [&] {
      writeMesh(result, scratch / "out.ply");
      writeMesh(result, scratch / "out.obj");
    });
    const std::string name = path.filename().string();
    std::printf(
        "mesh_bench {\"mesh\":\"%s\",\"runs\":%d,\"vertices\":%zu,\"faces\":%zu,"
        "\"read_s\":%.4f,\"read_cpu_s\":%.4f,\"repair_s\":%.4f,\"repair_cpu_s\":%.4f,"
        "\"write_s\":%.4f,\"write_cpu_s\":%.4f}\n",
        name.c_str(), runs, soup.vertexCount(), soup.faceCount(), read.wall, read.cpu, repair.wall,
        repair.cpu, write.wall, write.cpu);
    std::printf("%-28s %9zu %9zu | %8.1f %8.1f | %8.1f %8.1f | %8.1f %8.1f\n", name.c_str(),
                soup.vertexCount(), soup.faceCount(), 1e3 * read.wall, 1e3 * read.cpu,
                1e3 * repair.wall, 1e3 * repair.cpu, 1e3 * write.wall, 1e3 * write.cpu);
  }
  std::filesystem::remove_all(scratch);
  return 0;
}
