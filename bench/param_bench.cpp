// Benchmark of the HexCover parameterization (core/param): per-step times (median of 5 runs),
// peak memory, CHOLMOD vs Eigen SimplicialLDLT, and greedy vs direct rounding (energy, flipped
// triangles, time) on generated meshes with prescribed fields and on every clean/ mesh with the
// field of core/field.
//
// Prints one JSON line per run configuration ("param_bench {...}") and a table for people.
// Usage: bench_param [--runs R] [--only SUBSTRING]

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "core/common/memory.h"
#include "core/field/rosy_field.h"
#include "core/mesh/load.h"
#include "core/mesh/primitives.h"
#include "core/param/hexcover.h"
#include "tests/common/prescribed_fields.h"

namespace {

using namespace hexcover;
using test::icosahedralField;

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

struct Summary {
  std::map<std::string, double> stepMedian;  // step -> median seconds
  double totalMedian = 0.0;
  double cpuMedian = 0.0;  // process CPU seconds: less sensitive to other load on the machine
  Parameterization last;
};

Summary run(const TriMesh& mesh, const RosyField& field, const ParamOptions& options, int runs) {
  Summary summary;
  std::map<std::string, std::vector<double>> steps;
  std::vector<double> totals, cpu;
  for (int r = 0; r < runs; ++r) {
    const std::clock_t start = std::clock();
    summary.last = computeParameterization(mesh, field, options);
    cpu.push_back(static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC);
    for (const auto& t : summary.last.timings) steps[t.step].push_back(t.seconds);
    totals.push_back(totalSeconds(summary.last.timings));
  }
  for (auto& [step, values] : steps) summary.stepMedian[step] = median(values);
  summary.totalMedian = median(totals);
  summary.cpuMedian = median(cpu);
  return summary;
}

const char* solverName(LinearSolver s) {
  return s == LinearSolver::Cholmod ? "cholmod" : "simplicial_ldlt";
}

void report(const std::string& name, const TriMesh& mesh, const char* rounding, LinearSolver solver,
            const Summary& s) {
  std::printf("param_bench {\"mesh\":\"%s\",\"faces\":%zu,\"rounding\":\"%s\",\"solver\":\"%s\","
              "\"seconds_median\":%.4f,\"cpu_seconds_median\":%.4f,\"flipped\":%d,\"flipped_before_stiffening\":%d,"
              "\"degenerate\":%d,\"energy\":%.6g,\"local_energy\":%.6g,\"singularities\":%zu,"
              "\"integer_variables\":%d,\"stiffening_iterations\":%d,\"peak_memory_mib\":%.1f,"
              "\"steps\":{",
              name.c_str(), mesh.n_faces(), rounding, solverName(solver), s.totalMedian, s.cpuMedian,
              s.last.flippedTriangles, s.last.flippedBeforeStiffening, s.last.degenerateTriangles,
              s.last.energy, s.last.localEnergy, s.last.singularities.size(),
              s.last.integerVariables, s.last.stiffeningIterations, peakMemoryMiB());
  bool first = true;
  for (const auto& [step, seconds] : s.stepMedian) {
    std::printf("%s\"%s\":%.4f", first ? "" : ",", step.c_str(), seconds);
    first = false;
  }
  std::printf("}}\n");
  std::fflush(stdout);
}

struct Row {
  std::string name;
  std::size_t faces = 0;
  double seconds = 0.0, cpu = 0.0, ldlt = 0.0, direct = 0.0;  // default: greedy, CHOLMOD
  int flippedGreedy = 0, flippedDirect = 0, flippedPlain = 0;
  double energyGreedy = 0.0, energyDirect = 0.0, energyPlain = 0.0, localEnergy = 0.0;
  double memory = 0.0;
};

// The default (greedy rounding, lattice descent, CHOLMOD), the same with Eigen's SimplicialLDLT,
// direct rounding (§4.4) with the descent, and direct rounding alone.
Row benchmark(const std::string& name, const TriMesh& mesh, const RosyField& field, int runs) {
  Row row;
  row.name = name;
  row.faces = mesh.n_faces();
  ParamOptions options;
  const Summary greedy = run(mesh, field, options, runs);
  report(name, mesh, "greedy", options.solver, greedy);
  options.solver = LinearSolver::SimplicialLDLT;
  const Summary ldlt = run(mesh, field, options, runs);
  report(name, mesh, "greedy", options.solver, ldlt);
  options.solver = LinearSolver::Cholmod;
  options.rounding = RoundingMethod::Direct;
  const Summary direct = run(mesh, field, options, runs);
  report(name, mesh, "direct+descent", options.solver, direct);
  options.latticeDescent = false;
  const Summary plain = run(mesh, field, options, 1);
  report(name, mesh, "direct", options.solver, plain);
  row.seconds = greedy.totalMedian;
  row.cpu = greedy.cpuMedian;
  row.ldlt = ldlt.totalMedian;
  row.direct = direct.totalMedian;
  row.flippedGreedy = greedy.last.flippedTriangles;
  row.flippedDirect = direct.last.flippedTriangles;
  row.flippedPlain = plain.last.flippedTriangles;
  row.energyGreedy = greedy.last.energy;
  row.energyDirect = direct.last.energy;
  row.energyPlain = plain.last.energy;
  row.localEnergy = greedy.last.localEnergy;
  row.memory = peakMemoryMiB();
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5;
  std::string only;
  for (int i = 1; i < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--runs" && i + 1 < argc) {
      runs = std::max(1, std::atoi(argv[i + 1]));
    } else if (flag == "--only" && i + 1 < argc) {
      only = argv[i + 1];
    } else {
      std::fprintf(stderr, "usage: bench_param [--runs R] [--only SUBSTRING]\n");
      return 2;
    }
  }
  std::vector<Row> rows;
  const auto wanted = [&](const std::string& name) {
    return only.empty() || name.find(only) != std::string::npos;
  };
  try {
    if (wanted("generated/icosphere6")) {
      const TriMesh mesh = makeIcosphere(6);
      rows.push_back(benchmark("generated/icosphere6", mesh, icosahedralField(mesh), runs));
    }
    const std::filesystem::path clean = std::filesystem::path(HEXCOVER_SHARED_MESHES) / "clean";
    if (std::filesystem::exists(clean)) {
      std::vector<std::filesystem::path> files;
      for (const auto& entry : std::filesystem::directory_iterator(clean)) files.push_back(entry.path());
      std::sort(files.begin(), files.end());
      for (const auto& file : files) {
        const std::string name = "clean/" + file.filename().string();
        if (!wanted(name)) continue;
        const TriMesh mesh = loadMesh(file);
        FieldOptions fieldOptions;
        fieldOptions.maxMergedIndex = kMergedIndexForLattice;
        const RosyField field = computeRosyField(mesh, fieldOptions);
        rows.push_back(benchmark(name, mesh, field, runs));
      }
    } else {
      std::cerr << "bench_param: no shared meshes at " << clean << ", generated meshes only\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_param: " << e.what() << "\n";
    return 1;
  }

  std::printf("\n%-34s %7s %8s %8s %8s %8s %5s %5s %5s %9s %9s %9s %9s %7s\n", "mesh", "faces",
              "wall s", "cpu s", "ldlt s", "direct s", "flipG", "flipD", "flipP", "E greedy",
              "E direct", "E plain", "E local", "MiB");
  for (const auto& r : rows)
    std::printf("%-34s %7zu %8.3f %8.3f %8.3f %8.3f %5d %5d %5d %9.4g %9.4g %9.4g %9.4g %7.1f\n",
                r.name.c_str(), r.faces, r.seconds, r.cpu, r.ldlt, r.direct, r.flippedGreedy,
                r.flippedDirect, r.flippedPlain, r.energyGreedy, r.energyDirect, r.energyPlain,
                r.localEnergy, r.memory);
  std::printf("(medians of the runs; default = greedy rounding + lattice descent on CHOLMOD; ldlt: "
              "the same on Eigen's SimplicialLDLT; direct: direct rounding + descent; plain: direct "
              "rounding alone, one run; E: energy in area/h^2, flip: flipped triangles left)\n");
  return 0;
}
