#pragma once
// Validation of a polygon soup without changing it: the "as found" part of the report.

#include "core/mesh/mesh.h"
#include "core/mesh/report.h"

namespace hexcover {

/// Sizes, topology per component and defect counts of `soup` (report.h, MeshStatistics).
/// Never throws on bad geometry: NaN coordinates, out-of-range indices (counted as degenerate
/// faces) and non-manifold configurations are counted, not refused. Throws Error(InvalidMesh)
/// only for an inconsistent soup (faceStarts not rising from 0 to the corner count).
MeshStatistics measureMesh(const PolygonSoup& soup);

/// The report of `soup` as found: report.input = measureMesh(soup), repaired = false.
MeshReport validateMesh(const PolygonSoup& soup);

}  // namespace hexcover
