#pragma once
// The result of the HexCover parameterization (paper section 4), handed to extraction.
//
// Coordinates are lattice coordinates z = (a, b): the point of the plane is a·e1 + b·e2 with
// e1 = (1, 0) and, for N = 6, e2 = (1/2, √3/2) (the Eisenstein lattice G6 of eq. (3)); for N = 4,
// e2 = (0, 1) (Gauss integers). Lattice points are exactly the integer (a, b). One lattice unit
// maps to `edgeLength` on the surface (times the local sizing factor).
// In these coordinates the rotation by 2π/N is an integer matrix: N = 6: R = [[0, -1], [1, 1]]
// (R^3 = -I); N = 4: R = [[0, -1], [1, 0]].

#include <Eigen/Core>
#include <vector>

#include "core/common/timings.h"

namespace hexcover {

/// Transition across an edge e with halfedges h0 = halfedge(e,0) in face f0 and h1 in face f1:
/// z_f1 = R^rotation · z_f0 + translation for every point of the edge (paper eq. (2)).
/// rotation in {0..N-1}; translation is integral, so the pattern is seamless.
struct EdgeTransition {
  int rotation = 0;
  Eigen::Vector2i translation{0, 0};
};

struct ParamSingularity {
  int vertex = -1;
  int index = 0;             ///< I of the field singularity (index I/N)
  Eigen::Vector2d coords;    ///< lattice coordinates in the first face around the vertex
};

struct DistortionStats {
  double angleMean = 0.0;    ///< mean |angle(parameter triangle) - angle(surface triangle)|, degrees
  double angleMax = 0.0;
  double areaMean = 0.0;     ///< mean |log(parameter area / surface area)| after scaling by h²
  double areaMax = 0.0;
};

struct Parameterization {
  int n = 6;
  double edgeLength = 0.0;
  /// #halfedges: lattice coordinates of to_vertex(h) in face(h); unused for boundary halfedges.
  std::vector<Eigen::Vector2d> cornerCoords;
  /// #E transitions; identity for edges not on the cut and for boundary edges.
  std::vector<EdgeTransition> edgeTransition;
  /// #E: true for the edges of the cut graph.
  std::vector<bool> cutEdge;
  /// #F: the coordinates of face f follow the field's representative faceDirection[f] rotated by
  /// 2π·faceRotation[f]/N (the combing of the field along a dual spanning tree): ∇u ≈ that
  /// direction / (edgeLength / sizing), ∇v its 90° rotation, in Cartesian units (u, v) = M·z.
  std::vector<int> faceRotation;
  double cutLength = 0.0;        ///< total surface length of the cut graph
  int integerVariables = 0;      ///< independent integer unknowns after elimination (sec. 4.4)
  std::vector<ParamSingularity> singularities;
  int flippedTriangles = 0;      ///< parameter triangles with negative orientation
  int degenerateTriangles = 0;   ///< parameter triangles with (near) zero area
  DistortionStats distortion;
  /// Energy (4) plus the anisotropy term (ParamOptions::conformalWeight) of the final solution,
  /// in units of area/h², plus the crease terms (ParamOptions::creaseWeight) where the field has
  /// creases.
  double energy = 0.0;
  double localEnergy = 0.0;      ///< the same for the local step (no integer constraints; the
                                 ///< creases only aligned, not yet on lattice lines)
  int latticeDescentMoves =
      0;  ///< rounding improvements by lattice descent (EnergySystem::descendIntegers)
  int flippedBeforeStiffening = 0;  ///< flipped triangles right after the final solve (before
                                    ///< rounding repair and stiffening)
  int localRelaxations = 0;      ///< local re-solves around flipped triangles
  int stiffeningIterations = 0;  ///< global re-solves spent on removing fold-overs
  Timings timings;
};

}  // namespace hexcover
