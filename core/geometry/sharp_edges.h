#pragma once
// Sharp edges (creases) of a triangle mesh: the feature lines a remesh should follow.

#include <vector>

#include "core/mesh/mesh.h"

namespace hexcover {

/// #E: the dihedral angle of each interior edge in degrees (between the normals of its two
/// faces); 0 at boundary edges and at edges of a degenerate face.
std::vector<double> dihedralAngles(const TriMesh& mesh);

/// #E: true at the interior edges whose dihedral angle (between the normals of their two faces)
/// is at least `minDihedralDegrees` and that lie on a crease line at least `minLineLength` long
/// (mesh units). A line runs through vertices where exactly two such edges meet and turn by at
/// most 45°; it ends at corners (one, three or more such edges, or a sharper turn). Short lines
/// are the folds of a noisy scan or of a spike, not features. minDihedralDegrees ≤ 0: none.
std::vector<bool> sharpEdges(const TriMesh& mesh, double minDihedralDegrees, double minLineLength);

}  // namespace hexcover
