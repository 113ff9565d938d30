#pragma once
// Intrinsic per-element geometry that the field stage builds on: per-face tangent frames, the
// discrete Levi-Civita transport across edges, corner angles, angle defects and connected
// components with their Euler characteristics.
//
// Conventions (shared with core/field/rosy_field.h):
// - Face f has the orthonormal frame (xAxis[f], yAxis[f], normal[f]) with xAxis along the face's
//   first halfedge (mesh.halfedge_handle(f), from its from- to its to-vertex) and
//   yAxis = normal × xAxis. The tangent angle of a vector d in face f is atan2(d·y, d·x).
// - transport[e] for an interior edge e with h0 = halfedge(e,0) in f0 and h1 in f1 is the angle
//   ρ_e added to a tangent angle when the vector is carried from f0 into f1 by unfolding the two
//   triangles about the edge: angle_f1 = angle_f0 + ρ_e (mod 2π). 0 on boundary edges.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/mesh/mesh.h"

namespace hexcover {

struct FaceFrames {
  std::vector<Eigen::Vector3d> normal;  ///< #F unit normals (right-hand rule of the face's corners)
  std::vector<Eigen::Vector3d> xAxis;   ///< #F unit tangent along the face's first halfedge
  std::vector<Eigen::Vector3d> yAxis;   ///< #F normal × xAxis
  std::vector<double> area;             ///< #F triangle areas

  /// Tangent angle in face f of the vector d (projected to the face plane); 0 for d ⟂ plane.
  double angleOf(int f, const Eigen::Vector3d& d) const;
  /// Unit vector in face f with tangent angle `angle`.
  Eigen::Vector3d direction(int f, double angle) const;
};

/// Frames of every face. A face whose corners are (nearly) collinear gets the normal of its
/// neighbours (or any normal perpendicular to its longest edge), so the frame is always
/// orthonormal and finite.
FaceFrames computeFaceFrames(const TriMesh& mesh);

/// #E transport angles ρ_e (see above), in (-π, π]; 0 on boundary edges.
std::vector<double> edgeTransportAngles(const TriMesh& mesh, const FaceFrames& frames);

/// #halfedges: the triangle's interior angle at to_vertex(h) in face(h) (between the edge of h
/// and the edge of next(h)), in [0, π]; 0 for boundary halfedges. Computed as
/// atan2(|a×b|, a·b), which is exact for slivers and never NaN.
std::vector<double> cornerAngles(const TriMesh& mesh);

/// #V discrete Gauss curvature as angle defect: 2π − Σ corner angles at interior vertices,
/// π − Σ corner angles (the geodesic curvature, the boundary's turning angle) at boundary
/// vertices (in general 2π − π·b − Σ with b the number of boundary fans at the vertex), 0 at
/// isolated vertices. Σ over a component = 2π χ (discrete Gauss–Bonnet).
std::vector<double> angleDefects(const TriMesh& mesh);

/// Connected components of the faces (through shared edges and vertices of the manifold mesh).
struct FaceComponents {
  int count = 0;
  std::vector<int> faceComponent;        ///< #F component id in [0, count), by lowest face index
  std::vector<int> eulerCharacteristic;  ///< per component: V − E + F of its faces
  std::vector<int> boundaryLoops;        ///< per component: number of boundary loops
};

FaceComponents faceComponents(const TriMesh& mesh);

}  // namespace hexcover
