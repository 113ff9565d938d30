// The conformal scale of core/param/conformal_scale.h on shapes whose flat conformal metric is
// known in closed form.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/field/rosy_field.h"
#include "core/mesh/primitives.h"
#include "core/param/conformal_scale.h"
#include "core/param/hexcover.h"

namespace hexcover {
namespace {

Eigen::Vector3d faceCentroid(const TriMesh& mesh, OpenMesh::FaceHandle fh) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto vh : mesh.fv_range(fh)) c += toEigen(mesh.point(vh)) / 3.0;
  return c;
}

// The field along the parallels of a torus of revolution about the z axis.
RosyField parallelsField(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> directions;
  for (const auto fh : mesh.faces()) {
    const Eigen::Vector3d c = faceCentroid(mesh, fh);
    directions.emplace_back(-c.y(), c.x(), 0.0);
  }
  return rosyFieldFromDirections(mesh, directions, 6);
}

double standardDeviation(const std::vector<double>& values) {
  double mean = 0.0, square = 0.0;
  for (const double v : values) mean += v / values.size();
  for (const double v : values) square += (v - mean) * (v - mean) / values.size();
  return std::sqrt(square);
}

TEST(ConformalScale, ConstantFieldOnAPlaneHasUnitScale) {
  const TriMesh mesh = makeEquilateralGrid(12, 10, 0.5);
  const RosyField field =
      rosyFieldFromDirections(mesh, std::vector<Eigen::Vector3d>(mesh.n_faces(), {1, 0, 0}), 6);
  for (const double s : conformalFaceScale(mesh, field)) EXPECT_NEAR(s, 1.0, 1e-9);
}

// The torus metric ρ²dθ² + r²dψ² is ρ² times a flat one, so the parallels field becomes
// integrable when scaled by 1/ρ (ρ: distance from the axis): φ + log ρ is constant.
TEST(ConformalScale, TorusParallelsScaleAsTheInverseDistanceFromTheAxis) {
  const TriMesh mesh = makeTorus(3.0, 1.0, 120, 40);
  const RosyField field = parallelsField(mesh);
  ASSERT_TRUE(field.singularities.empty());
  const std::vector<double> scale = conformalFaceScale(mesh, field, 5.0, 5.0);
  std::vector<double> logScale, residual;
  for (const auto fh : mesh.faces()) {
    const Eigen::Vector3d c = faceCentroid(mesh, fh);
    logScale.push_back(std::log(scale[fh.idx()]));
    residual.push_back(logScale.back() + std::log(c.head<2>().norm()));
  }
  // log ρ spans log(2)..log(4): the scale varies, and 1/ρ explains it to within 1%.
  EXPECT_GT(standardDeviation(logScale), 0.2);
  EXPECT_LT(standardDeviation(residual), 0.01);

  // Mean lattice unit of 1: Σ A / s = Σ A.
  double area = 0.0, unit = 0.0;
  for (const auto fh : mesh.faces()) {
    area += mesh.calc_face_area(fh);
    unit += mesh.calc_face_area(fh) / scale[fh.idx()];
  }
  EXPECT_NEAR(unit / area, 1.0, 1e-9);
}

// On the torus the normalized log scale spans about [−0.23, 0.46] (lattice units from 0.63 to
// 1.26 times h): inside the default bounds [−0.5, 1], so nothing is clamped; bounds of 0.1 on
// growth and 0.3 on shrinking clamp each side to its own bound.
TEST(ConformalScale, ClampsTheGrowthAndTheShrinkingOfLatticeUnitsSeparately) {
  const TriMesh mesh = makeTorus(3.0, 1.0, 120, 40);
  const RosyField field = parallelsField(mesh);
  const std::vector<double> free = conformalFaceScale(mesh, field, 5.0, 5.0);
  EXPECT_EQ(conformalFaceScale(mesh, field), free) << "the defaults should not clamp the torus";
  const auto [freeMin, freeMax] = std::minmax_element(free.begin(), free.end());
  ASSERT_LT(*freeMin, std::exp(-0.2));
  ASSERT_GT(*freeMax, std::exp(0.4));
  const std::vector<double> clamped = conformalFaceScale(mesh, field, 0.3, 0.1);
  const auto [lowest, highest] = std::minmax_element(clamped.begin(), clamped.end());
  EXPECT_DOUBLE_EQ(*lowest, std::exp(-0.1)) << "lattice units grow at most e^0.1";
  EXPECT_DOUBLE_EQ(*highest, std::exp(0.3)) << "and shrink at most e^0.3";
  for (std::size_t f = 0; f < free.size(); ++f)
    if (free[f] > std::exp(-0.1) && free[f] < std::exp(0.3)) {
      EXPECT_DOUBLE_EQ(clamped[f], free[f]);
    }
}

// With the scale, the parallels field is (nearly) a gradient field: the local step's energy
// drops to a small fraction of the unscaled one, whose curl it cannot integrate.
TEST(ConformalScale, RemovesTheCurlThatAUnitFieldLeavesInTheLocalStep) {
  const TriMesh mesh = makeTorus(3.0, 1.0, 120, 40);
  const RosyField field = parallelsField(mesh);
  ParamOptions options;
  options.edgeLength = 0.3;
  options.conformalScale = false;
  const double unit = computeParameterization(mesh, field, options).localEnergy;
  options.conformalScale = true;
  const double scaled = computeParameterization(mesh, field, options).localEnergy;
  EXPECT_LT(scaled, 0.05 * unit) << "unit field " << unit << ", conformally scaled " << scaled;
}

}  // namespace
}  // namespace hexcover
