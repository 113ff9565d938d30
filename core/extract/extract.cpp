#include "core/extract/extract.h"

#include <algorithm>
#include <optional>
#include <string>

#include "core/common/error.h"
#include "core/extract/assembly.h"
#include "core/extract/boundary.h"
#include "core/extract/front_stitching.h"
#include "core/extract/lattice_extractor.h"
#include "core/extract/quad_mesh.h"
#include "core/extract/surface_fit.h"
#include "core/geometry/closest_point.h"

namespace hexcover {

using namespace extract_detail;

void ExtractOptions::validate() const {
  if (!(boundarySnapDistance > 0.0 && boundarySnapDistance < 1.0))
    throw Error(ErrorCode::InvalidOption, "boundarySnapDistance must be in (0, 1), got " +
                                              std::to_string(boundarySnapDistance));
  if (!(sharpBoundaryAngle >= 0.0 && sharpBoundaryAngle <= 180.0))
    throw Error(ErrorCode::InvalidOption, "sharpBoundaryAngle must be in [0, 180] degrees, got " +
                                              std::to_string(sharpBoundaryAngle));
  if (!(featureSnapDistance >= 0.0 && featureSnapDistance < 1.0))
    throw Error(ErrorCode::InvalidOption, "featureSnapDistance must be in [0, 1), got " +
                                              std::to_string(featureSnapDistance));
  if (!(sliverAngle >= 0.0 && sliverAngle < 60.0))
    throw Error(ErrorCode::InvalidOption,
                "sliverAngle must be in [0, 60) degrees, got " + std::to_string(sliverAngle));
  if (!(obtuseAngle > 60.0 && obtuseAngle <= 180.0))
    throw Error(ErrorCode::InvalidOption,
                "obtuseAngle must be in (60, 180] degrees, got " + std::to_string(obtuseAngle));
  if (!(creaseAngle >= 0.0 && creaseAngle <= 180.0))
    throw Error(ErrorCode::InvalidOption,
                "creaseAngle must be in [0, 180] degrees, got " + std::to_string(creaseAngle));
  if (threads < 1)
    throw Error(ErrorCode::InvalidOption,
                "threads must be at least 1, got " + std::to_string(threads));
}

namespace {

/// Largest distance of a triangle's centroid from the surface that `input` queries.
double farthestCentroid(const TriMesh& mesh, const ClosestPointQuery& input) {
  double farthest = 0.0;
  for (const auto f : mesh.faces()) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto v : f.vertices()) centroid += toEigen(mesh.point(v)) / 3.0;
    farthest = std::max(farthest, input.closest(centroid).distance);
  }
  return farthest;
}

/// Connected components of faces (through edges), numbered in order of their lowest face.
std::vector<int> faceComponents(const TriMesh& mesh, int& count) {
  std::vector<int> component(mesh.n_faces(), -1);
  count = 0;
  std::vector<TriMesh::FaceHandle> stack;
  for (const auto seed : mesh.faces()) {
    if (component[seed.idx()] >= 0) continue;
    component[seed.idx()] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const TriMesh::FaceHandle f = stack.back();
      stack.pop_back();
      for (const auto g : mesh.ff_range(f))
        if (component[g.idx()] < 0) component[g.idx()] = count, stack.push_back(g);
    }
    ++count;
  }
  return component;
}

}  // namespace

Remesh extractRemesh(const TriMesh& mesh, const Parameterization& param,
                     const ExtractOptions& options, const RunContext& context,
                     const TriMesh* given) {
  options.validate();
  if (param.n != 6 && param.n != 4)
    throw Error(ErrorCode::InvalidOption,
                "extraction supports the Eisenstein (N = 6) and Gauss (N = 4) lattices; got N = " +
                    std::to_string(param.n));
  if (param.cornerCoords.size() != mesh.n_halfedges() || param.edgeTransition.size() != mesh.n_edges())
    throw Error(ErrorCode::InvalidOption,
                "the parameterization does not belong to this mesh (" +
                    std::to_string(param.cornerCoords.size()) + " corner coordinates for " +
                    std::to_string(mesh.n_halfedges()) + " halfedges)");
  if (given && given->n_vertices() > mesh.n_vertices())
    throw Error(ErrorCode::InvalidOption,
                "the given input has more vertices (" + std::to_string(given->n_vertices()) +
                    ") than the mesh that refines it (" + std::to_string(mesh.n_vertices()) + ")");
  Remesh result;
  ExtractionReport& report = result.report;
  int componentCount = 0;
  const std::vector<int> faceComponent = faceComponents(mesh, componentCount);
  report.components = componentCount;
  const bool quads = param.n == 4;
  Assembly out;
  extractLattice(mesh, param, faceComponent, out, report, context);
  std::vector<TriMesh::VertexHandle> vertexOf;
  std::vector<Eigen::Vector3d> unfitted;  // N = 4: vertex positions before the fit
  std::vector<int> partner;               // N = 4: squarePartners
  std::vector<char> copied;  // per vertex of result.triangles: of a component copied (step 6)
  // Closest points on the input, built when first needed (a strip's split, the fit; then the quad
  // steps and the report's farthest centroid): built before the boundary step, it took the
  // 1.1M-face bunny's peak from 3361 to 4285 MiB.
  std::optional<ClosestPointQuery> inputQuery;
  {
    ScopedTimer timer(report.timings, "repair and boundary");
    context.report(stage::kExtraction, 0.7);
    context.throwIfCanceled();
    dropDegenerateAndOverlapping(out.triangles, report);
    if (componentCount > 0)
      closeBoundaries(mesh, options.fitToSurface ? &inputQuery : nullptr, faceComponent, options,
                      out, report);
    repairNonManifold(out, report);
    // Two copies of one lattice point merge into a cone of the triangle lattice (valence 4).
    if (!quads) report.latticePointCopiesMerged = collapseLatticePointCopies(out);
    const std::size_t remeshedVertices = out.positions.size();  // then the copied components'
    keepComponentsTooSmallForTheLattice(mesh, given ? *given : mesh, faceComponent, componentCount,
                                        options, out, report);
    result.triangles = buildMesh(out, report, vertexOf);
    copied.assign(result.triangles.n_vertices(), 0);
    for (std::size_t v = remeshedVertices; v < vertexOf.size(); ++v)
      if (vertexOf[v].is_valid()) copied[vertexOf[v].idx()] = 1;
    if (quads) {
      partner = squarePartners(result.triangles, out.squares, vertexOf);
      // A component copied unchanged keeps its triangles.
      for (const auto v : result.triangles.vertices())
        if (copied[v.idx()])
          for (const auto f : v.faces()) partner[f.idx()] = kKeptAsIs;
      report.mergedTrianglePairs = pairTriangles(result.triangles, partner);
    }
  }
  // Copied components keep their vertices and triangles through steps 7 and 8; a remesh made
  // only of them skips both, and so does, when asked, one whose lattice missed a component's
  // topology (the pipeline redoes it: the fit of 60 spheres' lattices that folded on the small
  // ones took 4-6 s per run).
  const bool onlyCopies = componentCount > 0 && report.componentsKept == componentCount;
  // (A remesh made only of copies is finished as it is: extracting it again would change nothing.)
  report.unfinished =
      !onlyCopies && !options.finishOtherTopology && report.componentsKeptForTopology > 0;
  if (!onlyCopies && !report.unfinished) {
    ScopedTimer timer(report.timings, "surface fit");
    context.report(stage::kExtraction, 0.8);
    context.throwIfCanceled();
    if (options.fitToSurface && result.triangles.n_faces() > 0) {
      if (!inputQuery) inputQuery.emplace(mesh);
      if (quads)
        for (const auto v : result.triangles.vertices())
          unfitted.push_back(toEigen(result.triangles.point(v)));
      SurfaceFitOptions fitOptions;
      fitOptions.featureSnapDistance = options.featureSnapDistance;
      fitOptions.creaseAngle = options.creaseAngle;
      fitOptions.balanceDeviation = options.balanceDeviation;
      fitOptions.threads = options.threads;
      const auto counts =
          fitRemeshToSurface(mesh, *inputQuery, result.triangles, fitOptions, partner, copied);
      report.featureSnaps = counts.snapped;
      report.smoothedVertices = counts.smoothed;
      report.relaxedVertices = counts.relaxed;
      report.balancedVertices = counts.balanced;
      report.outlierAngleMoves = counts.outliers;
    }
    // N = 4: after the quads' corners are mended (repairSliversBesideSquares).
    if (options.sliverAngle > 0.0 && !quads) {
      OpenMesh::FPropHandleT<bool> copiedFace;
      result.triangles.add_property(copiedFace);
      for (const auto f : result.triangles.faces())
        result.triangles.property(copiedFace, f) = copied[f.halfedge().to().idx()];
      const SliverRepairs done =
          repairBoundarySlivers(result.triangles, options.sliverAngle, options.obtuseAngle,
                                options.sharpBoundaryAngle, copiedFace);
      result.triangles.remove_property(copiedFace);
      report.boundarySliverCollapses = done.collapses;
      report.boundarySliverFlips = done.flips;
    }
  }
  if (quads) {
    if (!unfitted.empty()) {
      result.quads = pairSquares(result.triangles, partner);
      report.restoredVertices = restoreQuadCorners(result.quads, result.triangles, unfitted);
      report.centredVertices =
          centreIrregularVertices(result.quads, result.triangles, *inputQuery, copied);
    }
    if (options.sliverAngle > 0.0 && !onlyCopies && !report.unfinished) {
      const SliverRepairs done =
          repairSliversBesideSquares(result.triangles, partner, options.sliverAngle,
                                     options.obtuseAngle, options.sharpBoundaryAngle);
      report.boundarySliverCollapses = done.collapses;
      report.boundarySliverFlips = done.flips;
    }
    // Pairs that the fit and the repairs made square enough.
    report.mergedTrianglePairs += pairTriangles(result.triangles, partner);
    result.quads = pairSquares(result.triangles, partner);
  }
  if (inputQuery && !onlyCopies && !report.unfinished)
    report.farthestCentroid = farthestCentroid(result.triangles, *inputQuery);
  if (!quads) {
    ScopedTimer timer(report.timings, "hexagonal dual");
    context.report(stage::kExtraction, 0.9);
    result.hexDual = hexagonalDual(result.triangles);
  }
  context.report(stage::kExtraction, 1.0);
  return result;
}

}  // namespace hexcover
