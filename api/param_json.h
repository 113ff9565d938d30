#pragma once
// JSON form of the parameterization stage's result (core/param/parameterization.h), as the CLI
// prints it and the API reports it. Keys are snake_case. The per-corner arrays are not included
// (they go to files: the textured mesh).

#include <nlohmann/json.hpp>

#include "core/param/hexcover.h"
#include "core/param/parameterization.h"

namespace hexcover {

/// {"rosy": N, "edge_length": h, "flipped", "flipped_before_stiffening", "local_relaxations", "stiffening_iterations",
///  "degenerate", "singularities" (count), "singularity_coords": [{"vertex", "index_numerator",
///  "coords": [a, b]}], "cut_edges", "cut_length", "integer_variables", "energy",
///  "local_energy", "distortion": {"angle_mean_deg", "angle_max_deg", "area_mean_log",
///  "area_max_log"}, "seconds" (Σ of the step timings), "timings": [{"step", "seconds"}]}.
nlohmann::json toJson(const Parameterization& parameterization);

/// "direct" / "greedy"; parse throws Error(InvalidOption) naming the accepted values.
const char* roundingMethodName(RoundingMethod method);
RoundingMethod parseRoundingMethod(const std::string& name);

}  // namespace hexcover
