#pragma once
// Shared steps of the end-to-end tests: meshes the tests make themselves, uploads, and checks
// of downloaded results against the metrics document.

// clang-format off
// Eigen (through core/) before httplib.h: glibc's <resolv.h>, which httplib includes, defines a
// macro `_res` that breaks Eigen's headers.
#include "core/mesh/io.h"
#include "core/mesh/primitives.h"
#include <httplib.h>
// clang-format on

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace hexcover::server::test {

inline std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// An icosphere with `subdivisions` written as `dir/name` (format from the extension).
inline std::filesystem::path writeIcosphere(const std::filesystem::path& dir,
                                            const std::string& name, int subdivisions) {
  const auto path = dir / name;
  writeMesh(toPolygonSoup(makeIcosphere(subdivisions)), path);
  return path;
}

/// POSTs `bytes` raw, or as the `mesh` part of a multipart upload; returns the response.
inline httplib::Result upload(httplib::Client& client, const std::string& bytes, bool multipart,
                              const std::string& filename = "mesh", const std::string& query = "") {
  const std::string path = "/v1/jobs" + query;
  if (!multipart) return client.Post(path.c_str(), bytes, "application/octet-stream");
  const httplib::MultipartFormDataItems items = {
      {"mesh", bytes, filename, "application/octet-stream"}};
  return client.Post(path.c_str(), items);
}

/// Triangles and vertices of a .glb (one mesh, one primitive), or {-1, -1}.
inline std::pair<long long, long long> glbCounts(const std::string& bytes,
                                                 bool* hasTexcoords = nullptr) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  if (!loader.LoadBinaryFromMemory(&model, &error, &warning,
                                   reinterpret_cast<const unsigned char*>(bytes.data()),
                                   static_cast<unsigned int>(bytes.size())) ||
      model.meshes.size() != 1 || model.meshes[0].primitives.size() != 1)
    return {-1, -1};
  const auto& primitive = model.meshes[0].primitives[0];
  if (hasTexcoords) *hasTexcoords = primitive.attributes.count("TEXCOORD_0") > 0;
  return {static_cast<long long>(model.accessors[primitive.indices].count / 3),
          static_cast<long long>(model.accessors[primitive.attributes.at("POSITION")].count)};
}

/// The body of GET {self}/result?format=...&mesh=..., expecting 200 and a Content-Disposition
/// that names the mesh and format; empty on failure.
inline std::string downloadResult(httplib::Client& client, const std::string& self,
                                  const std::string& mesh, const std::string& format) {
  const auto res = client.Get((self + "/result?format=" + format + "&mesh=" + mesh).c_str());
  EXPECT_TRUE(res && res->status == 200) << mesh << "." << format;
  if (!res || res->status != 200) return std::string();
  EXPECT_NE(res->get_header_value("Content-Disposition").find(mesh + "." + format),
            std::string::npos);
  return res->body;
}

/// A downloaded mesh read back through a file of its format in `scratch`.
inline PolygonSoup parseDownload(const std::string& bytes, const std::string& format,
                                 const std::filesystem::path& scratch) {
  const auto file = scratch / ("download." + format);
  std::ofstream(file, std::ios::binary) << bytes;
  return readMesh(file);
}

/// Downloads every result of a succeeded job and checks that each parses and agrees with the
/// metrics document (face and vertex counts, hexagon counts) and the input report.
inline void expectResultsAgreeWithMetrics(httplib::Client& client, const nlohmann::json& job,
                                          const std::filesystem::path& scratch) {
  const std::string self = job.at("links").at("self");
  const auto metricsRes = client.Get((self + "/metrics").c_str());
  ASSERT_TRUE(metricsRes);
  ASSERT_EQ(metricsRes->status, 200);
  const auto metrics = nlohmann::json::parse(metricsRes->body);
  const long long faces = metrics.at("faces");
  const long long vertices =
      metrics.at("vertices").get<long long>() + metrics.at("isolated_vertices").get<long long>();
  const long long hexagons = metrics.at("hexagons").at("faces");
  ASSERT_GT(faces, 0);
  EXPECT_GT(hexagons, 0);

  const auto download = [&](const std::string& mesh, const std::string& format) {
    return downloadResult(client, self, mesh, format);
  };
  const auto parse = [&](const std::string& bytes, const std::string& format) {
    return parseDownload(bytes, format, scratch);
  };

  for (const std::string format : {"obj", "ply", "off", "stl"}) {
    const PolygonSoup soup = parse(download("triangles", format), format);
    EXPECT_EQ(static_cast<long long>(soup.faceCount()), faces) << "triangles." << format;
    if (format == "stl")
      EXPECT_LE(static_cast<long long>(soup.vertexCount()), vertices);  // STL welds by position
    else
      EXPECT_EQ(static_cast<long long>(soup.vertexCount()), vertices) << "triangles." << format;
  }
  const auto triangleGlb = glbCounts(download("triangles", "glb"));
  EXPECT_EQ(triangleGlb.first, faces);
  EXPECT_EQ(triangleGlb.second, vertices);

  const PolygonSoup hexObj = parse(download("hexagons", "obj"), "obj");
  EXPECT_EQ(static_cast<long long>(hexObj.faceCount()), hexagons);
  long long fanTriangles = 0;
  for (std::size_t f = 0; f < hexObj.faceCount(); ++f) fanTriangles += hexObj.faceSize(f) - 2;
  for (const std::string format : {"ply", "off"})
    EXPECT_EQ(static_cast<long long>(parse(download("hexagons", format), format).faceCount()),
              hexagons);
  EXPECT_EQ(static_cast<long long>(parse(download("hexagons", "stl"), "stl").faceCount()),
            fanTriangles);
  EXPECT_EQ(glbCounts(download("hexagons", "glb")).first, fanTriangles);

  const PolygonSoup textured = parse(download("textured", "obj"), "obj");
  EXPECT_FALSE(textured.cornerTexcoords.empty());
  EXPECT_EQ(textured.cornerTexcoords.size(), textured.cornerVertices.size());
  EXPECT_EQ(static_cast<long long>(textured.faceCount()),
            job.at("input").at("report").at("result").at("triangles").get<long long>());
  bool hasTexcoords = false;
  EXPECT_EQ(glbCounts(download("textured", "glb"), &hasTexcoords).first,
            static_cast<long long>(textured.faceCount()));
  EXPECT_TRUE(hasTexcoords);
}

}  // namespace hexcover::server::test
