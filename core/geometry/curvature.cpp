#include "core/geometry/curvature.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "core/common/error.h"
#include "core/geometry/frames.h"

namespace hexcover {
namespace {

/// A tangent frame (u, v) with u × v = n.
struct TangentFrame {
  Eigen::Vector3d u, v;
};

/// Second fundamental form [[ku, kuv], [kuv, kv]] in some tangent frame.
struct FundamentalForm {
  double ku = 0.0, kuv = 0.0, kv = 0.0;
};

Eigen::Vector3d anyPerpendicular(const Eigen::Vector3d& a) {
  const Eigen::Vector3d other =
      std::abs(a.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return a.cross(other).normalized();
}

/// Rusinkiewicz's rotate_coord_sys: the frame (u, v) rotated about u × v onto the plane ⟂ n.
TangentFrame rotateFrame(const TangentFrame& frame, const Eigen::Vector3d& n) {
  const Eigen::Vector3d oldNormal = frame.u.cross(frame.v);
  const double ndot = oldNormal.dot(n);
  if (ndot <= -1.0 + 1e-12) return {-frame.u, -frame.v};
  const Eigen::Vector3d perp = n - ndot * oldNormal;
  const Eigen::Vector3d dperp = (oldNormal + n) / (1.0 + ndot);
  return {frame.u - dperp * perp.dot(frame.u), frame.v - dperp * perp.dot(frame.v)};
}

/// The form `form`, given in frame `from` (already rotated into the target plane), in frame `to`.
FundamentalForm reexpress(const FundamentalForm& form, const TangentFrame& from,
                          const TangentFrame& to) {
  const double u1 = to.u.dot(from.u), v1 = to.u.dot(from.v);
  const double u2 = to.v.dot(from.u), v2 = to.v.dot(from.v);
  return {form.ku * u1 * u1 + 2.0 * form.kuv * u1 * v1 + form.kv * v1 * v1,
          form.ku * u1 * u2 + form.kuv * (u1 * v2 + u2 * v1) + form.kv * v1 * v2,
          form.ku * u2 * u2 + 2.0 * form.kuv * u2 * v2 + form.kv * v2 * v2};
}

/// Max's weights ("Weights for computing vertex normals from facet normals", 1999): each corner
/// contributes (e1 × e2) / (|e1|² |e2|²), which is exact for vertices on a sphere; area-weighted
/// normals are only first-order accurate and bias the normal differences the fit relies on.
std::vector<Eigen::Vector3d> vertexNormals(const TriMesh& mesh, const FaceFrames& frames) {
  std::vector<Eigen::Vector3d> normal(mesh.n_vertices(), Eigen::Vector3d::Zero());
  for (const auto vh : mesh.vertices()) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    const Eigen::Vector3d p = toEigen(mesh.point(vh));
    for (const auto heh : vh.outgoing_halfedges()) {
      if (heh.is_boundary()) continue;
      const Eigen::Vector3d e1 = toEigen(mesh.point(heh.to())) - p;
      const Eigen::Vector3d e2 = toEigen(mesh.point(heh.prev().from())) - p;
      const double lengths = e1.squaredNorm() * e2.squaredNorm();
      if (lengths > 0.0) n += e1.cross(e2) / lengths;
    }
    if (!(n.norm() > 0.0) || !n.allFinite()) {  // degenerate fan: the faces' own normals
      n.setZero();
      for (const auto fh : vh.faces()) n += frames.normal[fh.idx()];
    }
    normal[vh.idx()] = n.norm() > 0.0 ? n.normalized() : Eigen::Vector3d::UnitZ();
  }
  return normal;
}

/// Least-squares second fundamental form of one face in its frame (x, y) from the vertex normal
/// differences along its edges: II·(e·x, e·y) = (Δn·x, Δn·y). False when the fit is degenerate.
bool fitFaceForm(const std::array<Eigen::Vector3d, 3>& p, const std::array<Eigen::Vector3d, 3>& n,
                 const TangentFrame& frame, FundamentalForm& form) {
  Eigen::Matrix3d normalMatrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const Eigen::Vector3d e = p[k] - p[j], dn = n[k] - n[j];
    const double eu = e.dot(frame.u), ev = e.dot(frame.v);
    const Eigen::Vector3d row1(eu, ev, 0.0), row2(0.0, eu, ev);
    normalMatrix += row1 * row1.transpose() + row2 * row2.transpose();
    rhs += row1 * dn.dot(frame.u) + row2 * dn.dot(frame.v);
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(normalMatrix);
  const double scale = normalMatrix.trace();
  if (!(scale > 0.0) || ldlt.info() != Eigen::Success ||
      !(ldlt.vectorD().minCoeff() > 1e-10 * scale))
    return false;
  const Eigen::Vector3d x = ldlt.solve(rhs);
  if (!x.allFinite()) return false;
  form = {x[0], x[1], x[2]};
  return true;
}

}  // namespace

std::string CurvatureOptions::validate() const {
  std::ostringstream message;
  if (!(planarThreshold >= 0.0) || !std::isfinite(planarThreshold))
    message << "planarThreshold must be a finite number >= 0, got " << planarThreshold;
  else if (!(strongAreaFraction >= 0.0 && strongAreaFraction <= 1.0))
    message << "strongAreaFraction must be in [0, 1], got " << strongAreaFraction;
  return message.str();
}

CurvatureClass classifyCurvature(double rho, double phi, double planarRho) {
  if (!(rho >= planarRho)) return CurvatureClass::Planar;
  const double a = std::abs(phi);
  if (a > 3.0 * M_PI / 8.0) return CurvatureClass::Elliptic;
  if (a < M_PI / 8.0) return CurvatureClass::Hyperbolic;
  return CurvatureClass::Cylindrical;
}

std::vector<double> mixedVoronoiCornerAreas(const TriMesh& mesh) {
  std::vector<double> area(mesh.n_halfedges(), 0.0);
  for (const auto fh : mesh.faces()) {
    const auto h0 = mesh.halfedge_handle(fh);
    const std::array<TriMesh::HalfedgeHandle, 3> h = {h0, mesh.next_halfedge_handle(h0),
                                                      mesh.prev_halfedge_handle(h0)};
    std::array<Eigen::Vector3d, 3> p;  // p[i]: the corner of h[i] (its to-vertex)
    for (int i = 0; i < 3; ++i) p[i] = toEigen(mesh.point(mesh.to_vertex_handle(h[i])));
    const double doubleArea = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    if (!(doubleArea > 0.0)) continue;
    std::array<double, 3> dot;  // dot[i]: (p[j] − p[i])·(p[k] − p[i]), the cosine numerator at i
    for (int i = 0; i < 3; ++i) dot[i] = (p[(i + 1) % 3] - p[i]).dot(p[(i + 2) % 3] - p[i]);
    const int obtuse = dot[0] < 0.0 ? 0 : dot[1] < 0.0 ? 1 : dot[2] < 0.0 ? 2 : -1;
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      double a = 0.0;
      if (obtuse < 0) {  // Voronoi: (|p_i p_k|² cot j + |p_i p_j|² cot k) / 8, cot = dot / |cross|
        a = ((p[k] - p[i]).squaredNorm() * dot[j] + (p[j] - p[i]).squaredNorm() * dot[k]) /
            (8.0 * doubleArea);
      } else {
        a = 0.5 * doubleArea * (obtuse == i ? 0.5 : 0.25);
      }
      area[h[i].idx()] = std::max(a, 0.0);
    }
  }
  return area;
}

Eigen::Matrix3d Curvature::tensor(int v) const {
  return kappaMax[v] * directionMax[v] * directionMax[v].transpose() +
         kappaMin[v] * directionMin[v] * directionMin[v].transpose();
}

std::vector<double> Curvature::largestAbsolute() const {
  std::vector<double> largest(kappaMax.size());
  for (std::size_t v = 0; v < largest.size(); ++v)
    largest[v] = std::max(std::abs(kappaMax[v]), std::abs(kappaMin[v]));
  return largest;
}

Curvature computeCurvature(const TriMesh& mesh, const CurvatureOptions& options) {
  if (const auto problem = options.validate(); !problem.empty())
    throw Error(ErrorCode::InvalidOption, "curvature options: " + problem);
  const int nv = static_cast<int>(mesh.n_vertices());
  const FaceFrames frames = computeFaceFrames(mesh);
  const std::vector<double> cornerArea = mixedVoronoiCornerAreas(mesh);

  Curvature c;
  c.normal = vertexNormals(mesh, frames);
  c.gauss = angleDefects(mesh);
  c.area.assign(nv, 0.0);
  for (const auto heh : mesh.halfedges())
    if (!heh.is_boundary()) c.area[heh.to().idx()] += cornerArea[heh.idx()];

  // Vertex frames: the first outgoing edge projected to the tangent plane.
  std::vector<TangentFrame> vertexFrame(nv);
  for (const auto vh : mesh.vertices()) {
    const Eigen::Vector3d& n = c.normal[vh.idx()];
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (const auto heh : vh.outgoing_halfedges()) {
      u = toEigen(mesh.point(heh.to()) - mesh.point(vh));
      break;
    }
    u -= u.dot(n) * n;
    u = u.norm() > 0.0 ? u.normalized() : anyPerpendicular(n);
    vertexFrame[vh.idx()] = {u, n.cross(u)};
  }

  std::vector<FundamentalForm> sum(nv);
  std::vector<double> weight(nv, 0.0);
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    const auto h0 = mesh.halfedge_handle(fh);
    const std::array<TriMesh::HalfedgeHandle, 3> h = {h0, mesh.next_halfedge_handle(h0),
                                                      mesh.prev_halfedge_handle(h0)};
    std::array<Eigen::Vector3d, 3> p, n;
    for (int i = 0; i < 3; ++i) {
      const int v = mesh.to_vertex_handle(h[i]).idx();
      p[i] = toEigen(mesh.point(mesh.to_vertex_handle(h[i])));
      n[i] = c.normal[v];
    }
    const TangentFrame faceFrame{frames.xAxis[f], frames.yAxis[f]};
    FundamentalForm form;
    if (!fitFaceForm(p, n, faceFrame, form)) continue;
    for (int i = 0; i < 3; ++i) {
      const int v = mesh.to_vertex_handle(h[i]).idx();
      const double w = cornerArea[h[i].idx()];
      if (!(w > 0.0)) continue;
      const FundamentalForm local =
          reexpress(form, rotateFrame(faceFrame, c.normal[v]), vertexFrame[v]);
      sum[v].ku += w * local.ku;
      sum[v].kuv += w * local.kuv;
      sum[v].kv += w * local.kv;
      weight[v] += w;
    }
  }

  c.kappaMax.assign(nv, 0.0);
  c.kappaMin.assign(nv, 0.0);
  c.directionMax.resize(nv);
  c.directionMin.resize(nv);
  c.rho.assign(nv, 0.0);
  c.phi.assign(nv, 0.0);
  for (int v = 0; v < nv; ++v) {
    FundamentalForm form;
    if (weight[v] > 0.0)
      form = {sum[v].ku / weight[v], sum[v].kuv / weight[v], sum[v].kv / weight[v]};
    const double mean = 0.5 * (form.ku + form.kv);
    const double radius = std::hypot(0.5 * (form.ku - form.kv), form.kuv);
    const double theta = 0.5 * std::atan2(2.0 * form.kuv, form.ku - form.kv);  // atan2(0,0) = 0
    c.kappaMax[v] = mean + radius;
    c.kappaMin[v] = mean - radius;
    c.directionMax[v] = std::cos(theta) * vertexFrame[v].u + std::sin(theta) * vertexFrame[v].v;
    c.directionMin[v] = c.normal[v].cross(c.directionMax[v]);
    c.rho[v] = std::hypot(c.kappaMax[v], c.kappaMin[v]);
    c.phi[v] = std::atan2(c.kappaMax[v] + c.kappaMin[v], c.kappaMax[v] - c.kappaMin[v]);
  }

  const double diagonal = boundingBoxDiagonal(mesh);
  c.planarRho = diagonal > 0.0 ? options.planarThreshold / diagonal : 0.0;
  c.classification.resize(nv);
  for (int v = 0; v < nv; ++v)
    c.classification[v] = classifyCurvature(c.rho[v], c.phi[v], c.planarRho);

  // t_ρ: walking the vertices by decreasing ρ (ties by index), the strong ones are those
  // reached before their accumulated mixed area exceeds the requested fraction of the total.
  std::vector<int> order(nv);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return c.rho[a] != c.rho[b] ? c.rho[a] > c.rho[b] : a < b; });
  const double total = std::accumulate(c.area.begin(), c.area.end(), 0.0);
  c.strong.assign(nv, false);
  c.strongRho = std::numeric_limits<double>::infinity();
  double accumulated = 0.0;
  for (const int v : order) {
    if (!(accumulated < options.strongAreaFraction * total) || !(c.rho[v] > 0.0)) break;
    c.strong[v] = true;
    c.strongRho = c.rho[v];
    accumulated += c.area[v];
  }
  return c;
}

}  // namespace hexcover
