#pragma once
// Quality of a remeshed surface: distance to the input (two-sided Hausdorff, mean, RMS), triangle
// shape (corner angles, quality Q), vertex valences, edge lengths and topology.
//
// Distances are in percent of the REFERENCE mesh's bounding-box diagonal; angles in degrees.
// See hausdorff.h for how distances are sampled and certified.

#include <map>
#include <optional>

#include "core/common/timings.h"
#include "core/mesh/mesh.h"
#include "core/mesh/topology.h"
#include "core/metrics/hausdorff.h"

namespace hexcover {

/// Options of measureQuality (distance sampling only; everything else is exact).
struct MetricsOptions {
  DistanceOptions distance;

  void validate() const { distance.validate(); }
};

/// Distances between the result and the reference, in percent of the reference's bounding-box
/// diagonal. "Two-sided" combines both directions (Hausdorff: max; mean and RMS: area-weighted
/// over both surfaces, see TwoSidedDistance).
struct DistanceReport {
  double hausdorffPct = 0.0;            ///< sampled two-sided Hausdorff distance
  double hausdorffUpperBoundPct = 0.0;  ///< certified upper bound of it
  bool hausdorffCertified = false;      ///< both one-sided maxima met the tolerance
  double meanPct = 0.0;
  double rmsPct = 0.0;
  double resultToReferenceMaxPct = 0.0;  ///< sup over the result of the distance to the reference
  double resultToReferenceMeanPct = 0.0;
  double resultToReferenceRmsPct = 0.0;
  double referenceToResultMaxPct = 0.0;  ///< sup over the reference of the distance to the result
  double referenceToResultMeanPct = 0.0;
  double referenceToResultRmsPct = 0.0;
  double referenceDiagonal = 0.0;  ///< the unit: 100% (mesh length unit)
  std::size_t samples = 0;         ///< distance queries, both directions
};

/// Everything measureQuality reports about a result mesh.
struct QualityReport {
  int vertices = 0;  ///< vertices that belong to a face
  int faces = 0;

  // Corner angles over all 3·F corners (degrees).
  double angleMin = 0.0;
  double angleMax = 0.0;
  double angleMean = 0.0;
  double angleSd = 0.0;           ///< population standard deviation
  double anglesBelow30Pct = 0.0;  ///< percent of corners < 30°
  double anglesAbove90Pct = 0.0;  ///< percent of corners > 90°
  double minAngleMean = 0.0;      ///< mean over triangles of the smallest corner angle

  /// Triangle quality Q = 6·A / (√3·p·L_max) (A area, p half the perimeter, L_max longest edge;
  /// Frey–Borouchaki): 1 for an equilateral triangle, 0 for a degenerate one.
  double qualityMin = 0.0;
  double qualityMean = 0.0;

  /// Valence (number of incident edges) → number of vertices, for interior and boundary
  /// vertices that belong to a face.
  std::map<int, int> valenceInterior;
  std::map<int, int> valenceBoundary;
  int irregularInterior = 0;  ///< interior vertices of valence ≠ 6 (quad remesh: ≠ 4)
  int irregularBoundary = 0;  ///< boundary vertices of valence ≠ 4 (quad remesh: ≠ 3)
  int quads = 0;              ///< faces with four corners (measurePolygonQuality)

  double edgeLengthMean = 0.0;  ///< mesh length unit
  double edgeLengthCv = 0.0;    ///< coefficient of variation: SD / mean

  MeshTopology topology;

  /// Set when a reference was given.
  std::optional<DistanceReport> distance;
  std::optional<bool> topologyMatchesReference;

  Timings timings;  ///< "shape", "topology", "distance"
};

/// Measures `result`, and its distance and topology against `reference` when given.
/// Throws Error(InvalidMesh) if a mesh has no faces, Error(InvalidOption) for bad options.
QualityReport measureQuality(const TriMesh& result, const TriMesh* reference = nullptr,
                             const MetricsOptions& options = {});

/// measureQuality of a quad-dominant polygon mesh (the remesh of the Gauss lattice): the angles
/// over every corner of every polygon (90° in a square), the triangle quality Q over its
/// triangles only (0 without), the valences with 4 regular inside and 3 on the boundary, the edge
/// lengths over its polygon edges; topology and distances from `triangulated`, the same surface
/// with each polygon split into triangles.
QualityReport measurePolygonQuality(const PolygonSoup& result, const TriMesh& triangulated,
                                    const TriMesh* reference = nullptr,
                                    const MetricsOptions& options = {});

}  // namespace hexcover
