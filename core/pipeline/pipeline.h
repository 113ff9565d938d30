#pragma once
// The one entry point of the geometry library (paper sections 3-5):
// repair -> 6-RoSy field -> HexCover parameterization -> extraction -> metrics.
// The server, the CLI and the tests all call remesh(); it knows nothing about jobs or HTTP.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/common/run_context.h"
#include "core/common/timings.h"
#include "core/extract/extract.h"
#include "core/field/rosy_field.h"
#include "core/mesh/mesh.h"
#include "core/mesh/report.h"
#include "core/metrics/metrics.h"
#include "core/param/hexcover.h"

namespace hexcover {

enum class Sizing { Uniform, Curvature };

/// Where the remesh's vertices go after extraction (core/extract's surface fit): Balanced moves
/// the vertices where the remesh deviates most off the input along their normal, so that the
/// remesh straddles the input (about half the two-sided distance on curved patches); OnSurface
/// keeps every vertex on the input (for attribute transfer, or a remesh that must interpolate).
enum class VertexPlacement { Balanced, OnSurface };

/// Largest vertex count a remesh may be asked for, as a target or through the edge length.
inline constexpr long long kMaxTargetVertices = 100'000'000;

struct RemeshOptions {
  /// Target edge length in model units. At most one of edgeLength and targetVertices is set;
  /// with neither, the target is a quarter of the input's vertex count.
  std::optional<double> edgeLength;
  /// Target number of output vertices (the result is within 10% of it, not counting the vertices
  /// of components too small for the lattice, which are kept as they are and come on top).
  std::optional<long long> targetVertices;
  /// 6: triangles (Eisenstein lattice); 4: quads (Gauss lattice).
  int rosy = 6;
  Sizing sizing = Sizing::Uniform;
  VertexPlacement placement = VertexPlacement::Balanced;
  /// Creases of at least this dihedral angle (degrees) on lines at least kCreaseLineInEdges
  /// edge lengths long are followed by the field and by lattice lines, so that rows of remesh
  /// edges lie on them (CAD models); 0 turns crease alignment off. In [0, 180].
  double featureAngle = kDefaultFeatureAngle;
  /// Singularity clustering distance d_sing in model units; by default
  /// kSingularityDistanceInEdges × the edge length (paper 5.2, see pipeline.cpp).
  std::optional<double> dSing;
  /// Inputs with more faces are refused (ErrorCode::LimitExceeded), and the refinement before the
  /// field (kInputEdgeInEdgeLengths) stops there.
  std::size_t maxFaces = 5'000'000;

  /// Throws Error(InvalidOption) naming the first bad option.
  void validate() const;
};

/// The peak memory of a remesh in MiB, estimated from the faces of the input that the field and
/// the parameterization work on (as repaired and refined) and the vertex target (the remesh's
/// size): about 3.5 KiB per input face, 1 KiB per remesh vertex and 50 MiB besides. Measured peaks
/// (resident, CLI) lie 0-14% below it: the Stanford bunny (69K faces) at K = 8.7K 262 MiB and at
/// K = 139K 300 MiB, feline (100K faces) at K = 12.5K 402 MiB, the icosphere refined for
/// K = 300K 448 MiB, the bunny subdivided to 1.1M faces at K = 139K 3505 MiB.
double estimatedPeakMemoryMiB(std::size_t faces, double remeshVertices);

/// Before the field, the repaired input's edges are split until none is longer than this many
/// uniform edge lengths h (refineLongEdges in core/mesh/refine.h; remesh and `hexcover param`).
/// Scanned meshes are finer: the clean test meshes'
/// longest edges are 0.6-3.0 h at a quarter of their vertices, and none is split.
inline constexpr double kInputEdgeInEdgeLengths = 4.0;
/// When the field keeps an interior singularity of an index above kMergedIndexForLattice, the
/// input is refined to edges of at most this many h and the field computed again. The centres of
/// a CAD cylinder's caps (fans of slivers) carry the smoothest field's +6/6, which the field can
/// split only onto vertices around them (splitHighOrderNodes in core/field/clustering.h).
inline constexpr double kCoarseInputEdgeInEdgeLengths = 1.0;
/// ... provided the lattice has this many vertices for each first-order singularity those would
/// be split into (12 on a cylinder: from K = 48).
inline constexpr double kLatticeVerticesPerSplitSingularity = 4.0;

/// About how many vertices a uniform lattice of edge length h has on `mesh`.
double latticeVertexCount(const TriMesh& mesh, double h);

/// True when `field` keeps an interior singularity of an index above kMergedIndexForLattice and
/// a lattice of `latticeVertices` vertices has kLatticeVerticesPerSplitSingularity of them for
/// each first-order singularity it would split into: its input is then refined to
/// kCoarseInputEdgeInEdgeLengths and the field computed again (remesh and `hexcover param`).
bool needsFinerInputForLattice(const RosyField& field, double latticeVertices);

struct RemeshResult {
  MeshReport inputReport;      ///< validation and repair of the input
  /// Edges of the repaired input split before the field (kInputEdgeInEdgeLengths).
  long long inputEdgesSplit = 0;
  double edgeLength = 0.0;           ///< h used for the final parameterization (model units)
  double singularityDistance = 0.0;  ///< d_sing used by the field's clustering (model units)
  int sizeIterations = 1;  ///< parameterization + extraction runs (to meet targetVertices, to
                           ///< keep the input's topology, and along a second field that follows
                           ///< only the creases a lattice can follow together)
  int flippedParamTriangles = 0;  ///< left in the final parameterization (see Parameterization)
  Remesh remesh;               ///< triangle mesh, hexagonal dual, extraction report
  PolygonSoup textured;        ///< the repaired (and refined) input with texture coordinates
  std::vector<Singularity> singularities;
  QualityReport metrics;       ///< the remesh measured against the repaired input (before
                               ///< the refinement, the same surface)
  Timings timings;             ///< per stage
  double peakMemoryMiB = 0.0;
  /// What a user may want to act on, one sentence each: input components copied unchanged,
  /// fold-overs the extraction had to fill, a part of the input lost by a lattice too coarse for
  /// it, a sliver or a triangle off the input that the runs could not avoid, a vertex count more
  /// than 10% off the target.
  std::vector<std::string> warnings;
};

/// Remeshes `input`. Throws Error: InvalidMesh/LimitExceeded for refused input, InvalidOption,
/// NumericalFailure, Canceled when context.cancelRequested() turned true.
RemeshResult remesh(const PolygonSoup& input, const RemeshOptions& options,
                    const RunContext& context = {});

}  // namespace hexcover
