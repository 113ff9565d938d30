#pragma once
// Per-vertex curvature of a triangle mesh and the (ρ, φ) classification of paper eq. (1).
//
// Estimator: Rusinkiewicz ("Estimating curvatures and their derivatives on triangle meshes",
// 3DPVT 2004): a second fundamental form per face by least squares from the differences of the
// vertex normals along its three edges, rotated into each vertex's tangent frame and averaged with
// the vertex's mixed Voronoi area in the face (Meyer et al. 2003) as weight. Signs: with outward
// normals a convex surface has positive curvature (a sphere of radius r: κ = 1/r).
// Gauss curvature is the angle defect (integrated, in radians, core/geometry/frames.h).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/mesh/mesh.h"

namespace hexcover {

/// Curvature class of a point from (ρ, φ) of eq. (1).
enum class CurvatureClass {
  Planar,      ///< ρ < δ
  Elliptic,    ///< |φ| > 3π/8 (spherical or inverted spherical)
  Hyperbolic,  ///< |φ| < π/8
  Cylindrical,  ///< π/8 ≤ |φ| ≤ 3π/8 (cylindrical for φ > 0, inverted cylindrical for φ < 0)
};

struct CurvatureOptions {
  /// δ of section 3.2, in units of 1 / bounding-box diagonal: ρ below it is planar. Default 1: a
  /// sphere whose diameter is the diagonal has ρ = 2√2 / diagonal.
  double planarThreshold = 1.0;
  /// Fraction of the surface area labelled "strong" (ρ above t_ρ); the paper uses 35 %.
  double strongAreaFraction = 0.35;

  /// Empty when valid; otherwise names the bad option and the valid range.
  std::string validate() const;
};

/// Per-vertex arrays (#V each, indexed by vertex index). Isolated vertices get zeros and class
/// Planar. Every value is finite for any manifold mesh, including slivers and boundaries.
struct Curvature {
  std::vector<Eigen::Vector3d> normal;        ///< unit vertex normals (Max's weights)
  std::vector<double> kappaMax;               ///< κ1 ≥ κ2: maximum (signed) principal curvature
  std::vector<double> kappaMin;               ///< κ2
  std::vector<Eigen::Vector3d> directionMax;  ///< unit tangent direction of κ1
  std::vector<Eigen::Vector3d> directionMin;  ///< unit tangent direction of κ2 (n × directionMax)
  std::vector<double> gauss;                  ///< angle defect (integrated Gauss curvature), rad
  std::vector<double> area;  ///< mixed Voronoi area (Meyer et al.); Σ = surface area
  std::vector<double> rho;   ///< ρ = sqrt(κ1² + κ2²), eq. (1)
  std::vector<double> phi;   ///< φ = atan((κ1 + κ2) / (κ1 − κ2)) in [−π/2, π/2]
  std::vector<CurvatureClass> classification;
  std::vector<bool> strong;  ///< ρ > t_ρ
  double planarRho = 0.0;    ///< δ in 1 / length units
  double strongRho = 0.0;    ///< t_ρ

  /// The curvature tensor of vertex v as a symmetric 3×3 matrix κ1 d1 d1ᵀ + κ2 d2 d2ᵀ.
  Eigen::Matrix3d tensor(int v) const;
  /// #V: the largest absolute principal curvature max(|κ1|, |κ2|) (|κ2| where the surface is
  /// concave), the curvature that curvature-adaptive sizing follows (paper Fig. 13).
  std::vector<double> largestAbsolute() const;
};

/// Curvature of every vertex (section 3.2). Throws Error(InvalidOption) for invalid options.
Curvature computeCurvature(const TriMesh& mesh, const CurvatureOptions& options = {});

/// #halfedges: the mixed Voronoi area (Meyer et al. 2003) of to_vertex(h) in face(h): the Voronoi
/// part for non-obtuse triangles, else area/2 at the obtuse corner and area/4 at the others;
/// 0 for boundary halfedges.
std::vector<double> mixedVoronoiCornerAreas(const TriMesh& mesh);

/// Class of a point with tensor magnitude ρ and angle φ, given δ.
CurvatureClass classifyCurvature(double rho, double phi, double planarRho);

}  // namespace hexcover
