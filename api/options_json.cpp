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

/// The value of an enumerated option given as one of its words.
template <typename E, std::size_t K>
E enumerated(const std::string& name, const nlohmann::json& value,
             const std::array<OptionWord<E>, K>& words) {
  if (value.is_string())
    if (const auto known = valueOfWord(words, value.get<std::string>())) return *known;
  fail(name, wordList(words, "\""), value);
}

}  // namespace

RemeshOptions remeshOptionsFromJson(const nlohmann::json& options) {
  if (!options.is_object())
    throw Error(ErrorCode::InvalidOption, "options must be a JSON object, not " + options.dump());
  RemeshOptions result;
  for (const auto& [name, value] : options.items()) {
    const bool nullable = name == "edge_length" || name == "vertices" || name == "d_sing";
    if (value.is_null() && nullable) continue;  // null: the default
    if (name == "edge_length")
      result.edgeLength = number(name, value);
    else if (name == "vertices")
      result.targetVertices = integer(name, value);
    else if (name == "rosy")
      result.rosy = int(integer(name, value));
    else if (name == "sizing")
      result.sizing = enumerated(name, value, kSizingWords);
    else if (name == "placement")
      result.placement = enumerated(name, value, kPlacementWords);
    else if (name == "feature_angle")
      result.featureAngle = number(name, value);
    else if (name == "d_sing")
      result.dSing = number(name, value);
    else
      throw Error(ErrorCode::InvalidOption,
                  "unknown option '" + name + "'; the options are " + optionNameList());
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
          {"sizing", wordOf(kSizingWords, options.sizing)},
          {"placement", wordOf(kPlacementWords, options.placement)},
          {"feature_angle", options.featureAngle},
          {"d_sing", optional(options.dSing)}};
}

}  // namespace hexcover::api
