#pragma once
// Internal to core/extract: steps 1-3 of extract.h. The parameterization is sanitized onto a
// fixed-point grid (exact_lattice.h), then its lattice points are mapped onto the surface, each
// exactly once, and its unit lattice triangles are found by walking across parameter triangles.

#include <vector>

#include "core/common/run_context.h"
#include "core/extract/assembly.h"
#include "core/extract/extract.h"
#include "core/mesh/mesh.h"
#include "core/param/parameterization.h"

namespace hexcover::extract_detail {

/// Appends the lattice points of `param` on `mesh` and its unit lattice cells to `out` (triangles;
/// for N = 4 each square as two triangles, and in Assembly::squares), each
/// vertex tagged with the component (`faceComponent`) of the face that emits it. Counts and the
/// timings of "sanitize", "lattice points" and "lattice triangles" go to `report`.
void extractLattice(const TriMesh& mesh, const Parameterization& param,
                    const std::vector<int>& faceComponent, Assembly& out, ExtractionReport& report,
                    const RunContext& context);

}  // namespace hexcover::extract_detail
