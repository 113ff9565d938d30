#pragma once
// Exact closest points on a triangle mesh: point-to-triangle distances (Voronoi regions of a
// triangle's vertices, edges and interior) over an Embree 3 bounding-volume hierarchy; a
// triangle whose plane is farther than the best distance so far is skipped. Used by
// the metrics (surface distances) and by extraction (fitting the remesh to the input surface).

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "core/mesh/mesh.h"

namespace hexcover {

/// Closest point to p on triangle (a, b, c), exact up to rounding; a degenerate (collinear)
/// triangle gives the closest point of its three edges.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// Vertex positions and triangles of a TriMesh as arrays (#V positions, #F triangles), indexed
/// by OpenMesh index. Refuses a non-finite coordinate of a face's vertex (Error InvalidMesh).
struct TriangleArrays {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<int, 3>> triangles;
  std::vector<char> referenced;  ///< per vertex: belongs to a face

  explicit TriangleArrays(const TriMesh& mesh);
  const Eigen::Vector3d& corner(int face, int i) const { return positions[triangles[face][i]]; }
};

/// Exact closest-point queries against one triangle mesh. Builds the BVH once (O(F log F));
/// queries are thread-safe. Refuses a mesh without faces or with a non-finite coordinate
/// (Error InvalidMesh).
class ClosestPointQuery {
 public:
  explicit ClosestPointQuery(const TriMesh& target);
  ~ClosestPointQuery();
  ClosestPointQuery(const ClosestPointQuery&) = delete;
  ClosestPointQuery& operator=(const ClosestPointQuery&) = delete;

  struct Result {
    double distance = 0.0;
    /// Closest face, lowest index among exact ties (faces counted in iteration order: the
    /// OpenMesh index when the mesh has no deleted faces).
    int face = -1;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< closest point on the mesh
    int visited = 0;  ///< triangles the BVH handed to the exact distance (the query's cost)
  };
  /// Closest point of the mesh to `p`. `hintFace` (a face index, or −1) seeds the search radius
  /// with the distance to that face, which makes queries near a known answer fast.
  Result closest(const Eigen::Vector3d& p, int hintFace = -1) const;

  /// Distance from `p` to face `face` of the target mesh.
  double distanceToFace(const Eigen::Vector3d& p, int face) const;

  /// The target mesh's triangles, indexed as `Result::face`.
  const TriangleArrays& triangles() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hexcover
