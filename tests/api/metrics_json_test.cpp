// JSON form of the quality report: every documented key present, nulls without a reference.

#include "api/metrics_json.h"

#include <gtest/gtest.h>

#include "core/mesh/primitives.h"

namespace hexcover {
namespace {

const char* const kAlwaysNumbers[] = {"vertices",
                                      "faces",
                                      "angle_min",
                                      "angle_max",
                                      "angle_mean",
                                      "angle_sd",
                                      "angles_below_30_pct",
                                      "angles_above_90_pct",
                                      "min_angle_mean",
                                      "quality_min",
                                      "quality_mean",
                                      "irregular_interior",
                                      "irregular_boundary",
                                      "edge_length_mean",
                                      "edge_length_cv",
                                      "components",
                                      "boundary_loops",
                                      "euler_characteristic",
                                      "isolated_vertices"};
const char* const kReferenceKeys[] = {
    "hausdorff_pct",    "hausdorff_upper_bound_pct", "hausdorff_certified", "mean_dist_pct",
    "rms_dist_pct",     "result_to_reference",       "reference_to_result", "reference_diagonal",
    "distance_samples", "topology_matches_reference"};

TEST(MetricsJson, WithoutReferenceDistanceKeysAreNull) {
  const nlohmann::json json = toJson(measureQuality(makeTorus(2.0, 0.5, 20, 10)));
  for (const char* key : kAlwaysNumbers) {
    ASSERT_TRUE(json.contains(key)) << key;
    EXPECT_TRUE(json[key].is_number()) << key;
  }
  for (const char* key : kReferenceKeys) {
    ASSERT_TRUE(json.contains(key)) << key;
    EXPECT_TRUE(json[key].is_null()) << key;
  }
  EXPECT_EQ(json["genus"], 1);
  EXPECT_EQ(json["manifold"], true);
  EXPECT_EQ(json["valence_interior"], nlohmann::json({{"6", 200}}));
  EXPECT_TRUE(json["valence_boundary"].is_object());
  EXPECT_TRUE(json["valence_boundary"].empty());
}

TEST(MetricsJson, WithReferenceDistanceKeysCarryTheReport) {
  const TriMesh sphere = makeIcosphere(3);
  TriMesh larger = sphere;
  for (const auto vh : larger.vertices()) larger.set_point(vh, 1.02 * larger.point(vh));
  const QualityReport report = measureQuality(larger, &sphere);
  const nlohmann::json json = toJson(report);
  for (const char* key : kReferenceKeys) EXPECT_FALSE(json[key].is_null()) << key;
  EXPECT_DOUBLE_EQ(json["hausdorff_pct"].get<double>(), report.distance->hausdorffPct);
  EXPECT_DOUBLE_EQ(json["result_to_reference"]["max_pct"].get<double>(),
                   report.distance->resultToReferenceMaxPct);
  EXPECT_EQ(json["topology_matches_reference"], true);
  EXPECT_EQ(json["valence_interior"]["5"], 12);
  EXPECT_TRUE(json["timings"].contains("distance"));
}

TEST(MetricsJson, UndefinedGenusIsNull) {
  TriMesh mesh;  // two triangles joined at one vertex: not manifold
  std::vector<TriMesh::VertexHandle> v;
  for (const auto& p : {TriMesh::Point(0, 0, 0), TriMesh::Point(1, 0, 0), TriMesh::Point(0, 1, 0),
                        TriMesh::Point(-1, 0, 0), TriMesh::Point(0, -1, 0)})
    v.push_back(mesh.add_vertex(p));
  mesh.add_face(v[0], v[1], v[2]);
  mesh.add_face(v[0], v[3], v[4]);
  const nlohmann::json json = toJson(measureQuality(mesh));
  EXPECT_TRUE(json["genus"].is_null());
  EXPECT_EQ(json["manifold"], false);
}

}  // namespace
}  // namespace hexcover
