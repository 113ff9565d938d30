// bench_remesh: the whole pipeline on every clean/ mesh at two resolutions (K = V/4 and K = V).
// Prints one machine-readable line per run ("remesh mesh=... K=... key=value ...") and a markdown
// table: output size, each stage's median time over the runs, peak memory and the metrics.
// Usage: bench_remesh [--runs N] [--only NAME] [--quarter-only] [--subdivide S] [--generated]
//                     [--rosy 6|4]
// --subdivide S splits every triangle of the input 1-to-4 S times first (the 1M-face case:
// --only stanford-bunny --subdivide 2 --quarter-only --runs 1, 1.1M faces). --generated remeshes
// shapes tessellated as CAD exporters write them instead (core/mesh/primitives.h: a cylinder with
// fans of slivers for caps, a latitude-longitude sphere, a box of 12 triangles, an L-bracket and
// a plate with a hole, their faces fanned; and two spheres refined towards one pole, one smooth
// and one bumpy, makeGradedSphere; and 60 separate spheres of radii 0.2 to 1) at K = 300 and
// 3000. --rosy 4 remeshes into quads (the angles are then the quads' corners, the irregular
// vertices those of valence other than 4). The "repair s" column includes the refinement before
// the field. The peak memory is the process's over a row's runs (VmHWM reset before each row,
// after the previous rows' freed memory went back to the kernel): it includes the loaded inputs
// and what the libraries keep (a small mesh after the large ones: about 200 MiB).
// Never asserts on time.

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/common/memory.h"
#include "core/mesh/io.h"
#include "core/mesh/primitives.h"
#include "core/pipeline/pipeline.h"

namespace {

using namespace hexcover;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct Row {
  std::string mesh;
  long long inputVertices = 0, target = 0;
  RemeshResult last;
  std::map<std::string, std::vector<double>> stageSeconds;
  std::vector<double> totalSeconds;
  double peakMiB = 0.0;
  std::string error;
};

const char* const kStages[] = {"repair", "field", "parameterization", "extraction", "metrics"};

/// The input and the targets of one table row group.
struct Input {
  std::string name;
  PolygonSoup soup;
  std::vector<long long> targets;
};

/// Vertices of the soup that a face uses (unreferenced ones do not count).
long long referencedVertices(const PolygonSoup& soup) {
  std::vector<bool> used(soup.vertexCount(), false);
  for (const auto v : soup.cornerVertices) used[v] = true;
  return std::count(used.begin(), used.end(), true);
}

/// Splits every triangle 1-to-4 at its edge midpoints (shared midpoints, so the surface stays
/// connected); faces with more corners are kept as they are.
PolygonSoup subdivided(const PolygonSoup& soup) {
  PolygonSoup out;
  out.positions = soup.positions;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
  const auto middle = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::minmax(a, b);
    const auto [it, inserted] = midpoint.try_emplace({key.first, key.second}, 0);
    if (inserted) {
      it->second = static_cast<std::uint32_t>(out.positions.size());
      out.positions.push_back(0.5 * (soup.positions[a] + soup.positions[b]));
    }
    return it->second;
  };
  for (std::size_t f = 0; f < soup.faceCount(); ++f) {
    const std::uint32_t* c = &soup.cornerVertices[soup.faceStarts[f]];
    if (soup.faceSize(f) != 3) {
      out.addFace(std::vector<std::uint32_t>(c, c + soup.faceSize(f)));
      continue;
    }
    const std::uint32_t ab = middle(c[0], c[1]), bc = middle(c[1], c[2]), ca = middle(c[2], c[0]);
    out.addFace(std::array<std::uint32_t, 3>{c[0], ab, ca});
    out.addFace(std::array<std::uint32_t, 3>{ab, c[1], bc});
    out.addFace(std::array<std::uint32_t, 3>{ca, bc, c[2]});
    out.addFace(std::array<std::uint32_t, 3>{ab, bc, ca});
  }
  return out;
}

/// 60 icospheres of 642 vertices on a 4 × 4 × 4 grid 3 apart, their radii spread over [0.2, 1]:
/// separate parts of many sizes, where a coarse lattice folds on the small ones.
PolygonSoup separateSpheres() {
  constexpr int kSpheres = 60;
  PolygonSoup soup;
  for (int k = 0; k < kSpheres; ++k) {
    const double radius = 0.2 + 0.8 * ((k * 37) % kSpheres) / (kSpheres - 1.0);
    const Eigen::Vector3d centre(3.0 * (k % 4), 3.0 * (k / 4 % 4), 3.0 * (k / 16));
    appendToPolygonSoup(soup, makeIcosphere(3, radius), centre);
  }
  return soup;
}

}  // namespace

int main(int argc, char** argv) {
  hexcover::keepFreedMemoryForReuse();  // as the command line and the server do
  int runs = 5;
  std::string only;
  bool quarterOnly = false, generated = false;
  int subdivisions = 0, rosy = 6;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else if (!std::strcmp(argv[i], "--quarter-only")) quarterOnly = true;
    else if (!std::strcmp(argv[i], "--subdivide") && i + 1 < argc)
      subdivisions = std::max(0, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--generated"))
      generated = true;
    else if (!std::strcmp(argv[i], "--rosy") && i + 1 < argc &&
             (!std::strcmp(argv[i + 1], "4") || !std::strcmp(argv[i + 1], "6")))
      rosy = std::atoi(argv[++i]);
    else {
      std::cerr << "usage: bench_remesh [--runs N] [--only NAME] [--quarter-only] [--subdivide S] "
                   "[--generated] [--rosy 6|4]\n";
      return 2;
    }
  }
  std::vector<Input> inputs;
  if (generated) {
    inputs.push_back({"cylinder, 64 sides", toPolygonSoup(makeCappedCylinder(1.0, 2.0, 64)), {}});
    inputs.push_back(
        {"latitude-longitude sphere 32x16", toPolygonSoup(makeUvSphere(1.0, 32, 16)), {}});
    inputs.push_back({"box of 12 triangles", toPolygonSoup(makeBox(1.0, 0.8, 0.6, 1)), {}});
    inputs.push_back({"L-bracket", toPolygonSoup(makeLBracket(2.0, 0.5, 0.4)), {}});
    inputs.push_back(
        {"plate with a hole", toPolygonSoup(makePlateWithHole(2.0, 0.5, 0.2, 48)), {}});
    inputs.push_back(
        {"sphere refined towards a pole 120x80", toPolygonSoup(makeGradedSphere(120, 80)), {}});
    inputs.push_back({"bumpy sphere refined towards a pole 120x80",
                      toPolygonSoup(makeGradedSphere(120, 80, 0.1)),
                      {}});
    inputs.push_back({"60 spheres of radii 0.2-1", separateSpheres(), {}});
    for (auto& input : inputs) input.targets = {300, 3000};
  } else {
    const std::filesystem::path dir = std::filesystem::path(HEXCOVER_SHARED_MESHES) / "clean";
    if (!std::filesystem::is_directory(dir)) {
      std::cerr << "bench_remesh: no meshes at " << dir << "\n";
      return 1;
    }
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      if (entry.is_regular_file() &&
          (only.empty() || entry.path().filename().string().find(only) != std::string::npos))
        files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      Input input;
      try {
        input.soup = readMesh(file);
        for (int k = 0; k < subdivisions; ++k) input.soup = subdivided(input.soup);
      } catch (const Error& e) {
        std::cerr << file << ": " << e.what() << "\n";
        continue;
      }
      input.name = file.filename().string() +
                   (subdivisions > 0 ? " (subdivided " + std::to_string(subdivisions) + "x, " +
                                           std::to_string(input.soup.faceCount()) + " faces)"
                                     : std::string());
      const long long vertices = referencedVertices(input.soup);
      input.targets = {vertices / 4};
      if (!quarterOnly) input.targets.push_back(vertices);
      inputs.push_back(std::move(input));
    }
  }

  std::vector<Row> rows;
  for (const Input& input : inputs) {
    const PolygonSoup& soup = input.soup;
    for (const long long target : input.targets) {
      Row row;
      row.mesh = input.name;
      row.inputVertices = referencedVertices(soup);
      row.target = target;
      RemeshOptions options;
      options.targetVertices = target;
      options.rosy = rosy;
      // Each row's peak: the memory the previous rows freed goes back to the kernel first.
      releaseFreedMemory();
      resetPeakMemory();
      try {
        for (int r = 0; r < runs; ++r) {
          row.last = remesh(soup, options);
          for (const char* stage : kStages) {
            double seconds = 0.0;
            for (const auto& t : row.last.timings)
              if (t.step == stage || (t.step == "refinement" && std::strcmp(stage, "repair") == 0))
                seconds += t.seconds;
            row.stageSeconds[stage].push_back(seconds);
          }
          row.totalSeconds.push_back(totalSeconds(row.last.timings));
          row.peakMiB = std::max(row.peakMiB, row.last.peakMemoryMiB);
        }
      } catch (const Error& e) {
        row.error = e.what();
      }
      const QualityReport& m = row.last.metrics;
      std::ostringstream line;
      line << "remesh mesh=" << row.mesh << " K=" << target;
      if (!row.error.empty()) {
        line << " error=\"" << row.error << "\"";
      } else {
        line << " V=" << m.vertices << " F=" << m.faces << " total_s=" << median(row.totalSeconds);
        for (const char* stage : kStages) line << " " << stage << "_s=" << median(row.stageSeconds[stage]);
        line << " peak_mib=" << row.peakMiB << " hausdorff_pct="
             << (m.distance ? m.distance->hausdorffPct : -1.0) << " angle_min=" << m.angleMin
             << " angle_max=" << m.angleMax << " angle_sd=" << m.angleSd
             << " irregular_interior=" << m.irregularInterior
             << " singularities=" << row.last.singularities.size()
             << " topology_ok=" << (m.topologyMatchesReference.value_or(false) ? 1 : 0);
      }
      std::cout << line.str() << std::endl;
      rows.push_back(std::move(row));
    }
  }

  std::printf("\n| mesh | K | V out | F out | repair s | field s | param s | extract s | metrics s | "
              "total s | peak MiB | Hausdorff %% | min° | max° | SD° | irregular (%%) | sing. | topology |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& row : rows) {
    if (!row.error.empty()) {
      std::printf("| %s | %lld | error: %s |\n", row.mesh.c_str(), row.target, row.error.c_str());
      continue;
    }
    const QualityReport& m = row.last.metrics;
    std::printf("| %s | %lld | %d | %d | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.0f | %.3f | %.1f | "
                "%.1f | %.2f | %d (%.2f) | %zu | %s |\n",
                row.mesh.c_str(), row.target, m.vertices, m.faces, median(row.stageSeconds.at("repair")),
                median(row.stageSeconds.at("field")), median(row.stageSeconds.at("parameterization")),
                median(row.stageSeconds.at("extraction")), median(row.stageSeconds.at("metrics")),
                median(row.totalSeconds), row.peakMiB, m.distance ? m.distance->hausdorffPct : -1.0,
                m.angleMin, m.angleMax, m.angleSd, m.irregularInterior,
                m.vertices ? 100.0 * m.irregularInterior / m.vertices : 0.0,
                row.last.singularities.size(),
                m.topologyMatchesReference.value_or(false) ? "same" : "differs");
  }
  std::printf("\nmedians of %d runs; times in seconds on this machine.\n", runs);
  return 0;
}
