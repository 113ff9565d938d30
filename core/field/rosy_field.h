#pragma once
// N-RoSy direction fields on the faces of a triangle mesh (paper section 3).
//
// Conventions shared by every later stage:
// - faceDirection[f] is one representative of the N directions in face f: a unit 3D vector in
//   the face's plane. The others are it rotated by 2πk/N counter-clockwise about the face normal.
// - edgeMatching[e] = r_e in {0..N-1} for the edge e with halfedges h0 = halfedge(e,0) in face
//   f0 and h1 = halfedge(e,1) in face f1: the representative of f0, parallel-transported across
//   the edge into f1 (unfolding the two triangles about the edge), is closest to the
//   representative of f1 rotated by 2π r_e / N (paper eq. (2): F_u in f0 pairs with R^{r} F_u in
//   f1). Read from f1 to f0 it is (N - r_e) mod N. Boundary edges have 0.
// - A singularity of index I/N at a vertex (I ≠ 0). Indices include the angle defect, so that on
//   every component Σ I/N = χ (Poincaré–Hopf, with boundary vertices by their own rule).

#include <Eigen/Core>
#include <vector>

#include "core/common/timings.h"
#include "core/mesh/mesh.h"

namespace hexcover {

struct Singularity {
  int vertex = -1;               ///< vertex index in the mesh the field lives on
  int index = 0;                 ///< I: the singularity's index is I / N
  Eigen::Vector3d position{0, 0, 0};
};

struct RosyField {
  int n = 6;                                   ///< symmetry order N (6 or 4)
  std::vector<Eigen::Vector3d> faceDirection;  ///< #F unit representatives
  std::vector<int> edgeMatching;               ///< #E matchings r_e, see above
  std::vector<Singularity> singularities;      ///< final singularities, sorted by vertex
  int singularitiesInitial = 0;                ///< count before clustering
  Timings timings;
};

/// Builds a RosyField from given per-face representative directions (any tangent vectors, they
/// are projected and normalized): computes the matchings and the singularities (with their
/// index check). Used by the solver and by tests that prescribe fields.
RosyField rosyFieldFromDirections(const TriMesh& mesh, std::vector<Eigen::Vector3d> directions,
                                  int n);

}  // namespace hexcover
