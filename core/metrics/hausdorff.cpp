#include "core/metrics/hausdorff.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
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
  bool tight = false;  ///< `bound` is the split bound (`tightBound`)
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
      std::vector<int> loose;
      for (std::size_t i = 0; i < cells_.size(); ++i)
        if (!cells_[i].tight && cells_[i].bound > threshold && cells_[i].area <= maxCellArea)
          loose.push_back(static_cast<int>(i));
      parallelFor(loose.size(), options_.threads, [&](std::size_t k) {
        Cell& cell = cells_[loose[k]];
        cell.bound = tightBound(cell);
        cell.tight = true;
      });
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

  /// Upper bound U of d_B over a cell, from the closest triangles C of its corners and
  /// centroid: for a fixed triangle T, d(·, T) is convex, so its maximum over a convex piece of
  /// the cell is at one of the piece's corners. This is min over T ∈ C of max_i d(corner_i, T).
  double bound(const Cell& cell) const {
    return lowestPieceBound(whole(cell), closestTriangles(cell),
                            std::numeric_limits<double>::infinity());
  }

  /// The cell's bound lowered by cutting it into pieces with planes that separate the triangles
  /// of C (`splitBound`). Costlier, so computed only for cells that refinement would split.
  double tightBound(const Cell& cell) const {
    const Candidates candidates = closestTriangles(cell);
    return candidates.count > 1 ? splitBound(whole(cell), candidates, cell.bound) : cell.bound;
  }

  /// Closest triangles of a cell's samples (at most 4, distinct).
  struct Candidates {
    std::array<int, 4> faces{};
    int count = 0;

    Candidates without(int k) const {
      Candidates rest;
      for (int i = 0; i < count; ++i)
        if (i != k) rest.faces[rest.count++] = faces[i];
      return rest;
    }
  };

  /// A convex polygon in a cell: a triangle cut by at most 3 planes has at most 6 corners.
  /// `sample` is the corner's sample index, −1 for a point where a plane cut an edge.
  struct Piece {
    std::array<Vec3, 6> points;
    std::array<int, 6> samples{};
    int size = 0;

    void add(const Vec3& p, int sample) {
      points[size] = p;
      samples[size++] = sample;
    }
  };

  Candidates closestTriangles(const Cell& cell) const {
    Candidates candidates;
    for (const int t : {face_[cell.corners[0]], face_[cell.corners[1]], face_[cell.corners[2]],
                        face_[cell.centroid]})
      if (std::find(candidates.faces.begin(), candidates.faces.begin() + candidates.count, t) ==
          candidates.faces.begin() + candidates.count)
        candidates.faces[candidates.count++] = t;
    return candidates;
  }

  Piece whole(const Cell& cell) const {
    Piece piece;
    for (const int c : cell.corners) piece.add(points_[c], c);
    return piece;
  }

  /// A plane m·(p − origin) = 0 that separates two triangles of `to`, with the first on its
  /// positive side.
  struct Separator {
    Vec3 origin;
    Vec3 normal;
  };

  /// For triangles sharing an edge (a, b): the plane through the edge that bisects their
  /// dihedral angle, m = w1 − w2 with w_i the unit vector in t_i's plane, perpendicular to the
  /// edge, pointing into t_i; near a smooth surface it divides the cell as the closest points do.
  /// For triangles sharing only a vertex v: m = u1 − u2, u_i the unit vector from v to t_i's
  /// centroid. Nothing for triangles apart or folded onto each other.
  std::optional<Separator> separator(int t1, int t2) const {
    const TriangleArrays& target = to_.triangles();
    const auto& f1 = target.triangles[t1];
    const auto& f2 = target.triangles[t2];
    std::array<int, 3> shared{};
    int sharedCount = 0;
    for (const int v : f1)
      if (std::find(f2.begin(), f2.end(), v) != f2.end()) shared[sharedCount++] = v;
    if (sharedCount == 0 || sharedCount == 3) return std::nullopt;
    const Vec3& origin = target.positions[shared[0]];
    const Vec3 axis =
        sharedCount == 2 ? (target.positions[shared[1]] - origin).normalized() : Vec3::Zero();
    const auto direction = [&](const std::array<int, 3>& face) {
      const Vec3 r =
          (target.positions[face[0]] + target.positions[face[1]] + target.positions[face[2]]) /
              3.0 -
          origin;
      return (r - r.dot(axis) * axis).normalized();
    };
    const Vec3 normal = direction(f1) - direction(f2);
    if (!(normal.squaredNorm() > 1e-12)) return std::nullopt;
    return Separator{origin, normal};
  }

  /// max over the piece's corners of d(·, t), stopping at `cap`.
  double pieceBound(const Piece& piece, int t, double cap) const {
    double worst = 0.0;
    for (int i = 0; i < piece.size && worst < cap; ++i)
      worst = std::max(worst, piece.samples[i] >= 0 && face_[piece.samples[i]] == t
                                  ? distance_[piece.samples[i]]
                                  : to_.distanceToFace(piece.points[i], t));
    return worst;
  }

  /// min over the candidates T of pieceBound(piece, T), at most `cap`.
  double lowestPieceBound(const Piece& piece, const Candidates& candidates, double cap) const {
    double best = cap;
    for (int k = 0; k < candidates.count; ++k)
      best = std::min(best, pieceBound(piece, candidates.faces[k], best));
    return best;
  }

  /// Cuts the piece by the separator of the first two candidates that have one; the positive
  /// side keeps all but the second, the negative side all but the first, recursively. A piece
  /// left with one candidate, or with none that separate, is bounded by `pieceBound`.
  double splitBound(const Piece& piece, const Candidates& candidates, double cap) const {
    if (piece.size == 0) return 0.0;
    for (int k = 0; k < candidates.count; ++k)
      for (int l = k + 1; l < candidates.count; ++l) {
        const auto plane = separator(candidates.faces[k], candidates.faces[l]);
        if (!plane) continue;
        std::array<double, 6> side{};
        for (int i = 0; i < piece.size; ++i)
          side[i] = plane->normal.dot(piece.points[i] - plane->origin);
        // The edge from corner i to the next crosses the plane strictly.
        const auto crosses = [&](int i) {
          const double next = side[(i + 1) % piece.size];
          return (side[i] < 0.0 && next > 0.0) || (side[i] > 0.0 && next < 0.0);
        };
        int crossings = 0, above = 0, below = 0;
        for (int i = 0; i < piece.size; ++i) {
          crossings += crosses(i) ? 1 : 0;
          above += side[i] >= 0.0 ? 1 : 0;
          below += side[i] <= 0.0 ? 1 : 0;
        }
        // A convex piece crosses a plane at most twice; signs that alternate more (a piece
        // within rounding of the plane) would overflow the pieces: bounded without this cut.
        if (std::max(above, below) + crossings > static_cast<int>(side.size())) continue;
        Piece positive, negative;
        for (int i = 0; i < piece.size; ++i) {
          if (side[i] >= 0.0) positive.add(piece.points[i], piece.samples[i]);
          if (side[i] <= 0.0) negative.add(piece.points[i], piece.samples[i]);
          const int j = (i + 1) % piece.size;
          if (crosses(i)) {
            const Vec3 crossing = piece.points[i] + side[i] / (side[i] - side[j]) *
                                                        (piece.points[j] - piece.points[i]);
            positive.add(crossing, -1);
            negative.add(crossing, -1);
          }
        }
        const double worst = splitBound(positive, candidates.without(l), cap);
        if (worst >= cap) return cap;
        return std::max(worst, splitBound(negative, candidates.without(k), cap));
      }
    return lowestPieceBound(piece, candidates, cap);
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
