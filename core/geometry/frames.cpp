#include "core/geometry/frames.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hexcover {
namespace {

/// Any unit vector perpendicular to the unit vector a.
Eigen::Vector3d anyPerpendicular(const Eigen::Vector3d& a) {
  const Eigen::Vector3d other =
      std::abs(a.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return a.cross(other).normalized();
}

/// Wraps an angle into (-π, π].
double wrapAngle(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

double FaceFrames::angleOf(int f, const Eigen::Vector3d& d) const {
  const double x = d.dot(xAxis[f]), y = d.dot(yAxis[f]);
  return (x == 0.0 && y == 0.0) ? 0.0 : std::atan2(y, x);
}

Eigen::Vector3d FaceFrames::direction(int f, double angle) const {
  return std::cos(angle) * xAxis[f] + std::sin(angle) * yAxis[f];
}

FaceFrames computeFaceFrames(const TriMesh& mesh) {
  const auto nf = mesh.n_faces();
  FaceFrames frames;
  frames.normal.resize(nf);
  frames.xAxis.resize(nf);
  frames.yAxis.resize(nf);
  frames.area.resize(nf);
  std::vector<Eigen::Vector3d> areaVector(nf);  // (b - a) × (c - a), twice the area
  double scale = 0.0;
  for (const auto eh : mesh.edges()) scale = std::max(scale, mesh.calc_edge_length(eh));
  for (const auto fh : mesh.faces()) {
    const auto h = mesh.halfedge_handle(fh);
    const Eigen::Vector3d a = toEigen(mesh.point(mesh.from_vertex_handle(h)));
    const Eigen::Vector3d b = toEigen(mesh.point(mesh.to_vertex_handle(h)));
    const Eigen::Vector3d c =
        toEigen(mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h))));
    areaVector[fh.idx()] = (b - a).cross(c - a);
    frames.area[fh.idx()] = 0.5 * areaVector[fh.idx()].norm();
  }
  // A normal is trusted when the triangle is not collinear to within rounding of its coordinates.
  const double tinyArea = 1e-14 * scale * scale;
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    Eigen::Vector3d n = areaVector[f];
    if (n.norm() <= tinyArea) {
      n.setZero();
      for (const auto g : fh.faces()) n += areaVector[g.idx()];
    }
    const auto h = mesh.halfedge_handle(fh);
    Eigen::Vector3d x =
        toEigen(mesh.point(mesh.to_vertex_handle(h)) - mesh.point(mesh.from_vertex_handle(h)));
    x = x.norm() > 0.0 ? x.normalized() : Eigen::Vector3d::UnitX();
    n -= n.dot(x) * x;  // the fallback normal need not be perpendicular to this face's edge
    n = n.norm() > tinyArea ? n.normalized() : anyPerpendicular(x);
    frames.normal[f] = n;
    frames.xAxis[f] = x;
    frames.yAxis[f] = n.cross(x);
  }
  return frames;
}

std::vector<double> edgeTransportAngles(const TriMesh& mesh, const FaceFrames& frames) {
  std::vector<double> transport(mesh.n_edges(), 0.0);
  for (const auto eh : mesh.edges()) {
    if (mesh.is_boundary(eh)) continue;
    const auto h0 = mesh.halfedge_handle(eh, 0), h1 = mesh.halfedge_handle(eh, 1);
    const Eigen::Vector3d d =
        toEigen(mesh.point(mesh.to_vertex_handle(h0)) - mesh.point(mesh.from_vertex_handle(h0)));
    const int f0 = mesh.face_handle(h0).idx(), f1 = mesh.face_handle(h1).idx();
    transport[eh.idx()] = wrapAngle(frames.angleOf(f1, d) - frames.angleOf(f0, d));
  }
  return transport;
}

std::vector<double> cornerAngles(const TriMesh& mesh) {
  std::vector<double> angle(mesh.n_halfedges(), 0.0);
  for (const auto heh : mesh.halfedges()) {
    if (mesh.is_boundary(heh)) continue;
    const auto next = mesh.next_halfedge_handle(heh);
    const auto corner = mesh.point(mesh.to_vertex_handle(heh));
    const Eigen::Vector3d a = toEigen(mesh.point(mesh.from_vertex_handle(heh)) - corner);
    const Eigen::Vector3d b = toEigen(mesh.point(mesh.to_vertex_handle(next)) - corner);
    angle[heh.idx()] = std::atan2(a.cross(b).norm(), a.dot(b));  // atan2(0, 0) = 0: finite
  }
  return angle;
}

std::vector<double> angleDefects(const TriMesh& mesh) {
  const auto corner = cornerAngles(mesh);
  std::vector<double> defect(mesh.n_vertices(), 0.0);
  for (const auto vh : mesh.vertices()) {
    if (mesh.is_isolated(vh)) continue;
    double sum = 0.0;
    int gaps = 0;  // boundary fans end at outgoing boundary halfedges (2 at a pinched vertex)
    for (const auto heh : vh.incoming_halfedges()) {
      if (!heh.is_boundary()) sum += corner[heh.idx()];
      if (heh.opp().is_boundary()) ++gaps;
    }
    defect[vh.idx()] = 2.0 * M_PI - M_PI * gaps - sum;
  }
  return defect;
}

FaceComponents faceComponents(const TriMesh& mesh) {
  const int nf = static_cast<int>(mesh.n_faces());
  std::vector<int> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  const auto unite = [&](int a, int b) {
    a = findRoot(parent, a);
    b = findRoot(parent, b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the lowest face index
  };
  // Through vertices as well as edges, so that χ = V − E + F holds per component.
  for (const auto vh : mesh.vertices()) {
    int first = -1;
    for (const auto fh : vh.faces()) {
      if (first < 0)
        first = fh.idx();
      else
        unite(first, fh.idx());
    }
  }
  FaceComponents components;
  components.faceComponent.assign(nf, -1);
  std::vector<int> idOfRoot(nf, -1);
  for (int f = 0; f < nf; ++f) {
    const int root = findRoot(parent, f);
    if (idOfRoot[root] < 0) idOfRoot[root] = components.count++;
    components.faceComponent[f] = idOfRoot[root];
  }
  components.eulerCharacteristic.assign(components.count, 0);
  components.boundaryLoops.assign(components.count, 0);
  auto& chi = components.eulerCharacteristic;
  for (int f = 0; f < nf; ++f) ++chi[components.faceComponent[f]];
  for (const auto eh : mesh.edges()) {
    const auto h = mesh.is_boundary(eh.h0()) ? eh.h1() : eh.h0();
    if (h.face().is_valid()) --chi[components.faceComponent[h.face().idx()]];
  }
  for (const auto vh : mesh.vertices()) {
    for (const auto fh : vh.faces()) {
      ++chi[components.faceComponent[fh.idx()]];
      break;
    }
  }
  std::vector<bool> visited(mesh.n_halfedges(), false);
  for (const auto heh : mesh.halfedges()) {
    if (!heh.is_boundary() || visited[heh.idx()]) continue;
    const int component = components.faceComponent[heh.opp().face().idx()];
    ++components.boundaryLoops[component];
    for (auto h = heh; !visited[h.idx()]; h = h.next()) visited[h.idx()] = true;
  }
  return components;
}

}  // namespace hexcover
