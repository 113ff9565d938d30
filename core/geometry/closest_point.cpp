#include "core/geometry/closest_point.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/common/error.h"

namespace hexcover {

using Vec3 = Eigen::Vector3d;

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;
  if (!(denom > 0.0)) {  // degenerate (collinear) triangle: closest of its three edges
    const auto onSegment = [&](const Vec3& s, const Vec3& t) {
      const Vec3 st = t - s;
      const double len2 = st.squaredNorm();
      const double u = len2 > 0.0 ? std::clamp((p - s).dot(st) / len2, 0.0, 1.0) : 0.0;
      return Vec3(s + u * st);
    };
    std::array<Vec3, 3> candidates{onSegment(a, b), onSegment(b, c), onSegment(c, a)};
    return *std::min_element(candidates.begin(), candidates.end(),
                             [&](const Vec3& x, const Vec3& y) {
                               return (x - p).squaredNorm() < (y - p).squaredNorm();
                             });
  }
  return a + (vb / denom) * ab + (vc / denom) * ac;
}

TriangleArrays::TriangleArrays(const TriMesh& mesh)
    : positions(mesh.n_vertices()), referenced(mesh.n_vertices(), 0) {
  for (const auto vh : mesh.vertices()) positions[vh.idx()] = toEigen(mesh.point(vh));
  triangles.reserve(mesh.n_faces());
  for (const auto fh : mesh.faces()) {
    const auto h = fh.halfedge();
    const std::array<int, 3> t{h.from().idx(), h.to().idx(), h.next().to().idx()};
    for (const int v : t) {
      if (!positions[v].allFinite())
        throw Error(ErrorCode::InvalidMesh, "vertex " + std::to_string(v) +
                                                " has a non-finite coordinate: distances to or "
                                                "from this mesh are undefined");
      referenced[v] = 1;
    }
    triangles.push_back(t);
  }
}

// ---------------------------------------------------------------------------------------------
// ClosestPointQuery

struct ClosestPointQuery::Impl {
  TriangleArrays mesh;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  /// The BVH holds float copies of the points relative to this origin (the centre of the
  /// bounding box): far from the coordinate origin (georeferenced scans, ~10^6 units away) float
  /// coordinates would otherwise round by more than the mesh's own details.
  Vec3 origin = Vec3::Zero();
  /// Float rounding of the BVH: the search radius is kept this much larger than the best exact
  /// distance so that no closer triangle is culled.
  double slack = 0.0;
  /// Per triangle: unit normal, zero for a sliver (sine of its corner at the first vertex below
  /// kSliverSine: the normal's direction would be off by up to 1e-16 / kSliverSine). The
  /// distance to a triangle's plane is a lower bound of the distance to the triangle, and the
  /// cheaper test.
  std::vector<Vec3> unitNormal;
  static constexpr double kSliverSine = 1e-5;
  /// The rounding of the plane distance and of the exact distance stays below
  /// kRoundingMargin · (distance + 4 · extent): |p − a| ≤ best + the triangle's diameter.
  static constexpr double kRoundingMargin = 1e-9;
  double extent = 0.0;  ///< largest |coordinate − origin| of the mesh's vertices

  explicit Impl(const TriMesh& target) : mesh(target) {
    if (mesh.triangles.empty())
      throw Error(ErrorCode::InvalidMesh, "cannot measure distances to a mesh without faces");
    Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
      if (mesh.referenced[v]) {
        low = low.cwiseMin(mesh.positions[v]);
        high = high.cwiseMax(mesh.positions[v]);
      }
    origin = 0.5 * (low + high);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
      if (mesh.referenced[v])
        extent = std::max(extent, (mesh.positions[v] - origin).cwiseAbs().maxCoeff());
    slack = 16.0 * std::numeric_limits<float>::epsilon() * std::max(extent, 1e-30);
    unitNormal.reserve(mesh.triangles.size());
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const int face = static_cast<int>(f);
      const Vec3 u = mesh.corner(face, 1) - mesh.corner(face, 0);
      const Vec3 w = mesh.corner(face, 2) - mesh.corner(face, 0);
      const Vec3 normal = u.cross(w);
      const double length = normal.norm();
      unitNormal.push_back(length > kSliverSine * u.norm() * w.norm() ? Vec3(normal / length)
                                                                      : Vec3::Zero());
    }

    device = rtcNewDevice("verbose=0");
    if (!device) throw Error(ErrorCode::NumericalFailure, "Embree: cannot create a device");
    scene = rtcNewScene(device);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh.triangles.size()));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      release();
      throw Error(ErrorCode::LimitExceeded, "Embree: out of memory for the distance BVH");
    }
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
      for (int k = 0; k < 3; ++k)
        vertices[3 * v + k] =
            mesh.referenced[v] ? static_cast<float>(mesh.positions[v][k] - origin[k]) : 0.0f;
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
      for (int k = 0; k < 3; ++k) indices[3 * f + k] = static_cast<unsigned>(mesh.triangles[f][k]);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE) {
      release();
      throw Error(ErrorCode::NumericalFailure, "Embree: building the distance BVH failed");
    }
  }
  ~Impl() { release(); }

  void release() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
    scene = nullptr;
    device = nullptr;
  }

  Vec3 closestPointOnFace(const Vec3& p, int f) const {
    return closestPointOnTriangle(p, mesh.corner(f, 0), mesh.corner(f, 1), mesh.corner(f, 2));
  }
  double distanceToFace(const Vec3& p, int f) const {
    return (closestPointOnFace(p, f) - p).norm();
  }

  /// State of one query, passed to the Embree callback through userPtr.
  struct Search {
    const Impl* self;
    Vec3 p;
    double best;
    int bestFace;
    Vec3 bestPoint = Vec3::Zero();
    int visited = 0;
  };

  static bool visitTriangle(RTCPointQueryFunctionArguments* args) {
    auto& search = *static_cast<Search*>(args->userPtr);
    const int f = static_cast<int>(args->primID);
    ++search.visited;
    // A triangle whose plane is farther than the best distance (beyond rounding) cannot win, not
    // even a tie: the exact distance is skipped.
    const Impl& self = *search.self;
    const double planeDistance =
        std::abs(self.unitNormal[f].dot(search.p - self.mesh.corner(f, 0)));
    if (planeDistance > search.best + kRoundingMargin * (search.best + 4.0 * self.extent))
      return false;
    const Vec3 point = self.closestPointOnFace(search.p, f);
    const double d = (point - search.p).norm();
    if (d < search.best || (d == search.best && f < search.bestFace)) {
      search.best = d;
      search.bestFace = f;
      search.bestPoint = point;
    }
    const float radius = static_cast<float>(search.best + self.slack);
    if (radius < args->query->radius) {
      args->query->radius = radius;
      return true;
    }
    return false;
  }

  Result closest(const Vec3& p, int hintFace) const {
    Search search{this, p, std::numeric_limits<double>::infinity(), -1};
    if (hintFace >= 0) {
      search.bestPoint = closestPointOnFace(p, hintFace);
      search.best = (search.bestPoint - p).norm();
      search.bestFace = hintFace;
    }
    RTCPointQuery query;
    query.x = static_cast<float>(p.x() - origin.x());
    query.y = static_cast<float>(p.y() - origin.y());
    query.z = static_cast<float>(p.z() - origin.z());
    query.time = 0.0f;
    // The float query point is off by up to an ulp per coordinate; the slack covers it too.
    query.radius = std::isfinite(search.best) ? static_cast<float>(search.best + slack + slack)
                                              : std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene, &query, &context, &Impl::visitTriangle, &search);
    return {search.best, search.bestFace, search.bestPoint, search.visited};
  }
};

ClosestPointQuery::ClosestPointQuery(const TriMesh& target)
    : impl_(std::make_unique<Impl>(target)) {}
ClosestPointQuery::~ClosestPointQuery() = default;

ClosestPointQuery::Result ClosestPointQuery::closest(const Vec3& p, int hintFace) const {
  return impl_->closest(p, hintFace);
}

double ClosestPointQuery::distanceToFace(const Vec3& p, int face) const {
  return impl_->distanceToFace(p, face);
}

const TriangleArrays& ClosestPointQuery::triangles() const { return impl_->mesh; }

}  // namespace hexcover
