// `hexcover field MESH [--rosy 6|4] [--d-sing X] [--max-merged-index K] [--no-clustering]
// [--free-boundary] [-o FIELD.ply]`: the geometry-aware N-RoSy field of a mesh (paper section 3)
// as one JSON object on stdout (clustered as in the paper unless --max-merged-index K limits merged
// singularities to |I| ≤ K, as the remesh pipeline does with K = 1); -o writes a PLY that any
// mesh viewer shows: the mesh with its singular vertices coloured by index (red positive, blue
// negative, darker for |I| > 1) and, in every face, short segments along the N field directions
// (thin quads; the representative direction in orange).

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "api/field_json.h"
#include "clients/cli/arguments.h"
#include "clients/cli/commands.h"
#include "core/common/error.h"
#include "core/field/rosy_field.h"
#include "core/mesh/load.h"

namespace hexcover::cli {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

Rgb singularityColour(int index) {
  if (index >= 2) return {150, 0, 0};
  if (index == 1) return {230, 60, 40};
  if (index == -1) return {40, 90, 230};
  if (index <= -2) return {0, 0, 150};
  return {200, 200, 200};
}

/// Little-endian binary PLY with float positions, uchar colours and triangles.
class ColouredPly {
 public:
  int addVertex(const Eigen::Vector3d& p, const Rgb& colour) {
    positions_.push_back(p);
    colours_.push_back(colour);
    return static_cast<int>(positions_.size()) - 1;
  }
  void addTriangle(int a, int b, int c) { triangles_.push_back({a, b, c}); }

  void write(const std::string& path) const {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw Error(ErrorCode::Io, "cannot write " + path);
    out << "ply\nformat binary_little_endian 1.0\ncomment hexcover field: mesh, singular vertices "
           "and direction segments\nelement vertex "
        << positions_.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
           "property uchar green\nproperty uchar blue\nelement face "
        << triangles_.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    std::vector<char> bytes;
    bytes.reserve(positions_.size() * 15 + triangles_.size() * 13);
    for (std::size_t v = 0; v < positions_.size(); ++v) {
      for (int k = 0; k < 3; ++k) appendLittleEndian(bytes, static_cast<float>(positions_[v][k]));
      for (const auto channel : colours_[v]) bytes.push_back(static_cast<char>(channel));
    }
    for (const auto& t : triangles_) {
      bytes.push_back(3);
      for (const int index : t) appendLittleEndian(bytes, static_cast<std::int32_t>(index));
    }
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw Error(ErrorCode::Io, "cannot write " + path);
  }

 private:
  template <typename T>
  static void appendLittleEndian(std::vector<char>& bytes, T value) {
    std::uint32_t bits = 0;
    static_assert(sizeof(T) == sizeof(bits));
    std::memcpy(&bits, &value, sizeof(bits));
    for (int shift = 0; shift < 32; shift += 8) bytes.push_back(static_cast<char>(bits >> shift));
  }

  std::vector<Eigen::Vector3d> positions_;
  std::vector<Rgb> colours_;
  std::vector<std::array<int, 3>> triangles_;
};

void writeFieldPly(const TriMesh& mesh, const RosyField& field, const std::string& path) {
  ColouredPly ply;
  std::vector<int> index(mesh.n_vertices(), 0);
  for (const auto& s : field.singularities) index[s.vertex] = s.index;
  for (const auto vh : mesh.vertices())
    ply.addVertex(toEigen(mesh.point(vh)), singularityColour(index[vh.idx()]));
  double meanEdge = 0.0;
  for (const auto eh : mesh.edges()) meanEdge += mesh.calc_edge_length(eh);
  meanEdge /= std::max<std::size_t>(1, mesh.n_edges());
  const double length = 0.35 * meanEdge, width = length / 14.0, lift = 0.02 * length;
  for (const auto fh : mesh.faces()) {
    std::array<int, 3> corner{};
    std::array<Eigen::Vector3d, 3> p;
    int i = 0;
    for (const auto vh : mesh.fv_range(fh)) {
      corner[i] = vh.idx();
      p[i++] = toEigen(mesh.point(vh));
    }
    ply.addTriangle(corner[0], corner[1], corner[2]);
    const Eigen::Vector3d cross = (p[1] - p[0]).cross(p[2] - p[0]);
    const Eigen::Vector3d normal = cross.norm() > 0.0 ? cross.normalized() : Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d centre = (p[0] + p[1] + p[2]) / 3.0 + lift * normal;
    const Eigen::Vector3d& d0 = field.faceDirection[fh.idx()];
    // N even: the segment through the centre along direction k also shows direction k + N/2.
    for (int k = 0; k < field.n / 2; ++k) {
      const double angle = 2.0 * M_PI * k / field.n;
      const Eigen::Vector3d d = std::cos(angle) * d0 + std::sin(angle) * normal.cross(d0);
      const Eigen::Vector3d side = width * normal.cross(d);
      const Rgb colour = k == 0 ? Rgb{255, 140, 0} : Rgb{25, 25, 25};
      const Eigen::Vector3d a = centre - 0.5 * length * d, b = centre + 0.5 * length * d;
      const int v0 = ply.addVertex(a - side, colour), v1 = ply.addVertex(b - side, colour);
      const int v2 = ply.addVertex(b + side, colour), v3 = ply.addVertex(a + side, colour);
      ply.addTriangle(v0, v1, v2);
      ply.addTriangle(v0, v2, v3);
    }
  }
  ply.write(path);
}

}  // namespace

int runField(int argc, char** argv) {
  const Arguments args(argc, argv, 2, {"--rosy", "--d-sing", "--max-merged-index", "-o"},
                       {"--no-clustering", "--free-boundary"});
  const std::string& path = args.positional(0, "MESH");
  args.expectPositionalCount(1);
  FieldOptions options;
  if (const auto rosy = args.integer("--rosy")) {
    if (*rosy != 4 && *rosy != 6) throw UsageError("--rosy must be 6 or 4");
    options.n = static_cast<int>(*rosy);
  }
  if (const auto dSing = args.number("--d-sing")) {
    if (!(*dSing > 0.0)) throw UsageError("--d-sing must be a positive distance in mesh units");
    options.singularityDistance = *dSing;
  }
  if (const auto maxIndex = args.integer("--max-merged-index")) {
    if (*maxIndex < 0 || *maxIndex > 1000)
      throw UsageError("--max-merged-index must be between 0 (no limit) and 1000");
    options.maxMergedIndex = static_cast<int>(*maxIndex);
  }
  options.clusterSingularities = !args.has("--no-clustering");
  if (args.has("--free-boundary")) options.boundary = BoundaryAlignment::Free;

  const auto loadStart = std::chrono::steady_clock::now();
  const TriMesh mesh = loadMesh(path);
  const auto fieldStart = std::chrono::steady_clock::now();
  const RosyField field = computeRosyField(mesh, options);
  const auto end = std::chrono::steady_clock::now();

  nlohmann::json json = {{"file", path},
                         {"vertices", mesh.n_vertices()},
                         {"faces", mesh.n_faces()}};
  json.update(toJson(field));
  json["seconds"] = std::chrono::duration<double>(end - fieldStart).count();
  json["load_seconds"] = std::chrono::duration<double>(fieldStart - loadStart).count();
  json["max_merged_index"] = options.maxMergedIndex;
  if (const auto output = args.value("-o")) {
    writeFieldPly(mesh, field, *output);
    json["output"] = *output;
  }
  std::cout << json.dump(2) << "\n";
  return 0;
}

}  // namespace hexcover::cli
