// Curvature estimates against shapes with known curvature, and robustness on bad triangles.

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "core/common/error.h"
#include "core/geometry/curvature.h"
#include "core/geometry/frames.h"
#include "core/mesh/primitives.h"

namespace hexcover {
namespace {

double sum(const std::vector<double>& values) {
  return std::accumulate(values.begin(), values.end(), 0.0);
}

void expectAllFinite(const Curvature& c) {
  for (std::size_t v = 0; v < c.rho.size(); ++v) {
    ASSERT_TRUE(std::isfinite(c.kappaMax[v]) && std::isfinite(c.kappaMin[v])) << "vertex " << v;
    ASSERT_TRUE(c.directionMax[v].allFinite() && c.directionMin[v].allFinite()) << "vertex " << v;
    ASSERT_TRUE(std::isfinite(c.rho[v]) && std::isfinite(c.phi[v]) && std::isfinite(c.area[v]))
        << "vertex " << v;
    ASSERT_TRUE(std::isfinite(c.gauss[v])) << "vertex " << v;
    ASSERT_NEAR(c.directionMax[v].norm(), 1.0, 1e-9) << "vertex " << v;
  }
}

TEST(GeometryCurvature, SphereIsUmbilicWithCurvatureOneOverRadius) {
  const double radius = 2.0;
  const TriMesh sphere = makeIcosphere(4, radius);
  const Curvature c = computeCurvature(sphere);
  expectAllFinite(c);
  for (const auto vh : sphere.vertices()) {
    const int v = vh.idx();
    EXPECT_NEAR(c.kappaMax[v], 1.0 / radius, 1e-6) << "vertex " << v;  // exact: Max normals
    EXPECT_NEAR(c.kappaMin[v], 1.0 / radius, 1e-6) << "vertex " << v;
    EXPECT_EQ(c.classification[v], CurvatureClass::Elliptic);
    EXPECT_GT(c.normal[v].dot(toEigen(sphere.point(vh))), 0.0) << "normals point outwards";
  }
  EXPECT_NEAR(sum(c.gauss), 4.0 * M_PI, 1e-9);  // Gauss–Bonnet, χ = 2
  EXPECT_NEAR(sum(c.area), 4.0 * M_PI * radius * radius, 0.01 * 4.0 * M_PI * radius * radius);
}

TEST(GeometryCurvature, TubeBendsAroundItsCircumferenceAndIsCylindrical) {
  const double radius = 1.0;
  const TriMesh tube = makeTube(radius, 4.0, 48, 27);
  const Curvature c = computeCurvature(tube);
  expectAllFinite(c);
  int interior = 0;
  for (const auto vh : tube.vertices()) {
    // Boundary normals are one-sided; check from the second ring inwards (finite everywhere).
    const Eigen::Vector3d p = toEigen(tube.point(vh));
    if (p.z() < 0.3 || p.z() > 3.7) continue;
    ++interior;
    const int v = vh.idx();
    const Eigen::Vector3d around = Eigen::Vector3d(-p.y(), p.x(), 0.0).normalized();
    EXPECT_NEAR(c.kappaMax[v], 1.0 / radius, 1e-3) << "vertex " << v;
    EXPECT_NEAR(c.kappaMin[v], 0.0, 1e-3) << "vertex " << v;
    EXPECT_GT(std::abs(c.directionMax[v].dot(around)), std::cos(M_PI / 180.0)) << "vertex " << v;
    EXPECT_NEAR(c.phi[v], M_PI / 4.0, 0.03);
    EXPECT_EQ(c.classification[v], CurvatureClass::Cylindrical);
  }
  EXPECT_GT(interior, 0);
  EXPECT_NEAR(sum(c.gauss), 0.0, 1e-9);  // χ = 0, boundary turning included
}

TEST(GeometryCurvature, TorusHasTheAnalyticPrincipalCurvatures) {
  // Outer equator: κ = 1/r around the tube, 1/(R + r) along it (φ > 0, elliptic-ish);
  // inner equator: 1/r and −1/(R − r) (hyperbolic side).
  const double R = 3.0, r = 1.0;
  const TriMesh torus = makeTorus(R, r, 120, 40);
  const Curvature c = computeCurvature(torus);
  expectAllFinite(c);
  for (const auto vh : torus.vertices()) {
    const Eigen::Vector3d p = toEigen(torus.point(vh));
    const double ring = std::hypot(p.x(), p.y());
    const double cosB = (ring - R) / r;  // position around the tube
    const double kTube = 1.0 / r, kAlong = cosB / ring;
    const int v = vh.idx();
    EXPECT_NEAR(c.kappaMax[v], std::max(kTube, kAlong), 0.005) << "vertex " << v;
    EXPECT_NEAR(c.kappaMin[v], std::min(kTube, kAlong), 0.005) << "vertex " << v;
    const Eigen::Vector3d along = Eigen::Vector3d(-p.y(), p.x(), 0.0).normalized();
    EXPECT_LT(std::abs(c.directionMax[v].dot(along)), std::sin(M_PI / 360.0)) << "vertex " << v;
  }
  EXPECT_NEAR(sum(c.gauss), 0.0, 1e-9);
}

TEST(GeometryCurvature, StrongPointsCoverTheRequestedAreaFraction) {
  const TriMesh torus = makeTorus(3.0, 1.0, 60, 24);
  CurvatureOptions options;
  options.strongAreaFraction = 0.35;
  const Curvature c = computeCurvature(torus, options);
  double strong = 0.0, weakMax = 0.0, strongMin = 1e300;
  for (std::size_t v = 0; v < c.rho.size(); ++v) {
    if (c.strong[v]) {
      strong += c.area[v];
      strongMin = std::min(strongMin, c.rho[v]);
    } else {
      weakMax = std::max(weakMax, c.rho[v]);
    }
  }
  const double total = sum(c.area);
  EXPECT_GE(strong, 0.35 * total);
  EXPECT_LT(strong, 0.40 * total);
  EXPECT_LE(weakMax, strongMin) << "every strong point has larger ρ than every other point";
}

TEST(GeometryCurvature, FlatPatchIsPlanarAndBoundariesAreFinite) {
  const TriMesh grid = makeEquilateralGrid(8, 8);
  const Curvature c = computeCurvature(grid);
  expectAllFinite(c);
  for (std::size_t v = 0; v < c.rho.size(); ++v) {
    EXPECT_NEAR(c.rho[v], 0.0, 1e-12);
    EXPECT_EQ(c.classification[v], CurvatureClass::Planar);
  }
  EXPECT_NEAR(sum(c.gauss), 2.0 * M_PI, 1e-9);  // χ = 1: the boundary turns by 2π
}

TEST(GeometryCurvature, SliversAndValenceThreeVerticesGiveFiniteValues) {
  // A tetrahedron (valence 3 everywhere) with one face split at a point 1e-9 off its edge,
  // which makes a sliver, and an isolated vertex.
  TriMesh mesh;
  const auto a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({1, 0, 0}),
             d = mesh.add_vertex({0, 1, 0}), e = mesh.add_vertex({0, 0, 1});
  const auto s = mesh.add_vertex({0.5, 1e-9, 0.0});  // almost on edge a–b
  mesh.add_vertex({5, 5, 5});
  mesh.add_face(a, d, s);
  mesh.add_face(s, d, b);
  mesh.add_face(a, s, e);  // the sliver side: a, s, b nearly collinear
  mesh.add_face(s, b, e);
  mesh.add_face(a, e, d);
  mesh.add_face(b, d, e);
  ASSERT_EQ(mesh.n_faces(), 6u);
  const Curvature c = computeCurvature(mesh);
  expectAllFinite(c);
  EXPECT_NEAR(sum(c.gauss), 4.0 * M_PI, 1e-9);
}

TEST(GeometryCurvature, RejectsOutOfRangeOptions) {
  CurvatureOptions options;
  options.strongAreaFraction = 1.5;
  EXPECT_NE(options.validate().find("strongAreaFraction"), std::string::npos);
  EXPECT_THROW(computeCurvature(makeIcosphere(1), options), Error);
}

}  // namespace
}  // namespace hexcover
