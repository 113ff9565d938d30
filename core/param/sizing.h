#pragma once
// Sizing of a parameterization (hexcover.h): the edge length h for a target vertex count, and
// curvature-adaptive per-vertex sizing (ParamOptions::vertexSizing).

#include <vector>

#include "core/mesh/mesh.h"

namespace hexcover {

/// h such that a lattice of order n with sizing `vertexSizing` (#V, empty = uniform) covers the
/// mesh with about K vertices: a regular triangulation has 2 triangles per vertex of area
/// √3/4·(h/s)², so h = sqrt(2·Σ_f A_f s_f² / (√3·K)) for N = 6 (one square of area (h/s)² per
/// vertex for N = 4). Throws Error(InvalidOption) for K < 1.
double edgeLengthForVertexCount(const TriMesh& mesh, int targetVertices, int n,
                                const std::vector<double>& vertexSizing = {});

/// Curvature-adaptive sizing (paper Fig. 13): s_v = κ(v) / median κ, clamped to
/// [minScale, maxScale]; a lattice unit near v is h / s_v. `absMaxCurvature` is #V, ≥ 0: the
/// largest absolute principal curvature κ = max(|κ1|, |κ2|) (Curvature::largestAbsolute).
/// Throws Error(InvalidOption) for an empty input or a range with minScale ≤ 0 or > maxScale.
std::vector<double> curvatureSizing(const std::vector<double>& absMaxCurvature,
                                    double minScale = 0.5, double maxScale = 2.0);

/// Smooths a per-vertex sizing (#V, > 0) over about `radius` (model units): log s diffuses by
/// (I + (radius/ℓ)² L) log s' = log s, with L the graph Laplacian and ℓ the mean edge length.
/// Sizing that varies faster than the field can follow creates curl, which the parameterization
/// turns into anisotropy (curvature sizing as computed: angle SD 10-12° on spot and bunny_7k;
/// smoothed over ~5 edge lengths: 6-7°). Values stay within the input's range (the system is an
/// M-matrix). Throws Error(InvalidOption) for a wrong-sized or non-positive sizing.
std::vector<double> smoothSizing(const TriMesh& mesh, const std::vector<double>& sizing,
                                 double radius);

/// The radius of smoothSizing for curvature sizing, in uniform edge lengths (pipeline and CLI).
inline constexpr double kSizingSmoothingInEdges = 5.0;

}  // namespace hexcover
