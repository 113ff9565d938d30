// Surface distances (core/metrics/hausdorff.h, measureQuality with a reference) on shapes whose
// Hausdorff distance is known in closed form.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <tuple>

#include "core/common/error.h"
#include "core/mesh/load.h"
#include "core/mesh/primitives.h"
#include "core/metrics/metrics.h"
#include "tests/common/test_meshes.h"

namespace hexcover {
namespace {

TriMesh scaled(TriMesh mesh, double factor) {
  for (const auto vh : mesh.vertices()) mesh.set_point(vh, factor * mesh.point(vh));
  return mesh;
}

/// Planar n × n vertex grid over [0, 1]² in z = 0, quads split along one diagonal.
TriMesh unitSquare(int n) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> v;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      v.push_back(mesh.add_vertex({double(i) / (n - 1), double(j) / (n - 1), 0.0}));
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const auto a = v[j * n + i], b = v[j * n + i + 1], c = v[(j + 1) * n + i + 1],
                 d = v[(j + 1) * n + i];
      mesh.add_face(a, b, c);
      mesh.add_face(a, c, d);
    }
  return mesh;
}

TEST(MetricsDistance, SphereAgainstOnePercentLargerCopyIsOnePercentOfTheRadius) {
  const double radius = 2.0;
  const TriMesh sphere = makeIcosphere(4, radius);
  const TriMesh larger = scaled(sphere, 1.01);
  const QualityReport q = measureQuality(larger, &sphere);
  ASSERT_TRUE(q.distance.has_value());
  const double expectedPct = 100.0 * 0.01 * radius / boundingBoxDiagonal(sphere);
  EXPECT_NEAR(q.distance->hausdorffPct, expectedPct, 0.01 * expectedPct);
  EXPECT_TRUE(q.distance->hausdorffCertified);
  EXPECT_GE(q.distance->hausdorffUpperBoundPct, q.distance->hausdorffPct);
  // Faces of the larger copy are at 1.01·h from the centre, h ≤ R: the mean lies just below 1%.
  EXPECT_LT(q.distance->meanPct, expectedPct);
  EXPECT_GT(q.distance->meanPct, 0.98 * expectedPct);
  EXPECT_GE(q.distance->rmsPct, q.distance->meanPct);
  EXPECT_TRUE(*q.topologyMatchesReference);
}

TEST(MetricsDistance, MeshAgainstItselfIsZero) {
  const TriMesh torus = makeTorus(2.0, 0.7, 40, 16);
  const QualityReport q = measureQuality(torus, &torus);
  ASSERT_TRUE(q.distance.has_value());
  EXPECT_LT(q.distance->hausdorffPct, 1e-9);
  EXPECT_LT(q.distance->hausdorffUpperBoundPct, 1e-6);
  EXPECT_LT(q.distance->meanPct, 1e-9);
  EXPECT_TRUE(q.distance->hausdorffCertified);
  EXPECT_TRUE(*q.topologyMatchesReference);
}

TEST(MetricsDistance, LiftedVertexGivesTheLiftHeightExactly) {
  const TriMesh flat = unitSquare(5);
  TriMesh lifted = flat;
  const double d = 0.07;
  const auto center = TriMesh::VertexHandle(2 * 5 + 2);
  lifted.set_point(center, lifted.point(center) + TriMesh::Point(0, 0, d));
  const QualityReport q = measureQuality(lifted, &flat);
  const double pct = 100.0 / boundingBoxDiagonal(flat);
  EXPECT_NEAR(q.distance->hausdorffPct, pct * d, 1e-12);
  EXPECT_NEAR(q.distance->resultToReferenceMaxPct, pct * d, 1e-12);  // the lifted vertex
  // Every point of the flat square is closer to the bump than its height.
  EXPECT_LT(q.distance->referenceToResultMaxPct, pct * d);
  EXPECT_GT(q.distance->referenceToResultMaxPct, 0.5 * pct * d);
  EXPECT_TRUE(q.distance->hausdorffCertified);
}

TEST(MetricsDistance, PeakInsideAFaceIsFoundByRefinement) {
  // Flat equilateral triangle (split in two through a point that is not the centroid) against a
  // tent over the same triangle with its apex at height h above the centroid c. The distance from
  // the flat surface to the tent peaks at c, at r·h/√(r² + h²) (r: inradius), where no initial
  // sample lies.
  const double edge = 1.0, h = 0.2;
  const Eigen::Vector3d v0(0, 0, 0), v1(edge, 0, 0), v2(0.5 * edge, 0.5 * std::sqrt(3.0) * edge, 0);
  const Eigen::Vector3d c = (v0 + v1 + v2) / 3.0;
  const Eigen::Vector3d s = v1 + 0.3 * (v2 - v1);
  TriMesh flat;
  {
    const auto a = flat.add_vertex(toOpenMesh(v0)), b = flat.add_vertex(toOpenMesh(v1)),
               m = flat.add_vertex(toOpenMesh(s)), d = flat.add_vertex(toOpenMesh(v2));
    flat.add_face(a, b, m);
    flat.add_face(a, m, d);
  }
  TriMesh tent;
  {
    const auto a = tent.add_vertex(toOpenMesh(v0)), b = tent.add_vertex(toOpenMesh(v1)),
               d = tent.add_vertex(toOpenMesh(v2)),
               apex = tent.add_vertex(toOpenMesh(c + Eigen::Vector3d(0, 0, h)));
    tent.add_face(a, b, apex);
    tent.add_face(b, d, apex);
    tent.add_face(d, a, apex);
  }
  const double r = edge / (2.0 * std::sqrt(3.0));
  const double expected = r * h / std::sqrt(r * r + h * h);

  DistanceOptions options;
  options.minSamples = 1;  // only vertices and face centroids before refinement
  const ClosestPointQuery toTent(tent);
  const OneSidedDistance d = oneSidedDistance(flat, toTent, options);
  EXPECT_GT(d.refinementRounds, 0);
  EXPECT_NEAR(d.max, expected, 0.01 * expected);
  EXPECT_LE(d.max, expected * (1.0 + 1e-12));  // a sampled value never exceeds the supremum
  EXPECT_GE(d.maxUpperBound, expected * (1.0 - 1e-12));  // the bound is a true upper bound
  EXPECT_TRUE(d.certified);
  EXPECT_LT((d.farthestPoint - c).norm(), 0.05 * edge);

  // With a loose tolerance the samples miss the peak by more than 1%, yet the bound still holds.
  DistanceOptions loose = options;
  loose.relativeTolerance = 0.5;
  const OneSidedDistance rough = oneSidedDistance(flat, toTent, loose);
  EXPECT_LT(rough.max, 0.99 * expected);
  EXPECT_GE(rough.maxUpperBound, expected);
  EXPECT_LE(rough.maxUpperBound, 1.5 * rough.max);  // certified to the loose tolerance

  // Without room for refinement the result says it is not certified, and the bound still holds.
  DistanceOptions tight = options;
  tight.maxSamples = 10;  // the 4 vertices and 2 centroids leave no room for a split
  const OneSidedDistance capped = oneSidedDistance(flat, toTent, tight);
  EXPECT_EQ(capped.refinementRounds, 0);
  EXPECT_FALSE(capped.certified);
  EXPECT_GE(capped.maxUpperBound, expected);

  // The tent's apex is at height h above the flat triangle.
  const ClosestPointQuery toFlat(flat);
  EXPECT_NEAR(oneSidedDistance(tent, toFlat, options).max, h, 1e-12);
}

TEST(MetricsDistance, ClosestPointMatchesBruteForce) {
  const TriMesh torus = makeTorus(2.0, 0.6, 24, 10);
  const ClosestPointQuery query(torus);
  for (int k = 0; k < 200; ++k) {
    // Deterministic points spread through and around the torus.
    const double t = 0.1 * k;
    const Eigen::Vector3d p(3.0 * std::sin(1.3 * t), 3.0 * std::cos(0.7 * t), std::sin(2.9 * t));
    double brute = std::numeric_limits<double>::infinity();
    for (const auto fh : torus.faces()) brute = std::min(brute, query.distanceToFace(p, fh.idx()));
    const auto result = query.closest(p);
    EXPECT_NEAR(result.distance, brute, 1e-12);
    EXPECT_NEAR((result.point - p).norm(), brute, 1e-12);
    // A hint, good or bad, does not change the answer.
    EXPECT_NEAR(query.closest(p, k % static_cast<int>(torus.n_faces())).distance, brute, 1e-12);
  }
}

// Above a vertex of a flat grid its six triangles are exactly as close, and so are their planes
// (a plane test that culled ties would keep the hint): the lowest face index wins, whatever the
// hint. Outside a box's corner, the triangles around it tie at the corner across three planes:
// the result is brute force's lowest index.
TEST(MetricsDistance, ClosestPointTiesGoToTheLowestFaceIndex) {
  const TriMesh grid = makeEquilateralGrid(6, 6);
  const ClosestPointQuery query(grid);
  for (const auto vh : grid.vertices()) {
    if (grid.is_boundary(vh)) continue;
    int lowest = std::numeric_limits<int>::max();
    for (const auto fh : vh.faces()) lowest = std::min(lowest, fh.idx());
    const Eigen::Vector3d p = toEigen(grid.point(vh)) + Eigen::Vector3d(0.0, 0.0, 0.3);
    for (const auto hint : vh.faces()) {
      const auto result = query.closest(p, hint.idx());
      EXPECT_EQ(result.face, lowest) << "vertex " << vh.idx() << " hint " << hint.idx();
      EXPECT_EQ(result.distance, 0.3);
    }
  }
  const TriMesh box = makeBox(1.0, 1.0, 1.0, 3);
  const ClosestPointQuery toBox(box);
  for (const auto vh : box.vertices()) {
    const Eigen::Vector3d corner = toEigen(box.point(vh));
    if (corner.cwiseAbs().minCoeff() < 0.49) continue;  // not a corner of [-0.5, 0.5]³
    const Eigen::Vector3d p = 1.2 * corner;             // outside, nearest to the corner
    double brute = std::numeric_limits<double>::infinity();
    int face = -1;
    for (const auto fh : box.faces())
      if (const double d = toBox.distanceToFace(p, fh.idx()); d < brute) brute = d, face = fh.idx();
    const auto result = toBox.closest(p);
    EXPECT_EQ(result.distance, brute);
    EXPECT_EQ(result.face, face);
  }
}

// A georeferenced scan lies ~10^6 units from the origin, where float coordinates (the BVH's) round
// by 0.25 units: the BVH works relative to the mesh's centre, so a query stays local there
// (relative to the origin, every query would visit all 5120 triangles; here as many as at the
// origin).
TEST(MetricsDistance, ClosestPointFarFromTheOriginIsExactAndLocal) {
  const TriMesh sphere = makeIcosphere(4);
  const Eigen::Vector3d offset(5.0e5, 4.0e6, 120.0);
  TriMesh far = sphere;
  for (const auto vh : far.vertices()) far.set_point(vh, far.point(vh) + toOpenMesh(offset));
  const ClosestPointQuery nearQuery(sphere), farQuery(far);
  for (int k = 0; k < 50; ++k) {
    const double t = 0.37 * k;
    const Eigen::Vector3d p(1.1 * std::sin(1.3 * t), 0.9 * std::cos(0.7 * t), std::sin(2.9 * t));
    const auto expected = nearQuery.closest(p);
    const auto result = farQuery.closest(p + offset);
    EXPECT_NEAR(result.distance, expected.distance, 1e-8);
    EXPECT_LE(result.visited, 2 * expected.visited + 8) << "query " << k;
  }
}

/// n × n vertex grid over [0, 1]² at pseudo-random heights in [0, amplitude): every edge is a
/// crease, at angles that differ from edge to edge.
TriMesh creasedSheet(int n, double amplitude, double seed) {
  TriMesh mesh = unitSquare(n);
  for (const auto vh : mesh.vertices()) {
    const auto p = mesh.point(vh);
    const double hash = std::sin(127.1 * p[0] + 311.7 * p[1] + seed) * 43758.5453;
    mesh.set_point(vh, {p[0], p[1], amplitude * (hash - std::floor(hash))});
  }
  return mesh;
}

/// Largest distance to `to` over a barycentric grid of `divisions` steps on every face of `from`:
/// a lower bound of the supremum.
double denselySampledMax(const TriMesh& from, const ClosestPointQuery& to, int divisions) {
  double largest = 0.0;
  for (const auto fh : from.faces()) {
    std::array<Eigen::Vector3d, 3> corner;
    int k = 0;
    for (const auto vh : from.fv_range(fh)) corner[k++] = toEigen(from.point(vh));
    for (int i = 0; i <= divisions; ++i)
      for (int j = 0; i + j <= divisions; ++j) {
        const Eigen::Vector3d p = corner[0] + (corner[1] - corner[0]) * i / divisions +
                                  (corner[2] - corner[0]) * j / divisions;
        largest = std::max(largest, to.closest(p).distance);
      }
  }
  return largest;
}

TEST(MetricsDistance, BoundsHoldBetweenCreasedSurfaces) {
  // Cells whose corners are closest to different triangles are bounded piece by piece, the
  // pieces cut by planes through the triangles' shared edge or vertex. Every edge of these sheets
  // is a crease, so pieces that missed part of their cell, or a distance taken to another
  // triangle than the piece's, would undercut the true supremum (both checked to fail here).
  const TriMesh coarse = creasedSheet(6, 0.12, 0.0), fine = creasedSheet(17, 0.05, 1.0);
  const ClosestPointQuery toCoarse(coarse), toFine(fine);
  for (const double tolerance : {0.005, 0.3}) {
    DistanceOptions options;
    options.minSamples = 1;
    options.relativeTolerance = tolerance;
    for (const auto& [from, to, name] :
         {std::tuple{&coarse, &toFine, "coarse to fine"}, {&fine, &toCoarse, "fine to coarse"}}) {
      const OneSidedDistance d = oneSidedDistance(*from, *to, options);
      const double dense = denselySampledMax(*from, *to, 24);
      EXPECT_TRUE(d.certified) << name;
      EXPECT_GE(d.maxUpperBound, dense * (1.0 - 1e-12)) << name << ", tolerance " << tolerance;
      EXPECT_GE(d.max * (1.0 + tolerance), dense * (1.0 - 1e-12)) << name;
    }
  }
}

TEST(MetricsDistance, CloseSmoothSurfacesAreCertifiedWithinTheBudget) {
  // Two approximations of one sphere, turned against each other, are close everywhere, so
  // nearly every cell's bound must come near the maximum. Bounded by one triangle, a cell's
  // bound overshoots by its reach past that triangle's edges times their dihedral angle, and the
  // budget was spent with bounds 4 times the maximum; cut along the edges it is exact.
  TriMesh coarse = makeIcosphere(4);
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  for (const auto vh : coarse.vertices())
    coarse.set_point(vh, toOpenMesh(turn * toEigen(coarse.point(vh))));
  const TriMesh fine = makeIcosphere(5);
  const TwoSidedDistance d = twoSidedDistance(coarse, fine);
  const DistanceOptions defaults;
  for (const OneSidedDistance* side : {&d.aToB, &d.bToA}) {
    EXPECT_TRUE(side->certified);  // before the budget of samples was spent
  }
  EXPECT_GT(d.hausdorff(), 0.0);
  EXPECT_LE(d.hausdorffUpperBound(), d.hausdorff() * (1.0 + defaults.relativeTolerance));
}

TEST(MetricsDistance, ResultsDoNotDependOnThreadCount) {
  const TriMesh sphere = makeIcosphere(4);
  TriMesh bumpy = sphere;
  for (const auto vh : bumpy.vertices()) {
    const auto p = bumpy.point(vh);
    bumpy.set_point(vh, p * (1.0 + 0.02 * std::sin(5 * p[0]) * std::cos(3 * p[1])));
  }
  DistanceOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const TwoSidedDistance a = twoSidedDistance(bumpy, sphere, one);
  const TwoSidedDistance b = twoSidedDistance(bumpy, sphere, two);
  EXPECT_EQ(a.hausdorff(), b.hausdorff());
  EXPECT_EQ(a.mean(), b.mean());
  EXPECT_EQ(a.aToB.samples, b.aToB.samples);
}

TEST(MetricsDistance, TopologyMismatchIsReported) {
  const TriMesh sphere = makeIcosphere(2);
  const TriMesh torus = makeTorus(1.0, 0.3, 20, 10);
  const QualityReport q = measureQuality(torus, &sphere);
  ASSERT_TRUE(q.topologyMatchesReference.has_value());
  EXPECT_FALSE(*q.topologyMatchesReference);
}

TEST(MetricsDistance, RefusesNonFiniteCoordinatesWithTheVertex) {
  const TriMesh sphere = makeIcosphere(1);
  TriMesh broken = sphere;
  broken.set_point(TriMesh::VertexHandle(7), {0.0, std::nan(""), 0.0});
  try {
    measureQuality(sphere, &broken);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidMesh);
    EXPECT_NE(std::string(e.what()).find("vertex 7"), std::string::npos) << e.what();
  }
}

TEST(MetricsDistance, RejectsBadOptions) {
  MetricsOptions options;
  options.distance.relativeTolerance = 0.0;
  const TriMesh sphere = makeIcosphere(1);
  try {
    measureQuality(sphere, &sphere, options);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidOption);
    EXPECT_NE(std::string(e.what()).find("relativeTolerance"), std::string::npos);
  }
}

TEST(MetricsDistance, SharedBunnyAgainstItselfIsZero) {
  HEXCOVER_SHARED_MESH_OR_SKIP(path, "clean/bunny_7k.off");
  const TriMesh bunny = loadMesh(path);
  const QualityReport q = measureQuality(bunny, &bunny);
  EXPECT_LT(q.distance->hausdorffPct, 1e-9);
  EXPECT_LT(q.distance->meanPct, 1e-9);
  EXPECT_TRUE(q.distance->hausdorffCertified);
  EXPECT_EQ(q.topology.eulerCharacteristic, 2);  // shared/meshes/README: χ = 2, genus 0
  EXPECT_EQ(q.topology.genus(), 0);
  EXPECT_TRUE(*q.topologyMatchesReference);
}

TEST(MetricsDistance, SharedBunnyAgainstAShiftedCopyIsTheShift) {
  // A translation by t moves every point by |t|; a surface's distance to its translate is at
  // most |t| and equals it where the translate's normal is parallel to t on a flat enough patch,
  // so the two-sided Hausdorff distance lies just below |t|.
  HEXCOVER_SHARED_MESH_OR_SKIP(path, "clean/bunny_7k.off");
  const TriMesh bunny = loadMesh(path);
  const double diagonal = boundingBoxDiagonal(bunny);
  TriMesh shifted = bunny;
  const TriMesh::Point t(0.0, 0.0, 0.002 * diagonal);
  for (const auto vh : shifted.vertices()) shifted.set_point(vh, shifted.point(vh) + t);
  const QualityReport q = measureQuality(shifted, &bunny);
  EXPECT_LE(q.distance->hausdorffPct, 0.2 * (1.0 + 1e-9));
  EXPECT_GT(q.distance->hausdorffPct, 0.19);
  EXPECT_LT(q.distance->meanPct, q.distance->hausdorffPct);
  EXPECT_TRUE(q.distance->hausdorffCertified);
}

}  // namespace
}  // namespace hexcover
