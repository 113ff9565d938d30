// Field stage benchmark: for every mesh in shared/meshes/clean (or the files given as arguments),
// the whole field stage (computeRosyField with default options) run 5 times. Prints one JSON
// line per mesh (machine-readable; step times are medians of the per-run sums per step name),
// then a table: faces, singularities before/after clustering, median seconds, peak memory.
// Never asserts on time.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/common/memory.h"
#include "core/field/rosy_field.h"
#include "core/mesh/load.h"

namespace {

constexpr int kRuns = 5;

/// CPU time of the process: on a machine shared with other jobs, wall time overstates the cost.
double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n == 0 ? 0.0 : n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

struct Row {
  std::string name;
  std::size_t faces = 0;
  int before = 0, after = 0, boundary = 0;
  double seconds = 0.0, cpu = 0.0, peakMiB = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::filesystem::path> files;
  hexcover::FieldOptions options;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--threads" && i + 1 < argc) {
      options.threads = std::atoi(argv[++i]);
    } else if (argv[i][0] == '-' || !options.validate().empty()) {
      std::fprintf(stderr,
                   "usage: bench_field [--threads T] [mesh...]   (default: 2 threads, every "
                   "shared clean/ mesh)\n");
      return 2;
    } else {
      files.emplace_back(argv[i]);
    }
  }
  if (files.empty()) {
    const std::filesystem::path dir = std::filesystem::path(HEXCOVER_SHARED_MESHES) / "clean";
    if (!std::filesystem::is_directory(dir)) {
      std::fprintf(stderr, "bench_field: no meshes given and %s does not exist\n", dir.c_str());
      return 1;
    }
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      if (entry.is_regular_file() && entry.path().extension() != ".md")
        files.push_back(entry.path());
    std::sort(files.begin(), files.end());
  }

  std::vector<Row> rows;
  for (const auto& file : files) {
    hexcover::resetPeakMemory();  // the peak reported after a mesh is that mesh's own
    const hexcover::TriMesh mesh = hexcover::loadMesh(file);
    std::vector<double> total, cpu;
    std::map<std::string, std::vector<double>> steps;
    Row row{file.filename().string(), mesh.n_faces()};
    for (int run = 0; run < kRuns; ++run) {
      const auto start = std::chrono::steady_clock::now();
      const double cpuStart = cpuSeconds();
      const hexcover::RosyField field = hexcover::computeRosyField(mesh, options);
      cpu.push_back(cpuSeconds() - cpuStart);
      total.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      std::map<std::string, double> sums;
      for (const auto& t : field.timings) sums[t.step] += t.seconds;
      for (const auto& [step, seconds] : sums) steps[step].push_back(seconds);
      row.before = field.singularitiesInitial;
      row.after = static_cast<int>(field.singularities.size());
      row.boundary = 0;
      for (const auto& s : field.singularities) row.boundary += s.onBoundary ? 1 : 0;
    }
    row.seconds = median(total);
    row.cpu = median(cpu);
    row.peakMiB = hexcover::peakMemoryMiB();
    std::printf(
        "{\"mesh\": \"%s\", \"faces\": %zu, \"singularities_initial\": %d, "
        "\"singularities_final\": %d, \"singularities_final_boundary\": %d, "
        "\"seconds_median\": %.4f, \"cpu_seconds_median\": %.4f, \"peak_memory_mib\": %.1f, "
        "\"steps\": {",
        row.name.c_str(), row.faces, row.before, row.after, row.boundary, row.seconds, row.cpu,
        row.peakMiB);
    bool first = true;
    for (const auto& [step, seconds] : steps) {
      std::printf("%s\"%s\": %.4f", first ? "" : ", ", step.c_str(), median(seconds));
      first = false;
    }
    std::printf("}}\n");
    std::fflush(stdout);
    rows.push_back(row);
  }

  std::printf("\n%-28s %8s %8s %8s %10s %10s %10s %10s\n", "mesh", "faces", "sing.0", "sing.1",
              "(boundary)", "seconds", "cpu s", "peak MiB");
  for (const auto& r : rows)
    std::printf("%-28s %8zu %8d %8d %10d %10.3f %10.3f %10.1f\n", r.name.c_str(), r.faces, r.before,
                r.after, r.boundary, r.seconds, r.cpu, r.peakMiB);
  std::printf(
      "(seconds, cpu s: medians of %d runs of computeRosyField, wall and process CPU time; "
      "sing.0/sing.1: singularities before/after clustering; peak MiB: peak resident memory "
      "while loading the mesh and running the field 5 times)\n",
      kRuns);
  return 0;
}
