#include "api/param_json.h"

#include <string>

#include "core/common/error.h"

namespace hexcover {

nlohmann::json toJson(const Parameterization& p) {
  int cutEdges = 0;
  for (const bool cut : p.cutEdge) cutEdges += cut ? 1 : 0;
  nlohmann::json singularities = nlohmann::json::array();
  for (const auto& s : p.singularities)
    singularities.push_back({{"vertex", s.vertex},
                             {"index_numerator", s.index},
                             {"coords", {s.coords.x(), s.coords.y()}}});
  nlohmann::json timings = nlohmann::json::array();
  for (const auto& t : p.timings) timings.push_back({{"step", t.step}, {"seconds", t.seconds}});
  return {{"rosy", p.n},
          {"edge_length", p.edgeLength},
          {"flipped", p.flippedTriangles},
          {"flipped_before_stiffening", p.flippedBeforeStiffening},
          {"local_relaxations", p.localRelaxations},
          {"stiffening_iterations", p.stiffeningIterations},
          {"degenerate", p.degenerateTriangles},
          {"singularities", p.singularities.size()},
          {"singularity_coords", std::move(singularities)},
          {"cut_edges", cutEdges},
          {"cut_length", p.cutLength},
          {"integer_variables", p.integerVariables},
          {"energy", p.energy},
          {"local_energy", p.localEnergy},
          {"distortion",
           {{"angle_mean_deg", p.distortion.angleMean},
            {"angle_max_deg", p.distortion.angleMax},
            {"area_mean_log", p.distortion.areaMean},
            {"area_max_log", p.distortion.areaMax}}},
          {"seconds", totalSeconds(p.timings)},
          {"timings", std::move(timings)}};
}

const char* roundingMethodName(RoundingMethod method) {
  return method == RoundingMethod::Greedy ? "greedy" : "direct";
}

RoundingMethod parseRoundingMethod(const std::string& name) {
  if (name == "direct") return RoundingMethod::Direct;
  if (name == "greedy") return RoundingMethod::Greedy;
  throw Error(ErrorCode::InvalidOption, "rounding must be 'direct' or 'greedy', got '" + name + "'");
}

}  // namespace hexcover
