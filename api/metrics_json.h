#pragma once
// JSON form of the quality report (core/metrics/metrics.h). Keys are snake_case; every key is
// always present so clients can rely on them: values that need a reference mesh are null
// without one. Distances are in percent of the reference's bounding-box diagonal, angles in
// degrees.

#include <nlohmann/json.hpp>

#include "core/metrics/metrics.h"

namespace hexcover {

/// {"vertices", "faces",
///  "hausdorff_pct", "hausdorff_upper_bound_pct", "hausdorff_certified", "mean_dist_pct",
///  "rms_dist_pct", "result_to_reference": {max_pct, mean_pct, rms_pct},
///  "reference_to_result": {max_pct, mean_pct, rms_pct}, "reference_diagonal", "distance_samples"
///  (all null without a reference),
///  "angle_min", "angle_max", "angle_mean", "angle_sd", "angles_below_30_pct",
///  "angles_above_90_pct", "min_angle_mean", "quality_min", "quality_mean",
///  "valence_interior", "valence_boundary" (objects valence → count, e.g. {"5": 12, "6": 630}),
///  "irregular_interior", "irregular_boundary", "edge_length_mean", "edge_length_cv",
///  "components", "boundary_loops", "euler_characteristic", "genus" (null when undefined),
///  "isolated_vertices", "manifold", "topology_matches_reference" (null without a reference),
///  "timings": {step: seconds}}.
nlohmann::json toJson(const QualityReport& report);

}  // namespace hexcover
