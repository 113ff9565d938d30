// `hexcover metrics`: runs the real binary on generated files and checks the JSON and exit codes.

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/mesh/io.h"
#include "core/mesh/primitives.h"

namespace hexcover {
namespace {

struct CliRun {
  int status;
  std::string out;
};

CliRun runCli(const std::string& arguments) {
  const std::string command = std::string(HEXCOVER_CLI) + " " + arguments + " 2>/dev/null";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  std::string out;
  std::array<char, 4096> buffer;
  while (const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe.get()))
    out.append(buffer.data(), n);
  const int status = pclose(pipe.release());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

class MetricsCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("hexcover_metrics_cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    sphere_ = dir_ / "sphere.off";
    larger_ = dir_ / "larger.obj";
    const TriMesh sphere = makeIcosphere(3);
    TriMesh larger = sphere;
    for (const auto vh : larger.vertices()) larger.set_point(vh, 1.01 * larger.point(vh));
    writeMesh(toPolygonSoup(sphere), sphere_);
    writeMesh(toPolygonSoup(larger), larger_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path dir_, sphere_, larger_;
};

TEST_F(MetricsCommand, PrintsTheReportWithDistancesToTheReference) {
  const CliRun r = runCli("metrics " + larger_.string() + " --reference " + sphere_.string());
  ASSERT_EQ(r.status, 0);
  const auto json = nlohmann::json::parse(r.out);
  const double expected = 100.0 * 0.01 / json["reference_diagonal"].get<double>();  // radius 1
  EXPECT_NEAR(json["hausdorff_pct"].get<double>(), expected, 0.01 * expected);
  EXPECT_EQ(json["faces"], 1280);
  EXPECT_EQ(json["euler_characteristic"], 2);
  EXPECT_EQ(json["irregular_interior"], 12);
  EXPECT_EQ(json["topology_matches_reference"], true);
}

TEST_F(MetricsCommand, WithoutReferenceDistancesAreNull) {
  const CliRun r = runCli("metrics " + sphere_.string());
  ASSERT_EQ(r.status, 0);
  const auto json = nlohmann::json::parse(r.out);
  EXPECT_TRUE(json["hausdorff_pct"].is_null());
  EXPECT_TRUE(json["mean_dist_pct"].is_null());
  EXPECT_TRUE(json["topology_matches_reference"].is_null());
  EXPECT_EQ(json["manifold"], true);
}

TEST_F(MetricsCommand, ExitCodesSeparateBadInputFromBadUsage) {
  EXPECT_EQ(runCli("metrics").status, 2);
  EXPECT_EQ(runCli("metrics " + sphere_.string() + " --bogus").status, 2);
  EXPECT_EQ(runCli("metrics " + (dir_ / "missing.obj").string()).status, 1);
  const auto garbage = dir_ / "garbage.obj";
  {
    std::FILE* f = std::fopen(garbage.c_str(), "w");
    std::fputs("f 1 2 9\n", f);
    std::fclose(f);
  }
  EXPECT_EQ(runCli("metrics " + sphere_.string() + " --reference " + garbage.string()).status, 1);
}

}  // namespace
}  // namespace hexcover
