#include "core/metrics/metrics.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "core/common/error.h"

namespace hexcover {
namespace {

constexpr double kDegrees = 180.0 / M_PI;

/// Running mean and population variance (Welford).
class RunningStats {
 public:
  void add(double x) {
    ++count_;
    const double delta = x - mean_;
    mean_ += delta / static_cast<double>(count_);
    m2_ += delta * (x - mean_);
    min_ = std::min(min_, x);
    max_ = std::max(max_, x);
  }
  double mean() const { return mean_; }
  double sd() const { return count_ > 0 ? std::sqrt(m2_ / static_cast<double>(count_)) : 0.0; }
  double min() const { return count_ > 0 ? min_ : 0.0; }
  double max() const { return count_ > 0 ? max_ : 0.0; }
  std::size_t count() const { return count_; }

 private:
  std::size_t count_ = 0;
  double mean_ = 0.0, m2_ = 0.0;
  double min_ = std::numeric_limits<double>::infinity();
  double max_ = -std::numeric_limits<double>::infinity();
};

/// Angle between u and v in degrees; atan2 keeps it accurate near 0° and 180° and gives 0 for a
/// zero-length edge.
double angleDegrees(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v)) * kDegrees;
}

/// The corner angles, smallest angle per face, triangle quality and edge lengths of a mesh, as
/// QualityReport states them.
struct ShapeTally {
  RunningStats angles, minAngles, quality, edges;
  std::size_t below30 = 0, above90 = 0;

  void addAngle(double angle) {
    angles.add(angle);
    below30 += angle < 30.0;
    above90 += angle > 90.0;
  }
  /// Q = 6·A / (√3·p·L_max) of triangle (a, b, c).
  void addTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const double ab = (b - a).norm(), bc = (c - b).norm(), ca = (a - c).norm();
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const double denominator = std::sqrt(3.0) * 0.5 * (ab + bc + ca) * std::max({ab, bc, ca});
    quality.add(denominator > 0.0 ? 6.0 * area / denominator : 0.0);
  }
  void store(QualityReport& report) const {
    const double corners = static_cast<double>(angles.count());
    report.angleMin = angles.min();
    report.angleMax = angles.max();
    report.angleMean = angles.mean();
    report.angleSd = angles.sd();
    report.anglesBelow30Pct = corners > 0 ? 100.0 * static_cast<double>(below30) / corners : 0.0;
    report.anglesAbove90Pct = corners > 0 ? 100.0 * static_cast<double>(above90) / corners : 0.0;
    report.minAngleMean = minAngles.mean();
    report.qualityMin = quality.min();
    report.qualityMean = quality.mean();
    report.edgeLengthMean = edges.mean();
    report.edgeLengthCv = edges.mean() > 0.0 ? edges.sd() / edges.mean() : 0.0;
  }
};

void measureShape(const TriMesh& mesh, QualityReport& report) {
  ShapeTally tally;
  for (const auto fh : mesh.faces()) {
    const auto h = fh.halfedge();
    const std::array<Eigen::Vector3d, 3> p{toEigen(mesh.point(h.from())),
                                           toEigen(mesh.point(h.to())),
                                           toEigen(mesh.point(h.next().to()))};
    double smallest = 180.0;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d& a = p[i];
      const double angle = angleDegrees(p[(i + 1) % 3] - a, p[(i + 2) % 3] - a);
      tally.addAngle(angle);
      smallest = std::min(smallest, angle);
    }
    tally.minAngles.add(smallest);
    tally.addTriangle(p[0], p[1], p[2]);
  }
  for (const auto eh : mesh.edges()) tally.edges.add(mesh.calc_edge_length(eh));
  tally.store(report);

  for (const auto vh : mesh.vertices()) {
    const int valence = static_cast<int>(mesh.valence(vh));
    if (valence == 0) continue;  // isolated vertex
    ++report.vertices;
    if (mesh.is_boundary(vh)) {
      ++report.valenceBoundary[valence];
      report.irregularBoundary += valence != 4;
    } else {
      ++report.valenceInterior[valence];
      report.irregularInterior += valence != 6;
    }
  }
  report.faces = static_cast<int>(mesh.n_faces());
}

/// measureShape of a polygon mesh (see measurePolygonQuality).
void measurePolygonShape(const PolygonSoup& mesh, QualityReport& report) {
  ShapeTally tally;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const std::size_t size = mesh.faceSize(f);
    const auto at = [&](std::size_t k) -> const Eigen::Vector3d& {
      return mesh.positions[mesh.cornerVertices[mesh.faceStarts[f] + k % size]];
    };
    double smallest = 180.0;
    for (std::size_t k = 0; k < size; ++k) {
      const double angle = angleDegrees(at(k + 1) - at(k), at(k + size - 1) - at(k));
      tally.addAngle(angle);
      smallest = std::min(smallest, angle);
    }
    tally.minAngles.add(smallest);
    report.quads += size == 4;
    if (size == 3) tally.addTriangle(at(0), at(1), at(2));
  }
  const SoupEdges soup = soupEdges(mesh);
  std::vector<int> valence(mesh.vertexCount(), 0);
  std::vector<bool> onBoundary(mesh.vertexCount(), false);
  for (std::size_t e = 0; e < soup.edges.size(); ++e) {
    const auto [a, b] = soup.edges[e];
    tally.edges.add((mesh.positions[b] - mesh.positions[a]).norm());
    ++valence[a];
    ++valence[b];
    if (soup.uses[e] == 1) onBoundary[a] = onBoundary[b] = true;
  }
  tally.store(report);

  for (std::size_t v = 0; v < valence.size(); ++v) {
    if (valence[v] == 0) continue;  // isolated vertex
    ++report.vertices;
    if (onBoundary[v]) {
      ++report.valenceBoundary[valence[v]];
      report.irregularBoundary += valence[v] != 3;
    } else {
      ++report.valenceInterior[valence[v]];
      report.irregularInterior += valence[v] != 4;
    }
  }
  report.faces = static_cast<int>(mesh.faceCount());
}

DistanceReport measureDistance(const TriMesh& result, const TriMesh& reference,
                               const DistanceOptions& options) {
  DistanceReport report;
  report.referenceDiagonal = boundingBoxDiagonal(reference);
  if (!(report.referenceDiagonal > 0.0))
    throw Error(ErrorCode::InvalidMesh,
                "the reference mesh has a zero bounding-box diagonal: distances in percent of it "
                "are undefined");
  const TwoSidedDistance d = twoSidedDistance(result, reference, options);
  const double pct = 100.0 / report.referenceDiagonal;
  report.hausdorffPct = pct * d.hausdorff();
  report.hausdorffUpperBoundPct = pct * d.hausdorffUpperBound();
  report.hausdorffCertified = d.aToB.certified && d.bToA.certified;
  report.meanPct = pct * d.mean();
  report.rmsPct = pct * d.rms();
  report.resultToReferenceMaxPct = pct * d.aToB.max;
  report.resultToReferenceMeanPct = pct * d.aToB.mean;
  report.resultToReferenceRmsPct = pct * d.aToB.rms;
  report.referenceToResultMaxPct = pct * d.bToA.max;
  report.referenceToResultMeanPct = pct * d.bToA.mean;
  report.referenceToResultRmsPct = pct * d.bToA.rms;
  report.samples = d.aToB.samples + d.bToA.samples;
  return report;
}

/// Topology of `result` and, against `reference`, its topology match and distances.
void measureAgainstReference(const TriMesh& result, const TriMesh* reference,
                             const MetricsOptions& options, QualityReport& report) {
  {
    ScopedTimer timer(report.timings, "topology");
    report.topology = computeTopology(result);
    if (reference)
      report.topologyMatchesReference = report.topology.sameAs(computeTopology(*reference));
  }
  if (reference) {
    ScopedTimer timer(report.timings, "distance");
    report.distance = measureDistance(result, *reference, options.distance);
  }
}

void checkMeasurable(const TriMesh& result, const TriMesh* reference,
                     const MetricsOptions& options) {
  options.validate();
  if (result.n_faces() == 0)
    throw Error(ErrorCode::InvalidMesh, "the result mesh has no faces: nothing to measure");
  if (reference && reference->n_faces() == 0)
    throw Error(ErrorCode::InvalidMesh, "the reference mesh has no faces: nothing to compare with");
}

}  // namespace

QualityReport measureQuality(const TriMesh& result, const TriMesh* reference,
                             const MetricsOptions& options) {
  checkMeasurable(result, reference, options);
  QualityReport report;
  {
    ScopedTimer timer(report.timings, "shape");
    measureShape(result, report);
  }
  measureAgainstReference(result, reference, options, report);
  return report;
}

QualityReport measurePolygonQuality(const PolygonSoup& result, const TriMesh& triangulated,
                                    const TriMesh* reference, const MetricsOptions& options) {
  checkMeasurable(triangulated, reference, options);
  QualityReport report;
  {
    ScopedTimer timer(report.timings, "shape");
    measurePolygonShape(result, report);
  }
  measureAgainstReference(triangulated, reference, options, report);
  return report;
}

}  // namespace hexcover
