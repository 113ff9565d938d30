#include "core/field/rosy_field.h"

#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/field/singularities.h"

namespace hexcover {

RosyField rosyFieldFromDirections(const TriMesh& mesh, std::vector<Eigen::Vector3d> directions,
                                  int n) {
  if (n < 2 || n % 2 != 0)
    throw Error(
        ErrorCode::InvalidOption,
        "rosy field: symmetry order N must be even and at least 2, got " + std::to_string(n));
  if (directions.size() != mesh.n_faces())
    throw Error(ErrorCode::InvalidOption, "rosy field: " + std::to_string(directions.size()) +
                                              " directions for " + std::to_string(mesh.n_faces()) +
                                              " faces");
  for (std::size_t f = 0; f < directions.size(); ++f)
    if (!directions[f].allFinite())
      throw Error(ErrorCode::InvalidOption,
                  "rosy field: the direction of face " + std::to_string(f) + " is not finite");
  const field::FieldGeometry geometry(mesh);
  std::vector<double> angles(directions.size());
  for (std::size_t f = 0; f < directions.size(); ++f)
    angles[f] = geometry.frames.angleOf(static_cast<int>(f), directions[f]);
  return field::rosyFieldFromAngles(mesh, geometry, angles, n);
}

}  // namespace hexcover
