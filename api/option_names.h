#pragma once
// The names of the remesh options (api/options_json.h reads them), apart from the core types so
// that the server can check query parameters without including the geometry library.

#include <array>
#include <string>
#include <string_view>

namespace hexcover::api {

/// The option names (also the query parameters of POST /v1/jobs), in the order documents list
/// them.
inline constexpr std::array<std::string_view, 7> kOptionNames{
    "edge_length", "vertices", "rosy", "sizing", "placement", "feature_angle", "d_sing"};

/// "edge_length, vertices, …": the names for messages that list the options.
inline std::string optionNameList() {
  std::string list;
  for (const auto name : kOptionNames) list.append(list.empty() ? "" : ", ").append(name);
  return list;
}

}  // namespace hexcover::api
