#pragma once
// Internal to core/field: the intrinsic geometry a field lives on, and matchings and singularity
// indices of a field given by per-face tangent angles (conventions in rosy_field.h).

#include <vector>

#include "core/field/rosy_field.h"
#include "core/geometry/frames.h"

namespace hexcover::field {

/// Everything about the mesh that matchings, indices and the solves need; computed once.
struct FieldGeometry {
  FaceFrames frames;
  std::vector<double> transport;    ///< #E ρ_e
  std::vector<double> angleDefect;  ///< #V K_v (boundary: turning angle)
  FaceComponents components;
  std::vector<int> vertexComponent;  ///< #V component id, -1 for isolated vertices

  explicit FieldGeometry(const TriMesh& mesh);
};

/// Tangent angle in face f (of the face frame) of the boundary halfedge-side edge direction, for
/// each boundary edge: #E, NaN on interior edges.
std::vector<double> boundaryEdgeAngles(const TriMesh& mesh, const FieldGeometry& geometry);

/// Matchings, singularities and Euler characteristic of the field with representative angles θ
/// (#F, radians in each face frame), with the index checks described in rosy_field.h.
/// Fills every member of the result except timings (singularitiesInitial = singularities.size()).
/// The matching of edge e is the period nearest to the field's turn relative to ρ_e + shift_e
/// (`matchingShift`: #E, or empty for none): a field parallel for a corrected connection ρ + c
/// (Ray et al.) keeps the matching that connection intends even where |c_e| exceeds π/N, where
/// the nearest period relative to ρ alone would read the turn the other way round.
RosyField rosyFieldFromAngles(const TriMesh& mesh, const FieldGeometry& geometry,
                              const std::vector<double>& angles, int n,
                              const std::vector<double>& matchingShift = {});

}  // namespace hexcover::field
