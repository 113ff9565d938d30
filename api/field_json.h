#pragma once
// JSON form of the field stage's result (core/field/rosy_field.h), as the CLI prints it and the
// API reports it. Keys are snake_case.

#include <nlohmann/json.hpp>

#include "core/field/rosy_field.h"

namespace hexcover {

/// {"rosy": N, "euler_characteristic", "singularities_initial", "singularities_final",
///  "singularities_boundary" (how many of the final ones are boundary vertices),
///  "index_sum" (Σ I/N, = euler_characteristic), "singularity_distance" (d_sing, mesh units),
///  "singularities": [{"vertex", "index" (I/N rounded to 4 decimals, e.g. -0.1667),
///  "index_numerator" (I), "position": [x, y, z], "on_boundary"}] sorted by vertex,
///  "seconds" (Σ of the step timings), "timings": [{"step", "seconds"}] in run order}.
nlohmann::json toJson(const RosyField& field);

}  // namespace hexcover
