#pragma once
// Remesh options as JSON: the `options` part of an upload, the query parameters of
// POST /v1/jobs, and the normalized options stored with a job.
//
//   {"edge_length": number > 0 | null, "vertices": integer > 0 | null, "rosy": 4 | 6,
//    "sizing": "uniform" | "curvature", "placement": "balanced" | "on_surface",
//    "d_sing": number >= 0 | null}
//
// null (or absent) means the pipeline's default (RemeshOptions documents them).

#include <nlohmann/json.hpp>

#include "core/pipeline/pipeline.h"

namespace hexcover::api {

/// Reads options from a JSON object, checking names and types (layer 2 of validation: syntax is
/// nlohmann's, ranges and consistency are RemeshOptions::validate's). Throws
/// Error(InvalidOption) naming the option: unknown name, wrong type, or a value that no range
/// could accept (e.g. a fractional vertex count).
RemeshOptions remeshOptionsFromJson(const nlohmann::json& options);

/// Every option, defaults included (the normalized form stored with a job).
nlohmann::json toJson(const RemeshOptions& options);

}  // namespace hexcover::api
