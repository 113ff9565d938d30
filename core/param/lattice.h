#pragma once
// The parameter-space lattices of paper eq. (3) in lattice coordinates.
//
// A point of the parameter plane is z = (a, b) ↦ a·e1 + b·e2 (Cartesian, in units of h) with
// e1 = (1, 0) and e2 = (1/2, √3/2) for N = 6 (Eisenstein integers G6), e2 = (0, 1) for N = 4
// (Gauss integers G4). Lattice points are exactly Z², and the rotation by 2π/N is the integer
// matrix R (N = 6: [[0, -1], [1, 1]], R³ = -I; N = 4: [[0, -1], [1, 0]]), so transitions
// z ↦ R^k z + t with t ∈ Z² are exact in integer arithmetic.

#include <Eigen/Core>
#include <cmath>

namespace hexcover {

/// True for the symmetry orders with a rotation-invariant lattice (4 and 6).
inline bool isLatticeOrder(int n) { return n == 4 || n == 6; }

/// k mod n in [0, n) (rotation indices), for any integer k and n > 0.
inline int wrapIndex(int k, int n) { return ((k % n) + n) % n; }

/// R^k for the lattice of order n (k any integer, taken mod n).
inline Eigen::Matrix2i latticeRotation(int n, int k) {
  const Eigen::Matrix2i r = n == 6 ? (Eigen::Matrix2i() << 0, -1, 1, 1).finished()
                                   : (Eigen::Matrix2i() << 0, -1, 1, 0).finished();
  Eigen::Matrix2i result = Eigen::Matrix2i::Identity();
  for (int i = wrapIndex(k, n); i > 0; --i) result = r * result;
  return result;
}

/// The 2×2 matrix M with Cartesian = M · lattice (columns e1, e2).
inline Eigen::Matrix2d latticeBasis(int n) {
  Eigen::Matrix2d m;
  if (n == 6)
    m << 1.0, 0.5, 0.0, std::sqrt(3.0) / 2.0;
  else
    m.setIdentity();
  return m;
}

/// Area of one lattice triangle (half a lattice cell) in Cartesian units of h²:
/// √3/4 for N = 6, 1/2 for N = 4.
inline double latticeTriangleArea(int n) { return 0.5 * latticeBasis(n).determinant(); }

}  // namespace hexcover
