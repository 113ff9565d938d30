#pragma once
// The mesh types that cross stages.
//
// TriMesh is the repaired, manifold, consistently oriented triangle mesh every stage after
// core/mesh works on (OpenMesh for connectivity, double-precision points). Per-element data that
// one stage hands to the next lives in arrays indexed by OpenMesh's element index (vh.idx(),
// fh.idx(), eh.idx(), heh.idx()); never run garbage_collection() while such arrays are alive.
//
// PolygonSoup is the raw form: what a reader produced before validation and repair, and what the
// writers take (polygon meshes such as the hexagonal dual, and meshes with per-corner texture
// coordinates).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <array>
#include <cstdint>
#include <vector>

namespace hexcover {

struct MeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  using TexCoord2D = OpenMesh::Vec2d;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

/// Polygons over a shared vertex array. Face f has corners cornerVertices[faceStarts[f] ..
/// faceStarts[f+1]) in counter-clockwise order; faceStarts has faceCount()+1 entries.
/// cornerTexcoords is empty or has one (u, v) per corner.
struct PolygonSoup {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::uint32_t> faceStarts{0};
  std::vector<std::uint32_t> cornerVertices;
  std::vector<Eigen::Vector2d> cornerTexcoords;

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t faceCount() const { return faceStarts.size() - 1; }
  std::size_t faceSize(std::size_t f) const { return faceStarts[f + 1] - faceStarts[f]; }
  /// Triangles of the faces fan-triangulated (a face of n ≥ 3 corners gives n − 2).
  std::size_t triangleCount() const {
    std::size_t triangles = 0;
    for (std::size_t f = 0; f < faceCount(); ++f)
      triangles += faceSize(f) >= 3 ? faceSize(f) - 2 : 0;
    return triangles;
  }
  /// Appends a face with the given vertex indices.
  template <typename Range>
  void addFace(const Range& vertices) {
    for (const auto v : vertices) cornerVertices.push_back(static_cast<std::uint32_t>(v));
    faceStarts.push_back(static_cast<std::uint32_t>(cornerVertices.size()));
  }
};

/// Eigen view of a point.
inline Eigen::Vector3d toEigen(const OpenMesh::Vec3d& p) { return {p[0], p[1], p[2]}; }
inline OpenMesh::Vec3d toOpenMesh(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

/// Length of the diagonal of the axis-aligned bounding box of the mesh's vertices (0 if empty).
double boundingBoxDiagonal(const TriMesh& mesh);

/// The mesh as a polygon soup (triangles, no texture coordinates), vertex and face order kept.
PolygonSoup toPolygonSoup(const TriMesh& mesh);

/// Appends the mesh to `soup` as further vertices (moved by `offset`) and triangles, in the mesh's
/// order: one more part of a soup of several.
void appendToPolygonSoup(PolygonSoup& soup, const TriMesh& mesh,
                         const Eigen::Vector3d& offset = Eigen::Vector3d::Zero());

/// The distinct edges of a polygon soup's faces, in the order the faces first use them (face by
/// face, side by side), each as its two vertices in that first side's direction, with the number
/// of face sides on it (1: a boundary edge).
struct SoupEdges {
  std::vector<std::array<std::uint32_t, 2>> edges;
  std::vector<int> uses;
};
SoupEdges soupEdges(const PolygonSoup& soup);

}  // namespace hexcover
