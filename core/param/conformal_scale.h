#pragma once
// The scale that makes an N-RoSy field as integrable as it can be (local step, paper sec. 4.3).
//
// Energy (4) asks ∇u ≈ F_u and ∇v ≈ R_4 F_u; the paper leaves the length of F_u free. With unit
// F_u, a field that turns relative to parallel transport (wherever the Gauss curvature is not
// concentrated at the singularities) has curl, and the minimizer absorbs it by anisotropic
// stretch: triangles of the remesh lose their angles. A conformal map has Jacobian e^φ R(−θ),
// and log f' = φ − iθ is holomorphic, so the field angle θ and the log-scale φ satisfy the
// Cauchy–Riemann equation ∇φ = J ∇θ (J: rotation by +90° about the normal, θ measured against
// parallel transport). Scaling F_u by e^φ with the least-squares φ removes all the curl that a
// scale can remove; what remains is the field's own twist.
//
// Discretely, with θ per face and δ_e the field's turn across edge e relative to transport (see
// core/field/rosy_field.h), the Cauchy–Riemann equation along the edge a→b (face f0 on its left)
// reads φ_b − φ_a = δ_e / w_e with the cotangent weight w_e = (cot α + cot β)/2 (the ratio of the
// dual to the primal edge length). Least squares Σ_e w_e (φ_b − φ_a − δ_e / w_e)² gives the
// cotangent-Laplace equation L φ = Dᵀ δ: at an interior vertex the right-hand side is
// 2π I_v / N − K_v, so φ is the log conformal factor of the flat metric with cones at the
// singularities (Δφ = K − curvature of the cones).

#include <vector>

#include "core/field/rosy_field.h"
#include "core/mesh/mesh.h"

namespace hexcover {

/// #F factors e^{φ_f} (φ_f: mean of the face's corner values), normalized per connected
/// component so that the area-weighted mean lattice unit Σ_f A_f e^{−φ_f} / Σ_f A_f is 1 (one
/// lattice unit is h on average), then clamped to [−maxLogGrowth, maxLogScale]: lattice units
/// from h·e^{−maxLogScale} to h·e^{maxLogGrowth}. Growth is bounded more tightly by default:
/// where Gauss curvature is not matched by singularities (a tip between them, a fold narrower
/// than d_sing) the scale would leave triangles up to e times the mean edge length, whose
/// distance from the input breaks the Hausdorff floor (max-planck at K = V/4: 1.22 → 0.97% with
/// growth bounded by e^0.5), while smaller triangles only cost vertices. Degenerate faces get 1.
/// Throws Error(InvalidOption) when the field is not one of this mesh.
std::vector<double> conformalFaceScale(const TriMesh& mesh, const RosyField& field,
                                       double maxLogScale = 1.0, double maxLogGrowth = 0.5);

/// Σ_f A_f s_f² / Σ_f A_f: a lattice scaled by faceScale has this many times the vertices of
/// a uniform one with the same h (so h·sqrt(factor) keeps the vertex count).
double conformalVertexCountFactor(const TriMesh& mesh, const std::vector<double>& faceScale);

}  // namespace hexcover
