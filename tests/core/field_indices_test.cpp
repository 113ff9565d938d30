// Matchings and singularity indices of prescribed fields (rosyFieldFromDirections).

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "core/common/error.h"
#include "core/field/rosy_field.h"
#include "core/mesh/primitives.h"

namespace hexcover {
namespace {

Eigen::Vector3d centroid(const TriMesh& mesh, TriMesh::FaceHandle fh) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto vh : mesh.fv_range(fh)) c += toEigen(mesh.point(vh));
  return c / 3.0;
}

template <typename Function>
std::vector<Eigen::Vector3d> sampleField(const TriMesh& mesh, Function direction) {
  std::vector<Eigen::Vector3d> directions;
  for (const auto fh : mesh.faces()) directions.push_back(direction(centroid(mesh, fh)));
  return directions;
}

int indexSum(const RosyField& field) {
  int sum = 0;
  for (const auto& s : field.singularities) sum += s.index;
  return sum;
}

TEST(FieldIndices, FieldAlongTheMajorCircleOfATorusHasNoSingularities) {
  const TriMesh torus = makeTorus(2.0, 0.7, 48, 20);
  for (const int n : {4, 6}) {
    const RosyField field = rosyFieldFromDirections(
        torus,
        sampleField(torus,
                    [](const Eigen::Vector3d& p) { return Eigen::Vector3d(-p.y(), p.x(), 0); }),
        n);
    EXPECT_EQ(field.eulerCharacteristic, 0);
    EXPECT_TRUE(field.singularities.empty())
        << field.singularities.size() << " singularities, N = " << n;
    for (const int r : field.edgeMatching) EXPECT_EQ(r, 0);
  }
}

TEST(FieldIndices, SmoothFieldsOnTheIcosphereHaveIndexSumTwoAtThePoles) {
  const TriMesh sphere = makeIcosphere(3);
  const auto latitude = [](const Eigen::Vector3d& p) { return Eigen::Vector3d(-p.y(), p.x(), 0); };
  const auto meridian = [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(Eigen::Vector3d::UnitZ() - p.normalized().z() * p.normalized());
  };
  for (const int n : {4, 6}) {
    for (const auto& field : {rosyFieldFromDirections(sphere, sampleField(sphere, latitude), n),
                              rosyFieldFromDirections(sphere, sampleField(sphere, meridian), n)}) {
      EXPECT_EQ(field.eulerCharacteristic, 2);
      EXPECT_EQ(indexSum(field), 2 * n);
      ASSERT_FALSE(field.singularities.empty());
      // Near a pole, neighbouring faces' sampled directions differ by more than π/N, so the
      // pole's +N may split into several vertices of either sign; all of them lie near it.
      for (const auto& s : field.singularities) {
        EXPECT_GT(std::abs(s.position.z()), 0.9)
            << "singularity away from the poles at vertex " << s.vertex;
        EXPECT_FALSE(s.onBoundary);
      }
    }
  }
}

TEST(FieldIndices, ConstantFieldOnAFlatPatchCountsTheBoundaryTurningAngle) {
  // A lattice-aligned constant field follows every boundary edge of an equilateral patch, so a
  // boundary vertex with m triangles (turning angle π − m·π/3) has I = 6(π − mπ/3)/2π = 3 − m;
  // interior vertices are regular.
  const TriMesh grid = makeEquilateralGrid(9, 9);
  const RosyField field = rosyFieldFromDirections(
      grid, sampleField(grid, [](const Eigen::Vector3d&) { return Eigen::Vector3d::UnitX(); }), 6);
  EXPECT_EQ(field.eulerCharacteristic, 1);
  EXPECT_EQ(indexSum(field), 6);
  std::vector<int> index(grid.n_vertices(), 0);
  for (const auto& s : field.singularities) index[s.vertex] = s.index;
  for (const auto vh : grid.vertices()) {
    const int triangles = static_cast<int>(std::distance(vh.faces().begin(), vh.faces().end()));
    EXPECT_EQ(index[vh.idx()], grid.is_boundary(vh) ? 3 - triangles : 0) << "vertex " << vh.idx();
  }
}

TEST(FieldIndices, FieldAlongTheCircumferenceOfATubeHasNoSingularities) {
  const TriMesh tube = makeTube(1.0, 3.0, 32, 19);
  const RosyField field = rosyFieldFromDirections(
      tube,
      sampleField(tube, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(-p.y(), p.x(), 0); }),
      6);
  EXPECT_EQ(field.eulerCharacteristic, 0);
  EXPECT_TRUE(field.singularities.empty());
}

TEST(FieldIndices, MatchingPairsTheTransportedRepresentativeWithTheRotatedOne) {
  // Constant field along x on a flat patch, with one face's representative turned by +2·60°:
  // transported from f0, the representative of f0 equals that of f1 turned by 4·60° (r = 4);
  // read from f1 to f0 the matching is N − r = 2.
  const TriMesh grid = makeEquilateralGrid(5, 5);
  const auto eh = *std::find_if(grid.edges_begin(), grid.edges_end(),
                                [&](auto e) { return !grid.is_boundary(e); });
  const int f0 = grid.face_handle(grid.halfedge_handle(eh, 0)).idx();
  const int f1 = grid.face_handle(grid.halfedge_handle(eh, 1)).idx();
  std::vector<Eigen::Vector3d> directions(grid.n_faces(), Eigen::Vector3d::UnitX());
  const double turn = 2.0 * 2.0 * M_PI / 6.0;
  directions[f1] = {std::cos(turn), std::sin(turn), 0.0};
  const RosyField field = rosyFieldFromDirections(grid, directions, 6);
  EXPECT_EQ(field.edgeMatching[eh.idx()], 4);
  directions[f1] = Eigen::Vector3d::UnitX();
  directions[f0] = {std::cos(turn), std::sin(turn), 0.0};
  EXPECT_EQ(rosyFieldFromDirections(grid, directions, 6).edgeMatching[eh.idx()], 2);
}

TEST(FieldIndices, RejectsOddOrderAndWrongSizedInput) {
  const TriMesh grid = makeEquilateralGrid(4, 4);
  const std::vector<Eigen::Vector3d> directions(grid.n_faces(), Eigen::Vector3d::UnitX());
  EXPECT_THROW(rosyFieldFromDirections(grid, directions, 3), Error);
  EXPECT_THROW(rosyFieldFromDirections(grid, {Eigen::Vector3d::UnitX()}, 6), Error);
  auto bad = directions;
  bad[1].x() = std::nan("");
  EXPECT_THROW(rosyFieldFromDirections(grid, bad, 6), Error);
}

}  // namespace
}  // namespace hexcover
