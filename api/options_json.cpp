#include "api/options_json.h"

#include <cmath>

namespace hexcover::api {

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& expected,
                       const nlohmann::json& value) {
  throw Error(ErrorCode::InvalidOption,
              "option '" + name + "' must be " + expected + ", not " + value.dump());
}

double number(const std::string& name, const nlohmann::json& value) {
  if (!value.is_number() || !std::isfinite(value.get<double>()))
    fail(name, "a finite number", value);
  return value.get<double>();
}

long long integer(const std::string& name, const nlohmann::json& value) {
  if (value.is_number_integer()) return value.get<long long>();
  if (value.is_number_float()) {
    const double v = value.get<double>();
    if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9e15)
      return static_cast<long long>(v);
  }
  fail(name, "an integer", value);
}

}  // namespace

RemeshOptions remeshOptionsFromJson(const nlohmann::json& options) {
  if (!options.is_object())
    throw Error(ErrorCode::InvalidOption, "options must be a JSON object, not " + options.dump());
  RemeshOptions result;
  for (const auto& [name, value] : options.items()) {
    if (value.is_null() && name != "rosy" && name != "sizing" && name != "placement") {
      if (name != "edge_length" && name != "vertices" && name != "d_sing")
        throw Error(ErrorCode::InvalidOption,
                    "unknown option '" + name +
                        "'; the options are edge_length, vertices, rosy, sizing, placement, d_sing");
      continue;  // null: the default
    }
    if (name == "edge_length") {
      result.edgeLength = number(name, value);
    } else if (name == "vertices") {
      result.targetVertices = integer(name, value);
    } else if (name == "rosy") {
      result.rosy = int(integer(name, value));
    } else if (name == "sizing") {
      if (value == "uniform")
        result.sizing = Sizing::Uniform;
      else if (value == "curvature")
        result.sizing = Sizing::Curvature;
      else
        fail(name, "\"uniform\" or \"curvature\"", value);
    } else if (name == "placement") {
      if (value == "balanced")
        result.placement = VertexPlacement::Balanced;
      else if (value == "on_surface")
        result.placement = VertexPlacement::OnSurface;
      else
        fail(name, "\"balanced\" or \"on_surface\"", value);
    } else if (name == "d_sing") {
      result.dSing = number(name, value);
    } else {
      throw Error(ErrorCode::InvalidOption,
                  "unknown option '" + name +
                      "'; the options are edge_length, vertices, rosy, sizing, placement, d_sing");
    }
  }
  return result;
}

nlohmann::json toJson(const RemeshOptions& options) {
  const auto optional = [](const auto& value) {
    return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
  };
  return {{"edge_length", optional(options.edgeLength)},
          {"vertices", optional(options.targetVertices)},
          {"rosy", options.rosy},
          {"sizing", options.sizing == Sizing::Uniform ? "uniform" : "curvature"},
          {"placement",
           options.placement == VertexPlacement::Balanced ? "balanced" : "on_surface"},
          {"d_sing", optional(options.dSing)}};
}

}  // namespace hexcover::api
