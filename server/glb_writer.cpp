#include "server/glb_writer.h"

#include <tiny_gltf.h>

#include <cstring>
#include <limits>
#include <map>

#include "core/common/error.h"

namespace hexcover::server {

namespace {

/// Appends `values` to the buffer as a new view + accessor; returns the accessor index.
template <typename T>
int addAccessor(tinygltf::Model& model, const std::vector<T>& values, int componentType, int type,
                std::size_t count, int target) {
  auto& buffer = model.buffers[0].data;
  while (buffer.size() % 4 != 0) buffer.push_back(0);  // accessors are 4-byte aligned
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = values.size() * sizeof(T);
  view.target = target;
  const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
  buffer.insert(buffer.end(), bytes, bytes + view.byteLength);
  model.bufferViews.push_back(view);

  tinygltf::Accessor accessor;
  accessor.bufferView = int(model.bufferViews.size()) - 1;
  accessor.componentType = componentType;
  accessor.type = type;
  accessor.count = count;
  model.accessors.push_back(accessor);
  return int(model.accessors.size()) - 1;
}

}  // namespace

void writeGlb(const PolygonSoup& soup, const std::filesystem::path& path) {
  const bool textured = !soup.cornerTexcoords.empty();
  if (soup.cornerVertices.size() >= std::numeric_limits<std::uint32_t>::max())
    throw Error(ErrorCode::InvalidMesh, "the mesh is too large for glTF (2^32 corners)");

  // Output vertices: the soup's vertices, or one per distinct (vertex, uv) pair.
  std::vector<float> positions;
  std::vector<float> texcoords;
  std::vector<std::uint32_t> cornerToVertex(soup.cornerVertices.size());
  if (!textured) {
    for (const auto& p : soup.positions)
      for (int k = 0; k < 3; ++k) positions.push_back(float(p[k]));
    for (std::size_t c = 0; c < soup.cornerVertices.size(); ++c)
      cornerToVertex[c] = soup.cornerVertices[c];
  } else {
    std::map<std::tuple<std::uint32_t, double, double>, std::uint32_t> ids;
    for (std::size_t c = 0; c < soup.cornerVertices.size(); ++c) {
      const auto v = soup.cornerVertices[c];
      const auto& uv = soup.cornerTexcoords[c];
      const auto [it, added] = ids.try_emplace({v, uv.x(), uv.y()}, std::uint32_t(ids.size()));
      if (added) {
        for (int k = 0; k < 3; ++k) positions.push_back(float(soup.positions[v][k]));
        texcoords.push_back(float(uv.x()));
        texcoords.push_back(float(1.0 - uv.y()));
      }
      cornerToVertex[c] = it->second;
    }
  }

  std::vector<std::uint32_t> indices;
  for (std::size_t f = 0; f < soup.faceCount(); ++f)
    for (std::uint32_t k = soup.faceStarts[f] + 1; k + 1 < soup.faceStarts[f + 1]; ++k) {
      indices.push_back(cornerToVertex[soup.faceStarts[f]]);
      indices.push_back(cornerToVertex[k]);
      indices.push_back(cornerToVertex[k + 1]);
    }

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "hexcover";
  model.buffers.resize(1);
  const std::size_t vertexCount = positions.size() / 3;

  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  const int position = addAccessor(model, positions, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                   TINYGLTF_TYPE_VEC3, vertexCount, TINYGLTF_TARGET_ARRAY_BUFFER);
  // glTF requires POSITION bounds.
  auto& accessor = model.accessors[std::size_t(position)];
  accessor.minValues.assign(3, std::numeric_limits<double>::max());
  accessor.maxValues.assign(3, std::numeric_limits<double>::lowest());
  for (std::size_t i = 0; i < vertexCount; ++i)
    for (int k = 0; k < 3; ++k) {
      accessor.minValues[k] = std::min(accessor.minValues[k], double(positions[3 * i + k]));
      accessor.maxValues[k] = std::max(accessor.maxValues[k], double(positions[3 * i + k]));
    }
  if (vertexCount == 0) accessor.minValues.assign(3, 0.0), accessor.maxValues.assign(3, 0.0);
  primitive.attributes["POSITION"] = position;
  if (textured)
    primitive.attributes["TEXCOORD_0"] =
        addAccessor(model, texcoords, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2,
                    vertexCount, TINYGLTF_TARGET_ARRAY_BUFFER);
  primitive.indices =
      addAccessor(model, indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                  indices.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);

  tinygltf::Mesh mesh;
  mesh.name = "hexcover";
  mesh.primitives.push_back(primitive);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model, path.string(), false, true, false, true))
    throw Error(ErrorCode::Io, "cannot write " + path.string());
}

}  // namespace hexcover::server
