#pragma once
// Internal to core/extract: steps 4b and 5 of extract.h. The boundary loops of the lattice
// triangles are fronts along an input boundary loop, stitched to samples of that loop so that the
// output boundary lies on the input boundary, or coverage gaps, which are filled.

#include <optional>
#include <vector>

#include "core/extract/assembly.h"
#include "core/extract/extract.h"
#include "core/geometry/closest_point.h"
#include "core/mesh/mesh.h"

namespace hexcover::extract_detail {

/// Resolves every boundary loop of the lattice triangles in `out`: a front along an input
/// boundary loop of `mesh` is stitched to that loop's samples (BoundaryMode::Follow) or left
/// (Lattice); any other loop is a coverage gap and is filled. `faceComponent`: the input's
/// component of each face. `input` (closest points on `mesh`, built here when first needed; or
/// null) puts the vertices that split the strips' long edges onto the input.
void closeBoundaries(const TriMesh& mesh, std::optional<ClosestPointQuery>* input,
                     const std::vector<int>& faceComponent, const ExtractOptions& options,
                     Assembly& out, ExtractionReport& report);

}  // namespace hexcover::extract_detail
