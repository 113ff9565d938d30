#include "core/field/singularities.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace hexcover::field {
namespace {

/// x reduced by whole multiples of `period` into [−period/2, period/2]; also returns the multiple.
double reduce(double x, double period, long long& multiple) {
  multiple = std::llround(x / period);
  return x - static_cast<double>(multiple) * period;
}

}  // namespace

FieldGeometry::FieldGeometry(const TriMesh& mesh)
    : frames(computeFaceFrames(mesh)),
      transport(edgeTransportAngles(mesh, frames)),
      angleDefect(angleDefects(mesh)),
      components(faceComponents(mesh)),
      vertexComponent(mesh.n_vertices(), -1) {
  for (const auto vh : mesh.vertices())
    for (const auto fh : vh.faces()) {
      vertexComponent[vh.idx()] = components.faceComponent[fh.idx()];
      break;
    }
}

std::vector<double> boundaryEdgeAngles(const TriMesh& mesh, const FieldGeometry& geometry) {
  std::vector<double> angle(mesh.n_edges(), std::numeric_limits<double>::quiet_NaN());
  for (const auto eh : mesh.edges()) {
    if (!mesh.is_boundary(eh)) continue;
    const auto h = eh.h0().is_boundary() ? eh.h1() : eh.h0();
    const Eigen::Vector3d d = toEigen(mesh.point(h.to()) - mesh.point(h.from()));
    angle[eh.idx()] = geometry.frames.angleOf(h.face().idx(), d);
  }
  return angle;
}

RosyField rosyFieldFromAngles(const TriMesh& mesh, const FieldGeometry& geometry,
                              const std::vector<double>& angles, int n,
                              const std::vector<double>& matchingShift) {
  const double period = 2.0 * M_PI / n;
  RosyField field;
  field.n = n;
  field.faceDirection.resize(mesh.n_faces());
  for (const auto fh : mesh.faces())
    field.faceDirection[fh.idx()] = geometry.frames.direction(fh.idx(), angles[fh.idx()]);

  // Σ over the vertex's loop of the field's turn relative to transport, and the boundary terms.
  std::vector<double> turn(mesh.n_vertices(), 0.0);
  field.edgeMatching.assign(mesh.n_edges(), 0);
  for (const auto eh : mesh.edges()) {
    const auto h0 = eh.h0(), h1 = eh.h1();
    if (mesh.is_boundary(eh)) {
      const auto h = h0.is_boundary() ? h1 : h0;  // u→w with the surface on its left
      const Eigen::Vector3d d = toEigen(mesh.point(h.to()) - mesh.point(h.from()));
      long long unused = 0;
      const double psi = reduce(angles[h.face().idx()] - geometry.frames.angleOf(h.face().idx(), d),
                                period, unused);
      turn[h.from().idx()] += psi;
      turn[h.to().idx()] -= psi;
      continue;
    }
    const int f0 = h0.face().idx(), f1 = h1.face().idx();
    // x = θ0 + ρ + s − θ1 = 2π k / N − δ' with δ' in [−π/N, π/N]; r = k mod N. The turn
    // relative to ρ with that matching is δ = δ' + s.
    long long k = 0;
    const double shift = matchingShift.empty() ? 0.0 : matchingShift[eh.idx()];
    const double delta =
        shift - reduce(angles[f0] + geometry.transport[eh.idx()] + shift - angles[f1], period, k);
    field.edgeMatching[eh.idx()] = static_cast<int>(((k % n) + n) % n);
    turn[h0.to().idx()] += delta;
    turn[h1.to().idx()] -= delta;
  }

  std::vector<long long> componentSum(geometry.components.count, 0);
  for (const auto vh : mesh.vertices()) {
    const int v = vh.idx();
    if (geometry.vertexComponent[v] < 0) continue;
    const double value = n * (geometry.angleDefect[v] + turn[v]) / (2.0 * M_PI);
    const long long index = std::llround(value);
    if (!(std::abs(value - static_cast<double>(index)) < 1e-6)) {
      std::ostringstream message;
      message << "rosy field: the index of vertex " << v << " is not an integer (" << value
              << "): the transport, angle defect and field turn are inconsistent";
      throw std::logic_error(message.str());
    }
    componentSum[geometry.vertexComponent[v]] += index;
    if (index != 0)
      field.singularities.push_back(
          {v, static_cast<int>(index), toEigen(mesh.point(vh)), mesh.is_boundary(vh)});
  }
  for (int c = 0; c < geometry.components.count; ++c) {
    const long long expected =
        static_cast<long long>(n) * geometry.components.eulerCharacteristic[c];
    if (componentSum[c] != expected) {
      std::ostringstream message;
      message << "rosy field: Poincaré–Hopf fails on component " << c
              << ": Σ I = " << componentSum[c] << " but N·χ = " << expected;
      throw std::logic_error(message.str());
    }
    field.eulerCharacteristic += geometry.components.eulerCharacteristic[c];
  }
  field.singularitiesInitial = static_cast<int>(field.singularities.size());
  return field;
}

}  // namespace hexcover::field
