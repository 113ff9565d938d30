#include "api/metrics_json.h"

#include <string>

namespace hexcover {
namespace {

nlohmann::json histogram(const std::map<int, int>& counts) {
  nlohmann::json object = nlohmann::json::object();
  for (const auto& [valence, count] : counts) object[std::to_string(valence)] = count;
  return object;
}

nlohmann::json oneSided(double maxPct, double meanPct, double rmsPct) {
  return {{"max_pct", maxPct}, {"mean_pct", meanPct}, {"rms_pct", rmsPct}};
}

}  // namespace

nlohmann::json toJson(const QualityReport& report) {
  nlohmann::json json;
  json["vertices"] = report.vertices;
  json["faces"] = report.faces;
  json["quads"] = report.quads;

  const auto& d = report.distance;
  const nlohmann::json null;
  json["hausdorff_pct"] = d ? nlohmann::json(d->hausdorffPct) : null;
  json["hausdorff_upper_bound_pct"] = d ? nlohmann::json(d->hausdorffUpperBoundPct) : null;
  json["hausdorff_certified"] = d ? nlohmann::json(d->hausdorffCertified) : null;
  json["mean_dist_pct"] = d ? nlohmann::json(d->meanPct) : null;
  json["rms_dist_pct"] = d ? nlohmann::json(d->rmsPct) : null;
  json["result_to_reference"] =
      d ? oneSided(d->resultToReferenceMaxPct, d->resultToReferenceMeanPct,
                   d->resultToReferenceRmsPct)
        : null;
  json["reference_to_result"] =
      d ? oneSided(d->referenceToResultMaxPct, d->referenceToResultMeanPct,
                   d->referenceToResultRmsPct)
        : null;
  json["reference_diagonal"] = d ? nlohmann::json(d->referenceDiagonal) : null;
  json["distance_samples"] = d ? nlohmann::json(d->samples) : null;

  json["angle_min"] = report.angleMin;
  json["angle_max"] = report.angleMax;
  json["angle_mean"] = report.angleMean;
  json["angle_sd"] = report.angleSd;
  json["angles_below_30_pct"] = report.anglesBelow30Pct;
  json["angles_above_90_pct"] = report.anglesAbove90Pct;
  json["min_angle_mean"] = report.minAngleMean;
  json["quality_min"] = report.qualityMin;
  json["quality_mean"] = report.qualityMean;

  json["valence_interior"] = histogram(report.valenceInterior);
  json["valence_boundary"] = histogram(report.valenceBoundary);
  json["irregular_interior"] = report.irregularInterior;
  json["irregular_boundary"] = report.irregularBoundary;
  json["edge_length_mean"] = report.edgeLengthMean;
  json["edge_length_cv"] = report.edgeLengthCv;

  const MeshTopology& t = report.topology;
  json["components"] = t.components;
  json["boundary_loops"] = t.boundaryLoops;
  json["euler_characteristic"] = t.eulerCharacteristic;
  json["genus"] = t.genus() >= 0 ? nlohmann::json(t.genus()) : null;
  json["isolated_vertices"] = t.isolatedVertices;
  json["manifold"] = t.manifold;
  json["topology_matches_reference"] =
      report.topologyMatchesReference ? nlohmann::json(*report.topologyMatchesReference) : null;

  nlohmann::json timings = nlohmann::json::object();
  for (const auto& step : report.timings) timings[step.step] = step.seconds;
  json["timings"] = timings;
  return json;
}

}  // namespace hexcover
