// The `hexcover info`, `hexcover convert`, `hexcover field`, `hexcover param` and (quads)
// `hexcover remesh` commands, run as the built binary (HEXCOVER_CLI).

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "core/mesh/io.h"
#include "core/mesh/primitives.h"

namespace hexcover {
namespace {

struct CommandResult {
  int status = -1;
  std::string out;
  std::string err;
};

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("hexcover_cli_" + std::string(info->name()) + "_" +
            std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  static std::string slurp(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  // Runs `hexcover <arguments>` with stdout and stderr captured in files.
  CommandResult hexcover(const std::string& arguments) const {
    const auto out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string command = std::string("'") + HEXCOVER_CLI + "' " + arguments + " >'" +
                                out.string() + "' 2>'" + err.string() + "'";
    const int raw = std::system(command.c_str());
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(out), slurp(err)};
  }

  std::filesystem::path dir_;
};

TEST_F(CliTest, InfoPrintsTheReportOfAGeneratedMeshAsOneJsonObject) {
  const auto path = dir_ / "torus.obj";
  writeMesh(toPolygonSoup(makeTorus(3, 1, 24, 12)), path);
  const CommandResult run = hexcover("info '" + path.string() + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  const nlohmann::json report = nlohmann::json::parse(run.out);
  ASSERT_TRUE(report.is_object());
  EXPECT_EQ(report["input"]["vertices"], 24 * 12);
  EXPECT_EQ(report["input"]["faces"], 2 * 24 * 12);
  EXPECT_EQ(report["repaired"], true);
  EXPECT_EQ(report["repairs"]["dropped_faces"], 0);
  EXPECT_EQ(report["result"]["euler_characteristic"], 0);
  EXPECT_EQ(report["result"]["component_topology"][0]["genus"], 1);
  EXPECT_EQ(report["result"]["non_manifold_edges"], 0);
}

TEST_F(CliTest, InfoReportsRepairsOfADefectiveMesh) {
  // A unit square stored as two triangles with separate corners and one duplicate.
  const auto path = dir_ / "square.obj";
  std::ofstream(path)
      << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 4 5 6\nf 3 1 2\n";
  const CommandResult run = hexcover("info '" + path.string() + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(run.out);
  EXPECT_EQ(report["input"]["duplicate_vertices"], 2);
  EXPECT_EQ(report["input"]["duplicate_faces"], 1);
  EXPECT_EQ(report["repairs"]["welded_vertices"], 2);
  EXPECT_EQ(report["repairs"]["dropped_duplicate_faces"], 1);
  EXPECT_EQ(report["result"]["faces"], 2);
  EXPECT_EQ(report["result"]["boundary_loops"], 1);
}

TEST_F(CliTest, InfoOnABrokenFileExitsWithStatusOneAndOneLine) {
  const auto garbage = dir_ / "garbage.obj";
  std::ofstream(garbage) << "this is not a mesh\n";
  const CommandResult unknown = hexcover("info '" + garbage.string() + "'");
  EXPECT_EQ(unknown.status, 1);
  EXPECT_TRUE(unknown.out.empty());
  EXPECT_NE(unknown.err.find("unknown mesh format"), std::string::npos) << unknown.err;
  EXPECT_EQ(std::count(unknown.err.begin(), unknown.err.end(), '\n'), 1) << unknown.err;

  const auto outOfRange = dir_ / "range.off";
  std::ofstream(outOfRange) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
  const CommandResult range = hexcover("info '" + outOfRange.string() + "'");
  EXPECT_EQ(range.status, 1);
  EXPECT_NE(range.err.find("line 6"), std::string::npos) << range.err;

  const CommandResult missing = hexcover("info '" + (dir_ / "missing.ply").string() + "'");
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("cannot open"), std::string::npos) << missing.err;

  EXPECT_EQ(hexcover("info").status, 2);  // usage
}

// `hexcover <command> --help` (or -h) prints that command's usage to stdout and succeeds,
// whatever else is on the line (it was an unknown option: status 2).
TEST_F(CliTest, EveryCommandPrintsItsUsageForHelp) {
  for (const std::string command : {"info", "convert", "metrics", "remesh", "field", "param"}) {
    for (const std::string help : {"--help", "-h"}) {
      const CommandResult run = hexcover(command + " " + help);
      EXPECT_EQ(run.status, 0) << command << " " << help << ": " << run.err;
      EXPECT_EQ(run.out.rfind("usage: hexcover " + command, 0), 0u) << run.out;
      EXPECT_TRUE(run.err.empty()) << run.err;
    }
  }
  const CommandResult late = hexcover("remesh in.obj -o out.obj --help");
  EXPECT_EQ(late.status, 0) << late.err;
  EXPECT_NE(late.out.find("--vertices K"), std::string::npos) << late.out;
}

TEST_F(CliTest, ConvertWritesTheFormatOfTheOutputExtension) {
  const auto obj = dir_ / "sphere.obj", ply = dir_ / "sphere.ply", stl = dir_ / "sphere.stl";
  const PolygonSoup sphere = toPolygonSoup(makeIcosphere(2));
  writeMesh(sphere, obj);
  ASSERT_EQ(hexcover("convert '" + obj.string() + "' '" + ply.string() + "'").status, 0);
  EXPECT_EQ(detectFormat(slurp(ply)), MeshFormat::Ply);
  const PolygonSoup back = readMesh(ply);
  EXPECT_EQ(back.positions, sphere.positions);
  EXPECT_EQ(back.cornerVertices, sphere.cornerVertices);
  ASSERT_EQ(hexcover("convert '" + ply.string() + "' '" + stl.string() + "'").status, 0);
  EXPECT_EQ(readMesh(stl).faceCount(), sphere.faceCount());
  const CommandResult bad =
      hexcover("convert '" + obj.string() + "' '" + (dir_ / "x.fbx").string() + "'");
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find(".fbx"), std::string::npos) << bad.err;
}

TEST_F(CliTest, FieldPrintsSingularitiesWhoseIndicesSumToTheEulerCharacteristic) {
  const auto path = dir_ / "sphere.obj", ply = dir_ / "field.ply";
  const TriMesh sphere = makeIcosphere(3);
  writeMesh(toPolygonSoup(sphere), path);
  for (const int rosy : {6, 4}) {
    const CommandResult run = hexcover("field '" + path.string() + "' --rosy " +
                                       std::to_string(rosy) + " -o '" + ply.string() + "'");
    ASSERT_EQ(run.status, 0) << run.err;
    const nlohmann::json json = nlohmann::json::parse(run.out);
    EXPECT_EQ(json["euler_characteristic"], 2);
    EXPECT_EQ(json["max_merged_index"], 0) << "the paper's clustering";
    EXPECT_GT(json["seconds"].get<double>(), 0.0);
    EXPECT_GE(json["singularities_initial"].get<int>(), json["singularities_final"].get<int>());
    ASSERT_EQ(json["singularities"].size(), json["singularities_final"].get<std::size_t>());
    double sum = 0.0;
    for (const auto& s : json["singularities"]) {
      EXPECT_LT(s["vertex"].get<int>(), static_cast<int>(sphere.n_vertices()));
      ASSERT_EQ(s["position"].size(), 3u);
      sum += s["index"].get<double>();  // signed fractions such as 0.1667
    }
    EXPECT_NEAR(sum, 2.0, 1e-3) << "N = " << rosy;
    // The viewer file: the mesh plus a thin quad per field direction in every face.
    const PolygonSoup viewer = readMesh(ply);
    EXPECT_GE(viewer.faceCount(), sphere.n_faces() * (1 + rosy)) << "N = " << rosy;
  }
  const CommandResult limited = hexcover("field '" + path.string() + "' --max-merged-index 1");
  ASSERT_EQ(limited.status, 0) << limited.err;
  EXPECT_EQ(nlohmann::json::parse(limited.out)["max_merged_index"], 1);
  const CommandResult refused = hexcover("field '" + path.string() + "' --max-merged-index -1");
  EXPECT_EQ(refused.status, 2) << "a usage error";
  EXPECT_NE(refused.err.find("--max-merged-index"), std::string::npos) << refused.err;
}

TEST_F(CliTest, RemeshWithRosyFourWritesQuadsAndRefusesAHexagonalDual) {
  const auto path = dir_ / "sphere.obj", out = dir_ / "quads.obj", metrics = dir_ / "m.json";
  writeMesh(toPolygonSoup(makeIcosphere(4)), path);
  const CommandResult run =
      hexcover("remesh '" + path.string() + "' -o '" + out.string() +
               "' --rosy 4 --vertices 600 --quiet --metrics '" + metrics.string() + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const PolygonSoup quads = readMesh(out);
  ASSERT_GT(quads.faceCount(), 0u);
  for (std::size_t f = 0; f < quads.faceCount(); ++f) ASSERT_EQ(quads.faceSize(f), 4u);
  const nlohmann::json json = nlohmann::json::parse(slurp(metrics));
  EXPECT_EQ(json["quads"].get<std::size_t>(), quads.faceCount());
  EXPECT_EQ(json["irregular_interior"], 8) << "the sphere's eight +1/4 cones";
  EXPECT_GT(json["extraction"]["lattice_squares"].get<long long>(), 0);
  const CommandResult hex = hexcover("remesh '" + path.string() + "' -o '" + out.string() +
                                     "' --rosy 4 --hex '" + (dir_ / "hex.obj").string() + "'");
  EXPECT_EQ(hex.status, 2) << "a usage error";
  EXPECT_NE(hex.err.find("--hex"), std::string::npos) << hex.err;
}

TEST_F(CliTest, RemeshTakesTheSingularityDistanceItIsGiven) {
  const auto path = dir_ / "sphere.obj", out = dir_ / "remesh.obj", metrics = dir_ / "m.json";
  writeMesh(toPolygonSoup(makeIcosphere(4)), path);
  const std::string run = "remesh '" + path.string() + "' -o '" + out.string() +
                          "' --vertices 600 --quiet --metrics '" + metrics.string() + "'";
  ASSERT_EQ(hexcover(run).status, 0);
  const double byDefault =
      nlohmann::json::parse(slurp(metrics))["singularity_distance"].get<double>();
  const CommandResult given = hexcover(run + " --d-sing 0.125");
  ASSERT_EQ(given.status, 0) << given.err;
  const nlohmann::json json = nlohmann::json::parse(slurp(metrics));
  EXPECT_DOUBLE_EQ(json["singularity_distance"].get<double>(), 0.125);
  EXPECT_GT(byDefault, 2.0 * 0.125) << "6 h by default";
  int indexSum = 0;  // in units of 1/6
  for (const auto& s : json["singularities"]) indexSum += s["index"].get<int>();
  EXPECT_EQ(indexSum, 6 * 2) << "Poincaré–Hopf on the sphere";

  const CommandResult refused = hexcover(run + " --d-sing -1");
  EXPECT_EQ(refused.status, 2) << "a usage error";
  EXPECT_NE(refused.err.find("--d-sing"), std::string::npos) << refused.err;
}

TEST_F(CliTest, ParamClustersSingularitiesAtSixEdgeLengthsUnlessToldOtherwise) {
  const auto path = dir_ / "torus.obj", textured = dir_ / "textured.obj";
  writeMesh(toPolygonSoup(makeTorus(3, 1, 48, 16)), path);
  const CommandResult byDefault =
      hexcover("param '" + path.string() + "' -o '" + textured.string() + "' --edge-length 0.5");
  ASSERT_EQ(byDefault.status, 0) << byDefault.err;
  const nlohmann::json json = nlohmann::json::parse(byDefault.out);
  EXPECT_DOUBLE_EQ(json["singularity_distance"].get<double>(), 6.0 * 0.5) << "as the pipeline";
  EXPECT_EQ(json["flipped"], 0);

  const CommandResult given = hexcover("param '" + path.string() + "' -o '" + textured.string() +
                                       "' --edge-length 0.5 --d-sing 1.25");
  ASSERT_EQ(given.status, 0) << given.err;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(given.out)["singularity_distance"].get<double>(), 1.25);

  const CommandResult refused =
      hexcover("param '" + path.string() + "' -o '" + textured.string() + "' --d-sing -1");
  EXPECT_EQ(refused.status, 2) << "a usage error";
  EXPECT_NE(refused.err.find("--d-sing"), std::string::npos) << refused.err;
}

// A cylinder as CAD exporters write it (caps as fans of slivers, sides as full-height strips)
// has no room for the lattice: as in the remesh pipeline, `param` splits its long edges first,
// and its caps' +6/6 become first-order singularities. Before, the parameterization had 2
// singularities of +6/6 and 38 flipped triangles; the textured mesh is now the refined one.
TEST_F(CliTest, ParamRefinesAnInputMuchCoarserThanTheLattice) {
  const auto path = dir_ / "cylinder.obj", textured = dir_ / "textured.obj";
  const TriMesh cylinder = makeCappedCylinder(1.0, 2.0, 64);
  writeMesh(toPolygonSoup(cylinder), path);
  const CommandResult result =
      hexcover("param '" + path.string() + "' -o '" + textured.string() + "' --vertices 1000");
  ASSERT_EQ(result.status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(result.out);
  EXPECT_GT(json["input_edges_split"].get<long long>(), 0);
  EXPECT_EQ(json["flipped"], 0);
  EXPECT_EQ(json["degenerate"], 0);
  EXPECT_EQ(json["singularities"], 12);
  for (const auto& singularity : json["singularity_coords"])
    EXPECT_EQ(singularity["index_numerator"], 1);
  EXPECT_GT(readMesh(textured).vertexCount(), cylinder.n_vertices());
}

// An L-bracket's creases meet at 90°, which no hexagonal lattice follows at once: as the remesh
// pipeline does, `param` also parameterizes along the field that follows only the compatible
// creases, and keeps it for its lower angle distortion (3.3° with every crease).
TEST_F(CliTest, ParamFollowsTheCreasesALatticeCanFollowWhenThatDistortsLess) {
  const auto path = dir_ / "bracket.obj", textured = dir_ / "textured.obj";
  writeMesh(toPolygonSoup(makeLBracket(2.0, 0.5, 0.4)), path);
  const CommandResult result =
      hexcover("param '" + path.string() + "' -o '" + textured.string() + "' --vertices 1000");
  ASSERT_EQ(result.status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(result.out);
  EXPECT_EQ(json["creases"], "compatible");
  EXPECT_EQ(json["flipped"], 0);
  EXPECT_LT(json["distortion"]["angle_mean_deg"].get<double>(), 2.5);
}

}  // namespace
}  // namespace hexcover
