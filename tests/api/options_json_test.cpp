// Remesh options from JSON: names and types checked with the option named in the message,
// defaults kept, the normalized form round-trips.

#include "api/options_json.h"

#include <gtest/gtest.h>

namespace hexcover::api {
namespace {

std::string errorOf(const nlohmann::json& options) {
  try {
    remeshOptionsFromJson(options);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidOption);
    return e.what();
  }
  return "";
}

TEST(OptionsJson, EmptyObjectGivesThePipelineDefaults) {
  const RemeshOptions options = remeshOptionsFromJson(nlohmann::json::object());
  const RemeshOptions defaults;
  EXPECT_EQ(options.rosy, defaults.rosy);
  EXPECT_EQ(options.sizing, defaults.sizing);
  EXPECT_EQ(options.placement, defaults.placement);
  EXPECT_EQ(options.featureAngle, defaults.featureAngle);
  EXPECT_FALSE(options.edgeLength);
  EXPECT_FALSE(options.targetVertices);
  EXPECT_FALSE(options.dSing);
}

TEST(OptionsJson, ValuesAreReadAndNormalizedFormRoundTrips) {
  const auto options = remeshOptionsFromJson(
      {{"edge_length", 0.05}, {"rosy", 6}, {"sizing", "curvature"}, {"d_sing", 0.3}});
  EXPECT_DOUBLE_EQ(*options.edgeLength, 0.05);
  EXPECT_EQ(options.sizing, Sizing::Curvature);
  EXPECT_DOUBLE_EQ(*options.dSing, 0.3);
  const auto json = toJson(options);
  EXPECT_EQ(json.at("sizing"), "curvature");
  EXPECT_TRUE(json.at("vertices").is_null());
  EXPECT_EQ(toJson(remeshOptionsFromJson(json)), json);
  EXPECT_EQ(*remeshOptionsFromJson({{"vertices", 2000.0}}).targetVertices, 2000);
  EXPECT_EQ(json.at("placement"), "balanced");
  const auto onSurface = remeshOptionsFromJson({{"placement", "on_surface"}});
  EXPECT_EQ(onSurface.placement, VertexPlacement::OnSurface);
  EXPECT_EQ(toJson(onSurface).at("placement"), "on_surface");
  EXPECT_EQ(json.at("feature_angle"), 70.0);
  const auto noCreases = remeshOptionsFromJson({{"feature_angle", 0}});
  EXPECT_EQ(noCreases.featureAngle, 0.0);
  EXPECT_EQ(toJson(noCreases).at("feature_angle"), 0.0);
}

TEST(OptionsJson, BadNamesAndTypesNameTheOption) {
  EXPECT_NE(errorOf({{"speed", 3}}).find("'speed'"), std::string::npos);
  EXPECT_NE(errorOf({{"rosy", "six"}}).find("'rosy'"), std::string::npos);
  EXPECT_NE(errorOf({{"vertices", 10.5}}).find("'vertices'"), std::string::npos);
  EXPECT_NE(errorOf({{"sizing", "adaptive"}}).find("'sizing'"), std::string::npos);
  EXPECT_NE(errorOf({{"placement", "exact"}}).find("'placement'"), std::string::npos);
  EXPECT_NE(errorOf({{"edge_length", "1mm"}}).find("'edge_length'"), std::string::npos);
  EXPECT_NE(errorOf({{"feature_angle", "sharp"}}).find("'feature_angle'"), std::string::npos);
  EXPECT_NE(errorOf(nlohmann::json::array()).find("object"), std::string::npos);
}

}  // namespace
}  // namespace hexcover::api
