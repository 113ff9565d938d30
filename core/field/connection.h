#pragma once
// Internal to core/field: the geometry-aware connection of Ray et al. (paper section 3.2).
//
// The field solve transports directions across edge e by ρ_e + c_e instead of ρ_e. The
// corrections c (#E) are the smallest (Σ c_e² minimal) whose holonomy around every interior vertex
// turns the angle defect K_v into a target K̄_v:  Σ_e s_{v,e} c_e = K̄_v − K_v  (signs s as in
// rosy_field.h). A field that is parallel for the corrected transport then has, by the index
// formula of rosy_field.h, index N K̄_v / 2π at v: singularities appear only where K̄ accumulates
// multiples of 2π/N. With A the #constrained × #free-edges signed incidence matrix,
// c = Aᵀ (A Aᵀ)⁻¹ b, and A Aᵀ is the combinatorial graph Laplacian of the constrained vertices
// (Dirichlet at the others; a group without any pins one vertex, whose row is implied by Σ b = 0
// there). The initial solve constrains every interior vertex through every interior edge; the
// clustering re-solve constrains the vertices of the region R through the edges inside R.

#include <vector>

#include "core/common/sparse_cholesky.h"
#include "core/field/singularities.h"

namespace hexcover::field {

/// K̄: the angle defects of the interior vertices smoothed by `steps` steps of the conservative
/// lazy random-walk diffusion K'_v = K_v / 2 + Σ_{w~v} K_w / (2 deg w) over the interior vertices
/// (Σ K̄ = Σ K on every component; boundary vertices get 0). #V values, the same for any number
/// of threads.
std::vector<double> filterGaussCurvature(const TriMesh& mesh, const FieldGeometry& geometry,
                                         int steps, int threads = 1);

/// Number of diffusion steps for a filter radius (spread of the random walk ≈ ℓ̄ √(steps / 2)),
/// capped at 400.
int filterSteps(const TriMesh& mesh, double radius);

/// Prefactored minimal-norm corrections for any target curvature K̄ at a fixed set of vertices,
/// changing a fixed set of edges.
class ConnectionCorrector {
 public:
  /// `constrained` (#V): the vertices whose holonomy is prescribed (never boundary vertices);
  /// `freeEdges` (#E): the interior edges whose correction may change. A connected group of
  /// constrained vertices (through free edges) without a free edge to an unconstrained vertex
  /// pins its lowest vertex: its row is implied by the others when Σ_v (K̄_v − holonomy_v) = 0
  /// over the group (Poincaré–Hopf for the group), and absorbs the mismatch otherwise.
  /// `vertexOrder` (#V, optional): the vertices in a fill-reducing elimination order of the
  /// mesh's vertex graph (vertexGraphOrder), shared by several correctors.
  ConnectionCorrector(const TriMesh& mesh, const FieldGeometry& geometry,
                      const std::vector<bool>& constrained, const std::vector<bool>& freeEdges,
                      const std::vector<int>& vertexOrder = {});

  /// #E corrections c = base + Δ, with Δ supported on the free edges and the smallest that
  /// makes the holonomy of ρ + c at every constrained vertex equal to target[v] (#V). `base` is
  /// #E (empty: zero). Throws Error(NumericalFailure) if the factorization failed.
  std::vector<double> corrections(const std::vector<double>& target,
                                  const std::vector<double>& base = {}) const;

  /// Holonomy K_v + Σ_e s_{v,e} c_e of the transport ρ + c around every vertex (#V).
  std::vector<double> holonomy(const std::vector<double>& c) const;

 private:
  const TriMesh& mesh_;
  const FieldGeometry& geometry_;
  std::vector<bool> freeEdge_;
  std::vector<int> row_;  ///< #V row in the system, -1 for unconstrained and pinned vertices
  SparseCholesky<double> solver_;
};

/// The vertices in the minimum-degree elimination order of the mesh's vertex graph (see
/// sparse_cholesky.h).
std::vector<int> vertexGraphOrder(const TriMesh& mesh);

/// #V: true at the interior vertices (the constraints of the initial solve).
std::vector<bool> interiorVertices(const TriMesh& mesh);

/// #E: true at the interior edges (the free edges of the initial solve).
std::vector<bool> interiorEdges(const TriMesh& mesh);

}  // namespace hexcover::field
