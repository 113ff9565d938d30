#include "core/metrics/metrics.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

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

void measureShape(const TriMesh& mesh, QualityReport& report) {
  RunningStats angles, minAngles, quality;
  std::size_t below30 = 0, above90 = 0;
  for (const auto fh : mesh.faces()) {
    const auto h = fh.halfedge();
    const std::array<Eigen::Vector3d, 3> p{toEigen(mesh.point(h.from())),
                                           toEigen(mesh.point(h.to())),
                                           toEigen(mesh.point(h.next().to()))};
    double smallest = 180.0, perimeter = 0.0, longest = 0.0;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d& a = p[i];
      const Eigen::Vector3d& b = p[(i + 1) % 3];
      const Eigen::Vector3d& c = p[(i + 2) % 3];
      const double angle = angleDegrees(b - a, c - a);
      angles.add(angle);
      smallest = std::min(smallest, angle);
      below30 += angle < 30.0;
      above90 += angle > 90.0;
      const double length = (b - a).norm();
      perimeter += length;
      longest = std::max(longest, length);
    }
    minAngles.add(smallest);
    const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    const double denominator = std::sqrt(3.0) * 0.5 * perimeter * longest;
    quality.add(denominator > 0.0 ? 6.0 * area / denominator : 0.0);
  }
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

  RunningStats edges;
  for (const auto eh : mesh.edges()) edges.add(mesh.calc_edge_length(eh));
  report.edgeLengthMean = edges.mean();
  report.edgeLengthCv = edges.mean() > 0.0 ? edges.sd() / edges.mean() : 0.0;

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

}  // namespace

QualityReport measureQuality(const TriMesh& result, const TriMesh* reference,
                             const MetricsOptions& options) {
  options.validate();
  if (result.n_faces() == 0)
    throw Error(ErrorCode::InvalidMesh, "the result mesh has no faces: nothing to measure");
  if (reference && reference->n_faces() == 0)
    throw Error(ErrorCode::InvalidMesh, "the reference mesh has no faces: nothing to compare with");
  QualityReport report;
  {
    ScopedTimer timer(report.timings, "shape");
    measureShape(result, report);
  }
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
  return report;
}

}  // namespace hexcover
