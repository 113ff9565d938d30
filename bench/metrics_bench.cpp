// Benchmark of the quality metrics (core/metrics) on a realistic pair: the Stanford bunny
// (clean/stanford-bunny.obj, 69K faces) and a copy of it whose vertices are displaced along their
// normals by a smooth function (amplitude 0.25% of the bounding-box diagonal), written to a
// temporary OBJ so that both meshes go through read + validate/repair.
//
// Steps timed (median of R runs): read and repair of each file, then measureQuality of the copy
// against the bunny, split into shape/topology and the two-sided distance. Prints one JSON line
// per step ("metrics_bench {...}"), the distance figures, and a table for people.
// Usage: bench_metrics [--runs R] [--threads T]

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/mesh/io.h"
#include "core/mesh/repair.h"
#include "core/metrics/metrics.h"

namespace {

using namespace hexcover;

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

/// Wall-clock and process CPU seconds (all threads) of `runs` calls of one step.
struct Step {
  std::string name;
  std::vector<double> wall, cpu;
};

Step timeRuns(std::string name, int runs, const std::function<void()>& step) {
  Step out{std::move(name), {}, {}};
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpuStart = std::clock();
    step();
    out.cpu.push_back(static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC);
    out.wall.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return out;
}

/// The mesh with every vertex moved along its normal by a·sin(kx)·sin(ky)·sin(kz), with
/// a = 0.25% and the wavelength 1/4 of the bounding-box diagonal.
TriMesh displaced(TriMesh mesh) {
  const double diagonal = boundingBoxDiagonal(mesh);
  const double amplitude = 0.0025 * diagonal, k = 2.0 * M_PI / (0.25 * diagonal);
  mesh.request_face_normals();
  mesh.request_vertex_normals();
  mesh.update_normals();
  for (const auto vh : mesh.vertices()) {
    const auto p = mesh.point(vh);
    const double offset = amplitude * std::sin(k * p[0]) * std::sin(k * p[1]) * std::sin(k * p[2]);
    mesh.set_point(vh, p + offset * mesh.normal(vh));
  }
  mesh.release_vertex_normals();
  mesh.release_face_normals();
  return mesh;
}

int intOption(int argc, char** argv, const std::string& name, int fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (argv[i] == name) return std::max(1, std::atoi(argv[i + 1]));
  return fallback;
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = intOption(argc, argv, "--runs", 5);
  MetricsOptions options;
  options.distance.threads = intOption(argc, argv, "--threads", 2);

  const std::filesystem::path bunnyPath =
      std::filesystem::path(HEXCOVER_SHARED_MESHES) / "clean/stanford-bunny.obj";
  if (!std::filesystem::exists(bunnyPath)) {
    std::fprintf(stderr, "bench_metrics: %s not found (needs ../shared/meshes)\n",
                 bunnyPath.c_str());
    return 1;
  }
  const std::filesystem::path copyPath =
      std::filesystem::temp_directory_path() /
      ("hexcover_bench_bunny_displaced_" + std::to_string(::getpid()) + ".obj");
  writeMesh(toPolygonSoup(displaced(repairMesh(readMesh(bunnyPath)).mesh)), copyPath);

  std::vector<Step> steps;
  PolygonSoup bunnySoup, copySoup;
  TriMesh bunny, copy;
  QualityReport report;
  steps.push_back(timeRuns("read_bunny", runs, [&] { bunnySoup = readMesh(bunnyPath); }));
  steps.push_back(timeRuns("repair_bunny", runs, [&] { bunny = repairMesh(bunnySoup).mesh; }));
  steps.push_back(timeRuns("read_copy", runs, [&] { copySoup = readMesh(copyPath); }));
  steps.push_back(timeRuns("repair_copy", runs, [&] { copy = repairMesh(copySoup).mesh; }));
  std::vector<double> shape, distance;
  steps.push_back(timeRuns("metrics", runs, [&] {
    report = measureQuality(copy, &bunny, options);
    double rest = 0.0;
    for (const auto& t : report.timings) {
      if (t.step == "distance")
        distance.push_back(t.seconds);
      else
        rest += t.seconds;
    }
    shape.push_back(rest);
  }));
  std::filesystem::remove(copyPath);

  double total = 0.0, totalCpu = 0.0;
  for (const auto& step : steps) {
    total += median(step.wall);
    totalCpu += median(step.cpu);
    std::printf(
        "metrics_bench {\"step\": \"%s\", \"median_s\": %.4f, \"median_cpu_s\": %.4f, "
        "\"runs\": %d}\n",
        step.name.c_str(), median(step.wall), median(step.cpu), runs);
  }
  const auto& d = *report.distance;
  std::printf(
      "metrics_bench {\"step\": \"total\", \"median_s\": %.4f, \"median_cpu_s\": %.4f, "
      "\"faces\": [%d, %zu], "
      "\"threads\": %d, \"hausdorff_pct\": %.5f, \"hausdorff_upper_bound_pct\": %.5f, "
      "\"certified\": %s, \"mean_dist_pct\": %.5f, \"rms_dist_pct\": %.5f, \"distance_samples\": "
      "%zu}\n",
      total, totalCpu, report.faces, bunny.n_faces(), options.distance.threads, d.hausdorffPct,
      d.hausdorffUpperBoundPct, d.hausdorffCertified ? "true" : "false", d.meanPct, d.rmsPct,
      d.samples);

  std::printf("\n%-28s %10s %10s\n", "step (median of runs)", "wall s", "cpu s");
  for (const auto& step : steps)
    std::printf("%-28s %10.4f %10.4f\n", step.name.c_str(), median(step.wall), median(step.cpu));
  std::printf("%-28s %10.4f\n", "  metrics: distance", median(distance));
  std::printf("%-28s %10.4f\n", "  metrics: shape + topology", median(shape));
  std::printf("%-28s %10.4f %10.4f\n", "total", total, totalCpu);
  std::printf(
      "\nHausdorff %.4f%% (bound %.4f%%, %s), mean %.4f%%, RMS %.4f%% of the diagonal; "
      "%zu distance queries\n",
      d.hausdorffPct, d.hausdorffUpperBoundPct,
      d.hausdorffCertified ? "certified" : "not certified", d.meanPct, d.rmsPct, d.samples);
  return 0;
}
