// End to end against the real hexcover-server: every input format, raw and multipart, remeshed;
// every result format downloaded, parsed and compared with the metrics document.

#include <gtest/gtest.h>

#include "tests/common/test_meshes.h"
#include "tests/server/e2e_helpers.h"
#include "tests/server/in_process_server.h"
#include "tests/server/server_process.h"

namespace hexcover::server::test {
namespace {

struct Input {
  std::string name;
  std::string format;
  std::string bytes;
};

void remeshAllAndCheck(const std::vector<Input>& inputs) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--workers", "2"});
  ASSERT_TRUE(server.started()) << server.log();
  auto client = server.client();

  std::vector<std::pair<std::string, std::string>> jobs;  // (what, location)
  for (const auto& input : inputs)
    for (const bool multipart : {false, true}) {
      const auto res = upload(client, input.bytes, multipart, input.name);
      ASSERT_TRUE(res);
      ASSERT_EQ(res->status, 202) << input.name << ": " << res->body;
      EXPECT_EQ(nlohmann::json::parse(res->body).at("input").at("format"), input.format);
      jobs.emplace_back(input.name + (multipart ? " (multipart)" : " (raw)"),
                        res->get_header_value("Location"));
    }
  for (const auto& [what, location] : jobs) {
    SCOPED_TRACE(what);
    const auto job = waitForJob(client, location, std::chrono::seconds(120));
    ASSERT_EQ(job.value("state", ""), "succeeded") << job.dump();
    expectResultsAgreeWithMetrics(client, job, dir.path());
  }
}

TEST(EndToEnd, GeneratedIcosphereInEveryFormatRawAndMultipartRemeshesWithParsableResults) {
  HEXCOVER_SERVER_OR_SKIP();
  TempDir meshes;
  std::vector<Input> inputs;
  for (const std::string format : {"obj", "off", "ply", "stl"}) {
    const auto path = writeIcosphere(meshes.path(), "icosphere." + format, 3);
    inputs.push_back({path.filename().string(), format, readFile(path)});
  }
  remeshAllAndCheck(inputs);
}

TEST(EndToEnd, QuadJobOffersTheQuadRemeshInEveryFormatAndNoHexagons) {
  HEXCOVER_SERVER_OR_SKIP();
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  ASSERT_TRUE(server.started()) << server.log();
  auto client = server.client();
  const auto path = writeIcosphere(dir.path(), "icosphere.obj", 3);
  const auto res = upload(client, readFile(path), false, "icosphere.obj", "?rosy=4&vertices=300");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 202) << res->body;
  const auto job = waitForJob(client, res->get_header_value("Location"), std::chrono::seconds(60));
  ASSERT_EQ(job.value("state", ""), "succeeded") << job.dump();
  const std::string self = job.at("links").at("self");
  const auto metrics = nlohmann::json::parse(client.Get((self + "/metrics").c_str())->body);
  EXPECT_FALSE(metrics.contains("hexagons"));
  const long long faces = metrics.at("faces"), quads = metrics.at("quads");
  EXPECT_EQ(quads, faces) << "a closed sphere: quads only";
  EXPECT_EQ(metrics.at("irregular_interior"), 8);
  for (const std::string format : {"obj", "ply", "off"}) {
    const PolygonSoup soup =
        parseDownload(downloadResult(client, self, "quads", format), format, dir.path());
    EXPECT_EQ(static_cast<long long>(soup.faceCount()), faces) << format;
    for (std::size_t f = 0; f < soup.faceCount(); ++f) ASSERT_EQ(soup.faceSize(f), 4u) << format;
  }
  // The triangles of the same remesh: two per quad.
  const PolygonSoup triangles =
      parseDownload(downloadResult(client, self, "triangles", "obj"), "obj", dir.path());
  EXPECT_EQ(static_cast<long long>(triangles.faceCount()), 2 * quads);
  const auto hexagons = client.Get((self + "/result?mesh=hexagons&format=obj").c_str());
  ASSERT_TRUE(hexagons);
  EXPECT_EQ(hexagons->status, 404);
}

TEST(EndToEnd, SharedCleanMeshOfEachStoredFormatRemeshesWithParsableResults) {
  HEXCOVER_SERVER_OR_SKIP();
  // clean/ stores OBJ and OFF; the smallest of each keeps the suite fast.
  HEXCOVER_SHARED_MESH_OR_SKIP(off, "clean/venus_1k.off");
  HEXCOVER_SHARED_MESH_OR_SKIP(obj, "clean/spot.obj");
  remeshAllAndCheck({{"venus_1k.off", "off", readFile(off)}, {"spot.obj", "obj", readFile(obj)}});
}

}  // namespace
}  // namespace hexcover::server::test
