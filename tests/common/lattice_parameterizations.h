#pragma once
// Parameterizations built by hand, where the extraction's answer is known, for the lattices of
// order 6 (Eisenstein) and 4 (Gauss): a flat torus with integer periods, and a fan of planar
// triangles whose transitions make a cone at its centre. Also the valences of a polygon mesh.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/param/parameterization.h"

namespace hexcover::test {

/// The rotation by 2π/order in lattice coordinates (order 6: (a, b) ↦ (−b, a + b); order 4:
/// (a, b) ↦ (−b, a)), k times.
inline Eigen::Vector2d rotateLattice(Eigen::Vector2d z, int k, int order) {
  for (int i = 0; i < ((k % order) + order) % order; ++i)
    z = order == 6 ? Eigen::Vector2d(-z.y(), z.x() + z.y()) : Eigen::Vector2d(-z.y(), z.x());
  return z;
}

/// Fills the transitions of `param` (lattice order param.n) from its corner coordinates, given
/// each edge's rotation.
inline void fillTransitions(const TriMesh& mesh, Parameterization& param,
                            const std::function<int(TriMesh::EdgeHandle)>& rotation) {
  param.edgeTransition.assign(mesh.n_edges(), {});
  param.cutEdge.assign(mesh.n_edges(), false);
  for (const auto e : mesh.edges()) {
    if (mesh.is_boundary(e)) continue;
    const auto h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    const int r = rotation(e);
    // to_vertex(h0) = from_vertex(h1): its coordinates in f1 are those of prev(h1).
    const Eigen::Vector2d in0 = param.cornerCoords[h0.idx()];
    const Eigen::Vector2d in1 = param.cornerCoords[mesh.prev_halfedge_handle(h1).idx()];
    const Eigen::Vector2d t = in1 - rotateLattice(in0, r, param.n);
    param.edgeTransition[e.idx()] = {
        r, {static_cast<int>(std::lround(t.x())), static_cast<int>(std::lround(t.y()))}};
    param.cutEdge[e.idx()] = r != 0 || t.norm() > 0.5;
  }
}

/// Flat torus: the (around × tube) vertex grid of makeTorus mapped linearly onto the periods p1
/// (along the major circle) and p2 (around the tube), in lattice coordinates of the given order.
inline Parameterization flatTorusParameterization(const TriMesh& torus, int around, int tube,
                                                  const Eigen::Vector2d& p1,
                                                  const Eigen::Vector2d& p2, int order = 6) {
  Parameterization param;
  param.n = order;
  param.edgeLength = 1.0;
  param.cornerCoords.assign(torus.n_halfedges(), Eigen::Vector2d::Zero());
  for (const auto f : torus.faces()) {
    const auto h0 = torus.halfedge_handle(f);
    const int base = torus.to_vertex_handle(h0).idx();
    const int i0 = base / tube, j0 = base % tube;
    for (const auto h : torus.fh_range(f)) {
      const int v = torus.to_vertex_handle(h).idx();
      const int di = ((v / tube - i0 + around + 1) % around) - 1;
      const int dj = ((v % tube - j0 + tube + 1) % tube) - 1;
      param.cornerCoords[h.idx()] = double(i0 + di) / around * p1 + double(j0 + dj) / tube * p2;
    }
  }
  fillTransitions(torus, param, [](auto) { return 0; });
  return param;
}

/// A fan of `faces` planar triangles around the origin with the lattice triangle of legs `side`
/// (along e1 and its rotation) in each, rotated by 2π/order from face to face: the transition
/// across the last spoke rotates by order − faces (mod order), a cone of index
/// (order − faces)/order at the centre.
inline std::pair<TriMesh, Parameterization> coneFan(int faces, int side, int order = 6) {
  TriMesh mesh;
  const auto center = mesh.add_vertex({0, 0, 0});
  std::vector<TriMesh::VertexHandle> ring;
  for (int i = 0; i < faces; ++i)
    ring.push_back(
        mesh.add_vertex({std::cos(2 * M_PI * i / faces), std::sin(2 * M_PI * i / faces), 0}));
  for (int i = 0; i < faces; ++i) mesh.add_face(center, ring[i], ring[(i + 1) % faces]);
  Parameterization param;
  param.n = order;
  param.edgeLength = 1.0;
  param.cornerCoords.assign(mesh.n_halfedges(), Eigen::Vector2d::Zero());
  for (const auto f : mesh.faces()) {
    const int i = f.idx();
    for (const auto h : mesh.fh_range(f)) {
      const auto v = mesh.to_vertex_handle(h);
      Eigen::Vector2d z = Eigen::Vector2d::Zero();
      if (v == ring[i]) z = rotateLattice(Eigen::Vector2d(side, 0), i, order);
      if (v == ring[(i + 1) % faces]) z = rotateLattice(Eigen::Vector2d(side, 0), i + 1, order);
      param.cornerCoords[h.idx()] = z;
    }
  }
  // Spoke i+1 is shared by faces i and i+1 with the same coordinates, except the last spoke.
  const auto spoke0 = mesh.find_halfedge(center, ring[0]);
  fillTransitions(mesh, param, [&](TriMesh::EdgeHandle e) {
    if (e != mesh.edge_handle(spoke0)) return 0;
    // The face of halfedge(e,0) is the last face (coords R^faces e1) or face 0 (coords e1).
    const auto f0 = mesh.face_handle(mesh.halfedge_handle(e, 0));
    return f0.idx() == faces - 1 ? (order - faces % order) % order : faces % order;
  });
  return {std::move(mesh), std::move(param)};
}

/// Per vertex of a polygon mesh: its valence (distinct polygon edges) and whether it is on the
/// boundary (on an edge of one polygon).
struct PolygonValences {
  std::vector<int> valence;
  std::vector<bool> onBoundary;
};
inline PolygonValences polygonValences(const PolygonSoup& soup) {
  std::map<std::pair<int, int>, int> uses;
  for (std::size_t f = 0; f < soup.faceCount(); ++f)
    for (std::size_t k = 0; k < soup.faceSize(f); ++k) {
      const int a = static_cast<int>(soup.cornerVertices[soup.faceStarts[f] + k]);
      const int b =
          static_cast<int>(soup.cornerVertices[soup.faceStarts[f] + (k + 1) % soup.faceSize(f)]);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  PolygonValences result{std::vector<int>(soup.vertexCount(), 0),
                         std::vector<bool>(soup.vertexCount(), false)};
  for (const auto& [edge, count] : uses) {
    ++result.valence[edge.first], ++result.valence[edge.second];
    if (count == 1) result.onBoundary[edge.first] = result.onBoundary[edge.second] = true;
  }
  return result;
}

/// Faces of a polygon mesh with `size` corners.
inline int facesOfSize(const PolygonSoup& soup, std::size_t size) {
  int count = 0;
  for (std::size_t f = 0; f < soup.faceCount(); ++f) count += soup.faceSize(f) == size;
  return count;
}

}  // namespace hexcover::test
