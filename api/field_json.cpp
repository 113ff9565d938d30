#include "api/field_json.h"

#include <cmath>

namespace hexcover {

nlohmann::json toJson(const RosyField& field) {
  nlohmann::json singularities = nlohmann::json::array();
  int indexSum = 0, onBoundary = 0;
  for (const auto& s : field.singularities) {
    indexSum += s.index;
    onBoundary += s.onBoundary ? 1 : 0;
    singularities.push_back(
        {{"vertex", s.vertex},
         {"index", std::round(1e4 * s.index / field.n) / 1e4},
         {"index_numerator", s.index},
         {"position", {s.position.x(), s.position.y(), s.position.z()}},
         {"on_boundary", s.onBoundary}});
  }
  nlohmann::json timings = nlohmann::json::array();
  for (const auto& t : field.timings) timings.push_back({{"step", t.step}, {"seconds", t.seconds}});
  return {{"rosy", field.n},
          {"euler_characteristic", field.eulerCharacteristic},
          {"singularities_initial", field.singularitiesInitial},
          {"singularities_final", field.singularities.size()},
          {"singularities_boundary", onBoundary},
          {"index_sum", static_cast<double>(indexSum) / field.n},
          {"singularity_distance", field.singularityDistance},
          {"singularities", std::move(singularities)},
          {"seconds", field.seconds},
          {"timings", std::move(timings)}};
}

}  // namespace hexcover
