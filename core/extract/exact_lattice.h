#pragma once
// Exact arithmetic on lattice coordinates for extraction (internal to core/extract).
//
// A point z = (a, b) in lattice coordinates (paper eq. (3): a·e1 + b·e2) is stored as two int64
// in units of 2^-24 / 3 lattice units. On this grid the lattice rotations (Eisenstein
// R = [[0,-1],[1,1]] for N = 6, Gauss R = [[0,-1],[1,0]] for N = 4) and integer translations are
// exact, lattice points (a, b) ∈ Z², unit-triangle centroids (a+⅓, b+⅓), (a+⅔, b+⅔) and unit-square
// centres (a+½, b+½) are exact, and so are the fixed points of every holonomy R^k z + t
// (det(I − R^k) ∈ {1, 3, 4} for N = 6, {2, 4} for N = 4). The orientation predicate is exact in
// 128-bit integers as long as |a|, |b| < 2^20 lattice units (checked by quantize()). The map
// (a, b) ↦ a·e1 + b·e2 preserves orientation, so orientation in lattice coordinates is
// orientation in the plane.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "core/common/error.h"

namespace hexcover::extract_detail {

constexpr int kFractionBits = 24;
/// One lattice unit in fixed-point units.
constexpr std::int64_t kUnit = std::int64_t{3} << kFractionBits;
/// Largest |coordinate| accepted, in lattice units.
constexpr double kMaxCoordinate = 1 << 20;

struct FixedPoint {
  std::int64_t a = 0;
  std::int64_t b = 0;
  friend bool operator==(const FixedPoint&, const FixedPoint&) = default;
};

/// Nearest grid point to lattice coordinates z. Throws Error(NumericalFailure) when out of range.
inline FixedPoint quantize(const Eigen::Vector2d& z) {
  if (!(std::abs(z.x()) < kMaxCoordinate && std::abs(z.y()) < kMaxCoordinate))
    throw Error(ErrorCode::NumericalFailure,
                "parameterization coordinates exceed 2^20 lattice units (or are not finite): the "
                "edge length is far too small for this mesh");
  const double scale = static_cast<double>(std::int64_t{1} << kFractionBits);
  return {3 * std::llround(z.x() * scale), 3 * std::llround(z.y() * scale)};
}

inline Eigen::Vector2d toLattice(const FixedPoint& p) {
  return {static_cast<double>(p.a) / kUnit, static_cast<double>(p.b) / kUnit};
}

/// The lattice point (a, b) ∈ Z².
inline FixedPoint latticePoint(std::int64_t a, std::int64_t b) { return {a * kUnit, b * kUnit}; }

/// Whether p is a lattice point.
inline bool isLatticePoint(const FixedPoint& p) { return p.a % kUnit == 0 && p.b % kUnit == 0; }

/// floor(p / kUnit) for each coordinate (p may be negative).
inline std::int64_t floorUnits(std::int64_t x) {
  return x >= 0 ? x / kUnit : -((-x + kUnit - 1) / kUnit);
}
inline std::int64_t ceilUnits(std::int64_t x) { return -floorUnits(-x); }

/// R p with R the rotation by 2π/n (n = 6 or 4) in lattice coordinates: (a, b) ↦ (−b, a + b) for
/// the Eisenstein lattice, (a, b) ↦ (−b, a) for the Gauss lattice.
template <typename Vector>
Vector rotateOnce(const Vector& z, int n) {
  return n == 6 ? Vector(-z.y(), z.x() + z.y()) : Vector(-z.y(), z.x());
}
/// R^k z (k any integer, taken mod n).
template <typename Vector>
Vector rotate(Vector z, int k, int n) {
  for (int i = 0; i < ((k % n) + n) % n; ++i) z = rotateOnce(z, n);
  return z;
}
inline FixedPoint rotate(FixedPoint p, int k, int n) {
  for (int i = 0; i < ((k % n) + n) % n; ++i)
    p = n == 6 ? FixedPoint{-p.b, p.a + p.b} : FixedPoint{-p.b, p.a};
  return p;
}

/// Twice the signed area of (p, q, r) in fixed-point units²: > 0 counter-clockwise. Exact.
inline __int128 orient(const FixedPoint& p, const FixedPoint& q, const FixedPoint& r) {
  return static_cast<__int128>(q.a - p.a) * (r.b - p.b) -
         static_cast<__int128>(q.b - p.b) * (r.a - p.a);
}

/// z ↦ R^rotation z + translation, an integral transition (paper eq. (2)) of the lattice of order
/// `n` (6: Eisenstein, 4: Gauss).
struct Transition {
  int rotation = 0;
  Eigen::Matrix<std::int64_t, 2, 1> translation{0, 0};
  int n = 6;

  FixedPoint operator()(const FixedPoint& p) const {
    const FixedPoint r = rotate(p, rotation, n);
    return {r.a + translation.x() * kUnit, r.b + translation.y() * kUnit};
  }
  Transition inverse() const {
    const int back = (n - rotation) % n;
    return {back, -rotate(translation, back, n), n};
  }
  /// (this ∘ first)(z) = this(first(z)).
  Transition after(const Transition& first) const {
    return {(rotation + first.rotation) % n, rotate(first.translation, rotation, n) + translation,
            n};
  }
};

/// The fixed point of z ↦ R^k z + t for k ≠ 0 (mod n): the solution of (I − R^k) z = t, exact on
/// the fixed-point grid because det(I − R^k) ∈ {1, 2, 3, 4} divides kUnit.
inline FixedPoint fixedPoint(const Transition& holonomy) {
  // Columns of R^k are R^k e1 and R^k e2.
  using Vector = Eigen::Matrix<std::int64_t, 2, 1>;
  const auto c1 = rotate(Vector(1, 0), holonomy.rotation, holonomy.n);
  const auto c2 = rotate(Vector(0, 1), holonomy.rotation, holonomy.n);
  const std::int64_t m00 = 1 - c1.x(), m01 = -c2.x(), m10 = -c1.y(), m11 = 1 - c2.y();
  const std::int64_t det = m00 * m11 - m01 * m10;
  const auto& t = holonomy.translation;
  // z = adj(M) t / det, scaled to fixed-point units (det divides kUnit).
  return {(m11 * t.x() - m01 * t.y()) * (kUnit / det), (-m10 * t.x() + m00 * t.y()) * (kUnit / det)};
}

}  // namespace hexcover::extract_detail
