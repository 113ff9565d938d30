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

/// Largest deviation, in degrees, of the angle between two crease lines at a shared corner from
/// a multiple of the lattice angle 360°/N for them to count as compatible.
inline constexpr double kCompatibleCornerTolerance = 15.0;

/// The crease lines of `sharp` (#E) that a lattice of N-fold symmetry can follow all at once:
/// lines meeting at a corner at an angle that is not a multiple of 360°/N (a box's 90° corners
/// for N = 6) cannot both be lattice lines, and a field that follows both twists across the
/// faces between them. Longest lines first, a line is kept when every kept line that ends at
/// one of its corners meets it at a compatible angle; of a square's four sides, two opposite
/// ones stay. Closed lines and lines meeting at compatible angles all stay.
std::vector<bool> latticeCompatibleCreases(const TriMesh& mesh, const std::vector<bool>& sharp,
                                           int n);

}  // namespace hexcover
