#include "core/metrics/hausdorff.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/common/concurrency.h"
#include "core/common/error.h"

namespace hexcover {
namespace {

using Vec3 = Eigen::Vector3d;

}  // namespace

// ---------------------------------------------------------------------------------------------
// Sampling and refinement of one surface against another

void DistanceOptions::validate() const {
  if (!(relativeTolerance > 0.0 && relativeTolerance < 1.0))
    throw Error(ErrorCode::InvalidOption,
                "relativeTolerance must be in (0, 1), got " + std::to_string(relativeTolerance));
  if (maxSamples == 0) throw Error(ErrorCode::InvalidOption, "maxSamples must be positive");
  if (threads < 1)
    throw Error(ErrorCode::InvalidOption,
                "threads must be at least 1, got " + std::to_string(threads));
}

namespace {

/// A planar sub-triangle of a face of the sampled surface: three corner samples, one centroid
/// sample, its area and the upper bound U of the distance over it.
struct Cell {
  std::array<int, 3> corners;
  int centroid;
  double area;
  double bound = 0.0;
};

/// Samples of the surface `from` with their exact distance to `to`, and the cell partition.
class SurfaceSampler {
 public:
  SurfaceSampler(const TriangleArrays& from, const ClosestPointQuery& to,
                 const DistanceOptions& options)
      : to_(to), options_(options) {
    // Vertex samples keep the vertex index as sample id.
    points_ = from.positions;
    distance_.assign(points_.size(), 0.0);
    face_.assign(points_.size(), -1);
    hint_.assign(points_.size(), -1);
    std::vector<int> vertexSamples;
    for (std::size_t v = 0; v < points_.size(); ++v)
      if (from.referenced[v]) vertexSamples.push_back(static_cast<int>(v));
    query(vertexSamples);

    cells_.reserve(from.triangles.size());
    const std::size_t firstNew = points_.size();
    for (const auto& t : from.triangles) {
      const Vec3 a = points_[t[0]], b = points_[t[1]], c = points_[t[2]];
      const double area = 0.5 * (b - a).cross(c - a).norm();
      cells_.push_back({t, addSample((a + b + c) / 3.0, face_[t[0]]), area});
    }
    queryFrom(firstNew);
    parallelFor(cells_.size(), options_.threads,
                [&](std::size_t i) { cells_[i].bound = bound(cells_[i]); });
  }

  /// Splits cells (area-proportional sampling, then bound-driven refinement) until the
  /// tolerance is met or the budget is spent.
  void refine(double maxCellArea, double absoluteTolerance) {
    for (;;) {
      const double threshold = largest() * (1.0 + options_.relativeTolerance) + absoluteTolerance;
      std::vector<int> selected;
      for (std::size_t i = 0; i < cells_.size(); ++i)
        if (cells_[i].area > maxCellArea || cells_[i].bound > threshold)
          selected.push_back(static_cast<int>(i));
      if (selected.empty()) return;
      // Each split adds at most 3 midpoints and 4 centroids.
      const std::size_t room =
          points_.size() < options_.maxSamples ? options_.maxSamples - points_.size() : 0;
      if (7 * selected.size() > room) {
        std::stable_sort(selected.begin(), selected.end(),
                         [&](int x, int y) { return cells_[x].bound > cells_[y].bound; });
        selected.resize(room / 7);
        if (selected.empty()) return;
      }
      split(selected);
      ++rounds_;
    }
  }

  OneSidedDistance result(double relativeTolerance, double absoluteTolerance) const {
    OneSidedDistance out;
    int farthest = -1;
    for (std::size_t i = 0; i < points_.size(); ++i)
      if (face_[i] >= 0 && (farthest < 0 || distance_[i] > distance_[farthest]))
        farthest = static_cast<int>(i);
    out.max = distance_[farthest];
    out.farthestPoint = points_[farthest];
    out.maxUpperBound = out.max;
    double integral = 0.0, integralSquared = 0.0;
    for (const auto& cell : cells_) {
      out.maxUpperBound = std::max(out.maxUpperBound, cell.bound);
      out.area += cell.area;
      const double d = distance_[cell.centroid];
      integral += cell.area * d;
      integralSquared += cell.area * d * d;
    }
    if (out.area > 0.0) {
      out.mean = integral / out.area;
      out.rms = std::sqrt(integralSquared / out.area);
    }
    out.certified = out.maxUpperBound <= out.max * (1.0 + relativeTolerance) + absoluteTolerance;
    out.samples = queries_;
    out.refinementRounds = rounds_;
    return out;
  }

  double totalArea() const {
    double area = 0.0;
    for (const auto& cell : cells_) area += cell.area;
    return area;
  }

 private:
  int addSample(const Vec3& p, int hint) {
    points_.push_back(p);
    distance_.push_back(0.0);
    face_.push_back(-1);
    hint_.push_back(hint);
    return static_cast<int>(points_.size() - 1);
  }

  void query(const std::vector<int>& samples) {
    parallelFor(samples.size(), options_.threads, [&](std::size_t k) {
      const int s = samples[k];
      const auto r = to_.closest(points_[s], hint_[s]);
      distance_[s] = r.distance;
      face_[s] = r.face;
    });
    queries_ += samples.size();
    for (const int s : samples) largest_ = std::max(largest_, distance_[s]);
  }
  void queryFrom(std::size_t first) {
    std::vector<int> samples(points_.size() - first);
    std::iota(samples.begin(), samples.end(), static_cast<int>(first));
    query(samples);
  }

  double largest() const { return largest_; }

  /// U = min over the closest triangles T of the cell's samples of max_i d(corner_i, T):
  /// d(·, T) is convex, so its maximum over the cell is at a corner.
  double bound(const Cell& cell) const {
    const std::array<int, 4> candidates{face_[cell.corners[0]], face_[cell.corners[1]],
                                        face_[cell.corners[2]], face_[cell.centroid]};
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 4; ++k) {
      const int t = candidates[k];
      if (std::find(candidates.begin(), candidates.begin() + k, t) != candidates.begin() + k)
        continue;
      double worst = 0.0;
      for (const int c : cell.corners) {
        worst = std::max(worst, face_[c] == t ? distance_[c] : to_.distanceToFace(points_[c], t));
        if (worst >= best) break;
      }
      best = std::min(best, worst);
    }
    return best;
  }

  int midpoint(int a, int b) {
    const auto key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) |
                     static_cast<std::uint32_t>(std::max(a, b));
    const auto [it, inserted] = midpoints_.try_emplace(key, 0);
    if (inserted) it->second = addSample(0.5 * (points_[a] + points_[b]), face_[a]);
    return it->second;
  }

  /// Splits each selected cell 1-to-4 at its edge midpoints (the children replace it).
  void split(const std::vector<int>& selected) {
    const std::size_t firstSample = points_.size();
    const std::size_t firstCell = cells_.size();
    std::vector<int> changed;
    for (const int i : selected) {
      const Cell parent = cells_[i];
      const auto [a, b, c] = parent.corners;
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      const std::array<std::array<int, 3>, 4> children{
          {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}}};
      for (int k = 0; k < 4; ++k) {
        const auto& t = children[k];
        const int centroid = addSample((points_[t[0]] + points_[t[1]] + points_[t[2]]) / 3.0,
                                       face_[parent.centroid]);
        const Cell child{t, centroid, parent.area / 4.0};
        if (k == 0) {
          cells_[i] = child;
          changed.push_back(i);
        } else {
          cells_.push_back(child);
        }
      }
    }
    for (std::size_t i = firstCell; i < cells_.size(); ++i) changed.push_back(static_cast<int>(i));
    queryFrom(firstSample);
    parallelFor(changed.size(), options_.threads,
                [&](std::size_t k) { cells_[changed[k]].bound = bound(cells_[changed[k]]); });
  }

  const ClosestPointQuery& to_;
  const DistanceOptions& options_;
  std::vector<Vec3> points_;
  std::vector<double> distance_;
  std::vector<int> face_;  ///< closest face of `to`, −1 for samples not queried
  std::vector<int> hint_;
  std::vector<Cell> cells_;
  std::unordered_map<std::uint64_t, int> midpoints_;
  double largest_ = 0.0;
  std::size_t queries_ = 0;
  int rounds_ = 0;
};

}  // namespace

OneSidedDistance oneSidedDistance(const TriMesh& from, const ClosestPointQuery& to,
                                  const DistanceOptions& options) {
  options.validate();
  const TriangleArrays surface(from);
  if (surface.triangles.empty())
    throw Error(ErrorCode::InvalidMesh, "cannot measure distances from a mesh without faces");
  SurfaceSampler sampler(surface, to, options);
  const double area = sampler.totalArea();
  const std::size_t cells = std::max(surface.triangles.size(), options.minSamples);
  const double maxCellArea = 2.0 * area / static_cast<double>(cells);
  // Distances below this are rounding noise (coincident surfaces).
  const double absoluteTolerance = 1e-9 * boundingBoxDiagonal(from);
  sampler.refine(maxCellArea, absoluteTolerance);
  return sampler.result(options.relativeTolerance, absoluteTolerance);
}

double TwoSidedDistance::hausdorff() const { return std::max(aToB.max, bToA.max); }
double TwoSidedDistance::hausdorffUpperBound() const {
  return std::max(aToB.maxUpperBound, bToA.maxUpperBound);
}
double TwoSidedDistance::mean() const {
  const double area = aToB.area + bToA.area;
  return area > 0.0 ? (aToB.mean * aToB.area + bToA.mean * bToA.area) / area : 0.0;
}
double TwoSidedDistance::rms() const {
  const double area = aToB.area + bToA.area;
  return area > 0.0
             ? std::sqrt((aToB.rms * aToB.rms * aToB.area + bToA.rms * bToA.rms * bToA.area) / area)
             : 0.0;
}

TwoSidedDistance twoSidedDistance(const TriMesh& a, const TriMesh& b,
                                  const DistanceOptions& options) {
  options.validate();
  const ClosestPointQuery toA(a), toB(b);
  return {oneSidedDistance(a, toB, options), oneSidedDistance(b, toA, options)};
}

}  // namespace hexcover
