#include "core/extract/boundary.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_set>

#include "core/extract/fan_geometry.h"

namespace hexcover::extract_detail {
namespace {

/// Closest point on segment [a, b] to p: returns the parameter in [0, 1].
double closestOnSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double len2 = d.squaredNorm();
  if (len2 <= 0.0) return 0.0;
  return std::clamp((p - a).dot(d) / len2, 0.0, 1.0);
}

}  // namespace

DirectedEdges::DirectedEdges(const std::vector<Triangle>& triangles) {
  int vertices = 0;
  for (const auto& t : triangles)
    for (const int v : t) vertices = std::max(vertices, v + 1);
  first_.assign(static_cast<std::size_t>(vertices) + 1, 0);
  for (const auto& t : triangles)
    for (const int v : t) ++first_[v + 1];
  for (int v = 0; v < vertices; ++v) first_[v + 1] += first_[v];
  std::vector<int> next(first_.begin(), first_.end() - 1);
  to_.resize(3 * triangles.size());
  apex_.resize(3 * triangles.size());
  slot_.resize(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int e = next[triangles[t][k]]++;
      to_[e] = triangles[t][(k + 1) % 3];
      apex_[e] = triangles[t][(k + 2) % 3];
      slot_[3 * t + k] = e;
    }
}

std::vector<std::vector<int>> traceBoundaryLoops(const std::vector<Triangle>& triangles) {
  return traceBoundaryLoops(triangles, DirectedEdges(triangles));
}

std::vector<std::vector<int>> traceBoundaryLoops(const std::vector<Triangle>& triangles,
                                                 const DirectedEdges& edges) {
  std::vector<std::array<int, 2>> boundaryEdges;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k)
      if (edges.find(t[(k + 1) % 3], t[k]) < 0) boundaryEdges.push_back({t[k], t[(k + 1) % 3]});

  // The boundary edge that follows (u, v): rotate about v through the fan of (u, v)'s triangle.
  // A set that breaks the precondition (a directed edge in two triangles) can make the rotation
  // cycle without reaching a boundary edge: after as many steps as there are triangles, there is
  // none, and the loop ends there.
  const auto nextEdge = [&](int u, int v) -> std::optional<std::array<int, 2>> {
    int w = edges.apex(edges.find(u, v));
    for (std::size_t step = 0; step < triangles.size(); ++step) {
      const int across = edges.find(w, v);
      if (across < 0) return std::array<int, 2>{v, w};
      w = edges.apex(across);
    }
    return std::nullopt;
  };

  std::vector<char> used(edges.size(), 0);  // per directed edge (its first occurrence)
  std::vector<std::vector<int>> loops;
  for (const auto& start : boundaryEdges) {
    if (used[edges.find(start[0], start[1])]) continue;
    std::vector<int> loop;
    std::optional<std::array<int, 2>> edge = start;
    while (edge) {
      char& seen = used[edges.find((*edge)[0], (*edge)[1])];
      if (seen) break;
      seen = 1;
      loop.push_back((*edge)[0]);
      edge = nextEdge((*edge)[0], (*edge)[1]);
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

BoundaryIndex::BoundaryIndex(std::vector<std::vector<Eigen::Vector3d>> loops, double cellSize,
                             std::vector<int> loopComponent)
    : loops_(std::move(loops)), loopComponent_(std::move(loopComponent)), cell_(cellSize) {
  arcs_.reserve(loops_.size());
  for (int i = 0; i < static_cast<int>(loops_.size()); ++i) {
    const auto& loop = loops_[i];
    std::vector<double> arc(loop.size() + 1, 0.0);
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Eigen::Vector3d& a = loop[k];
      const Eigen::Vector3d& b = loop[(k + 1) % loop.size()];
      arc[k + 1] = arc[k] + (b - a).norm();
      // Register the segment in every cell its bounding box touches.
      const Eigen::Vector3d lo = a.cwiseMin(b) / cell_, hi = a.cwiseMax(b) / cell_;
      for (auto x = std::floor(lo.x()); x <= std::floor(hi.x()); ++x)
        for (auto y = std::floor(lo.y()); y <= std::floor(hi.y()); ++y)
          for (auto z = std::floor(lo.z()); z <= std::floor(hi.z()); ++z)
            grid_[cellKey(Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5) * cell_)].push_back(
                {i, static_cast<int>(k)});
    }
    arcs_.push_back(std::move(arc));
  }
}

std::uint64_t BoundaryIndex::cellKey(const Eigen::Vector3d& p) const {
  const auto c = [&](double x) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x / cell_)) & 0x1FFFFF);
  };
  return (c(p.x()) << 42) | (c(p.y()) << 21) | c(p.z());
}

BoundaryIndex::Hit BoundaryIndex::nearest(const Eigen::Vector3d& p, double radius,
                                          int onlyLoop) const {
  return nearestAdmitted(p, radius, [&](int loop) { return onlyLoop < 0 || loop == onlyLoop; });
}

BoundaryIndex::Hit BoundaryIndex::nearestInComponent(const Eigen::Vector3d& p, double radius,
                                                     int component) const {
  return nearestAdmitted(p, radius, [&](int loop) {
    return loopComponent_.empty() || loopComponent_[loop] == component;
  });
}

template <typename Admit>
BoundaryIndex::Hit BoundaryIndex::nearestAdmitted(const Eigen::Vector3d& p, double radius,
                                                  const Admit& admit) const {
  Hit best;
  const int reach = static_cast<int>(std::ceil(radius / cell_));
  for (int dx = -reach; dx <= reach; ++dx)
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dz = -reach; dz <= reach; ++dz) {
        const auto it = grid_.find(cellKey(p + cell_ * Eigen::Vector3d(dx, dy, dz)));
        if (it == grid_.end()) continue;
        for (const auto& [loop, k] : it->second) {
          if (!admit(loop)) continue;
          const auto& points = loops_[loop];
          const Eigen::Vector3d& a = points[k];
          const Eigen::Vector3d& b = points[(k + 1) % points.size()];
          const double t = closestOnSegment(p, a, b);
          const double d = (a + t * (b - a) - p).norm();
          // Ties (the same segment seen from several cells, shared end points) go to the
          // lowest (loop, segment) so the answer does not depend on the grid's order.
          if (d < best.distance || (d == best.distance && loop < best.loop)) {
            best = {loop, d, arcs_[loop][k] + t * (arcs_[loop][k + 1] - arcs_[loop][k])};
          }
        }
      }
  if (best.distance > radius) return {};
  return best;
}

BoundaryIndex::Hit BoundaryIndex::nearestOnLoop(const Eigen::Vector3d& p, int i) const {
  Hit best;
  const auto& points = loops_[i];
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector3d& a = points[k];
    const Eigen::Vector3d& b = points[(k + 1) % points.size()];
    const double t = closestOnSegment(p, a, b);
    const double d = (a + t * (b - a) - p).norm();
    if (d < best.distance) best = {i, d, arcs_[i][k] + t * (arcs_[i][k + 1] - arcs_[i][k])};
  }
  return best;
}

BoundaryIndex::Hit BoundaryIndex::farthestFromChord(int i, double from, double to) const {
  const auto& arc = arcs_[i];
  const auto& points = loops_[i];
  const double length = arc.back();
  const Eigen::Vector3d a = pointAt(i, wrappedArc(i, from)), b = pointAt(i, wrappedArc(i, to));
  Hit farthest;
  // The loop's points at unwrapped arc lengths arc[k] + offset inside (from, to), offset a
  // multiple of the length; arc[0 .. points.size()) is ascending, so each period is one range.
  // (The search starts one point early: the test below is the exact one.)
  const auto pointArcs = arc.begin() + static_cast<std::ptrdiff_t>(points.size());
  for (double offset = std::floor(from / length) * length; offset < to; offset += length) {
    auto k = std::upper_bound(arc.begin(), pointArcs, from - offset);
    for (k = k == arc.begin() ? k : k - 1; k != pointArcs && offset + *k < to; ++k) {
      if (!(offset + *k > from)) continue;
      const Eigen::Vector3d& p = points[static_cast<std::size_t>(k - arc.begin())];
      const double d = (a + closestOnSegment(p, a, b) * (b - a) - p).norm();
      if (farthest.loop < 0 || d > farthest.distance) farthest = {i, d, *k};
    }
  }
  if (farthest.loop < 0) farthest.distance = 0.0;
  return farthest;
}

Eigen::Vector3d BoundaryIndex::pointAt(int i, double s) const {
  const auto& arc = arcs_[i];
  const auto& points = loops_[i];
  const auto it = std::upper_bound(arc.begin(), arc.end(), s);
  const std::size_t k =
      std::min<std::size_t>(std::max<std::ptrdiff_t>(it - arc.begin() - 1, 0), points.size() - 1);
  const double len = arc[k + 1] - arc[k];
  const double t = len > 0.0 ? std::clamp((s - arc[k]) / len, 0.0, 1.0) : 0.0;
  return points[k] + t * (points[(k + 1) % points.size()] - points[k]);
}

std::vector<double> sharpCorners(const BoundaryIndex& index, int loop, double spacing,
                                 double sharpAngleDeg, std::vector<double>* turnDegrees) {
  const auto& points = index.loop(loop);
  const std::size_t n = points.size();
  const double total = index.loopLength(loop);
  std::vector<double> corners, turns;
  double arc = 0.0;
  const double cosSharp = std::cos(sharpAngleDeg * M_PI / 180.0);
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d in = points[k] - points[(k + n - 1) % n];
    const Eigen::Vector3d out = points[(k + 1) % n] - points[k];
    // A corner closer than half a spacing to the previous one (a jagged input boundary) is
    // not kept: samples that close would make slivers.
    if (in.norm() > 0.0 && out.norm() > 0.0 && in.normalized().dot(out.normalized()) < cosSharp &&
        (corners.empty() || arc - corners.back() >= 0.5 * spacing)) {
      corners.push_back(arc);
      turns.push_back(std::acos(std::clamp(in.normalized().dot(out.normalized()), -1.0, 1.0)) *
                      180.0 / M_PI);
    }
    arc += out.norm();
  }
  if (corners.size() > 1 && corners.front() + total - corners.back() < 0.5 * spacing) {
    corners.pop_back();
    turns.pop_back();
  }
  if (turnDegrees) *turnDegrees = std::move(turns);
  return corners;
}

std::vector<double> sampleBoundaryLoop(const BoundaryIndex& index, int loop, double spacing,
                                       double sharpAngleDeg, std::vector<bool>* corner) {
  const double total = index.loopLength(loop);
  std::vector<double> corners = sharpCorners(index, loop, spacing, sharpAngleDeg);
  if (corners.empty()) corners.push_back(0.0);
  std::vector<double> samples;
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const double from = corners[c];
    const double to = c + 1 < corners.size() ? corners[c + 1] : corners[0] + total;
    const int pieces = std::max(1, static_cast<int>(std::lround((to - from) / spacing)));
    for (int i = 0; i < pieces; ++i) samples.push_back(std::fmod(from + (to - from) * i / pieces, total));
  }
  if (samples.size() < 3) {
    samples.clear();
    for (int i = 0; i < 3; ++i) samples.push_back(corners[0] + total * i / 3.0);
    for (double& s : samples) s = std::fmod(s, total);
  }
  std::sort(samples.begin(), samples.end());
  if (corner) {
    corner->assign(samples.size(), false);
    for (std::size_t k = 0; k < samples.size(); ++k)
      (*corner)[k] = std::find(corners.begin(), corners.end(), samples[k]) != corners.end();
  }
  return samples;
}

void stitchStrip(const std::vector<Eigen::Vector3d>& positions,
                 const std::vector<Eigen::Vector3d>& normals, const std::vector<int>& outer,
                 const std::vector<double>& outerParam, const std::vector<int>& front,
                 const std::vector<double>& frontParam, double length,
                 std::vector<Triangle>& out) {
  const std::size_t m = outer.size(), n = front.size();
  std::vector<double> s(outerParam), t(frontParam);
  s.push_back(outerParam[0] + length);
  t.push_back(frontParam[0] + length);
  for (std::size_t j = 1; j <= n; ++j) t[j] = std::max(t[j], t[j - 1]);

  // Zip the two sequences: each step adds the triangle on the next outer edge or the one on the
  // next front edge. Prefer the one that faces the surface's side and has the larger smallest
  // angle; when neither faces the right way, follow the positions along the loop.
  const auto quality = [&](int a, int b, int c, const Eigen::Vector3d& normal) {
    const Eigen::Vector3d &pa = positions[a], &pb = positions[b], &pc = positions[c];
    if ((pb - pa).cross(pc - pa).dot(normal) <= 0.0) return -1.0;
    double smallest = M_PI;
    const std::array<Eigen::Vector3d, 3> p{pa, pb, pc};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
      smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)));
    }
    return smallest;
  };
  std::size_t i = 0, j = 0;
  while (i < m || j < n) {
    const int b0 = outer[i % m], b1 = outer[(i + 1) % m];
    const int l0 = front[j % n], l1 = front[(j + 1) % n];
    bool advanceOuter = j == n;
    if (i < m && j < n) {
      const double onOuter = quality(b0, b1, l0, normals[l0]);
      const double onFront = quality(l1, l0, b0, normals[l0] + normals[l1]);
      advanceOuter = onOuter < 0.0 && onFront < 0.0 ? s[i + 1] <= t[j + 1] : onOuter >= onFront;
      // Neither side may run ahead of the other by more than one vertex along the loop, or the
      // zip ends in a fan.
      if (advanceOuter && s[i + 1] > t[std::min(j + 2, n)] && onFront >= 0.0) advanceOuter = false;
      if (!advanceOuter && t[j + 1] > s[std::min(i + 2, m)] && onOuter >= 0.0) advanceOuter = true;
      // A step after which the other side's next triangle would face backwards leads into a fan
      // (where the front turns towards the loop, every later sample lies behind its edge): take
      // the other side's triangle first while it still faces the right way.
      const bool outerStrandsFront =
          onFront >= 0.0 && quality(l1, l0, b1, normals[l0] + normals[l1]) < 0.0;
      const bool frontStrandsOuter = onOuter >= 0.0 && quality(b0, b1, l1, normals[l1]) < 0.0;
      if (outerStrandsFront != frontStrandsOuter) advanceOuter = frontStrandsOuter;
    }
    if (advanceOuter) {
      out.push_back({b0, b1, l0});
      ++i;
    } else {
      out.push_back({l1, l0, b0});
      ++j;
    }
  }
}

void alignFrontToLoop(const std::vector<double>& outerArc, std::vector<int>& front,
                      std::vector<double>& frontArc, double loopLength) {
  const std::size_t n = front.size();
  const auto wrapped = [&](double d) { return d - loopLength * std::round(d / loopLength); };
  std::size_t start = 0;
  for (std::size_t j = 1; j < n; ++j)
    if (std::abs(wrapped(frontArc[j] - outerArc[0])) <
        std::abs(wrapped(frontArc[start] - outerArc[0])))
      start = j;
  std::vector<int> rotated(n);
  std::vector<double> param(n);
  param[0] = outerArc[0] + wrapped(frontArc[start] - outerArc[0]);
  for (std::size_t j = 0; j < n; ++j) {
    rotated[j] = front[(start + j) % n];
    if (j > 0)
      param[j] = param[j - 1] + wrapped(frontArc[(start + j) % n] - frontArc[(start + j - 1) % n]);
  }
  front = std::move(rotated);
  frontArc = std::move(param);
}

int fillHole(const std::vector<int>& loop, std::vector<Eigen::Vector3d>& positions,
             std::vector<Triangle>& out) {
  const std::size_t n = loop.size();
  // The loop runs with the existing triangles on its left: the hole's triangles run backwards.
  if (n == 3) {
    out.push_back({loop[2], loop[1], loop[0]});
    return 1;
  }
  if (n == 4) {
    const auto& p = positions;
    if ((p[loop[0]] - p[loop[2]]).norm() <= (p[loop[1]] - p[loop[3]]).norm()) {
      out.push_back({loop[2], loop[1], loop[0]});
      out.push_back({loop[0], loop[3], loop[2]});
    } else {
      out.push_back({loop[3], loop[1], loop[0]});
      out.push_back({loop[3], loop[2], loop[1]});
    }
    return 2;
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const int v : loop) centroid += positions[v];
  const int center = static_cast<int>(positions.size());
  positions.push_back(centroid / static_cast<double>(n));
  for (std::size_t k = 0; k < n; ++k) out.push_back({loop[(k + 1) % n], loop[k], center});
  return static_cast<int>(n);
}

namespace {

std::uint64_t undirectedKey(int a, int b) {
  const auto [lo, hi] = std::minmax(a, b);
  return (static_cast<std::uint64_t>(lo) << 32) | static_cast<std::uint32_t>(hi);
}

/// The corners of triangle t.
std::array<Eigen::Vector3d, 3> cornersOf(const std::vector<Eigen::Vector3d>& p, const Triangle& t) {
  return {p[t[0]], p[t[1]], p[t[2]]};
}

Eigen::Vector3d areaNormal(const std::vector<Eigen::Vector3d>& p, const Triangle& t) {
  return (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
}

}  // namespace

int improveByFlips(const std::vector<Eigen::Vector3d>& positions,
                   const std::vector<Triangle>& others, std::vector<Triangle>& region) {
  // Triangles per undirected edge: only an edge of exactly two triangles, both in the region,
  // is flipped (one in more, a fold the repair mends later, stays as it is).
  std::unordered_map<std::uint64_t, int> edges;
  for (const std::vector<Triangle>* set : {&others, static_cast<const std::vector<Triangle>*>(&region)})
    for (const auto& t : *set)
      for (int k = 0; k < 3; ++k) ++edges[undirectedKey(t[k], t[(k + 1) % 3])];
  int flips = 0;
  constexpr int kMaxPasses = 20;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    // Directed edge a→b → (triangle, corner of a).
    std::unordered_map<std::uint64_t, std::pair<int, int>> directed;
    for (int i = 0; i < static_cast<int>(region.size()); ++i)
      for (int k = 0; k < 3; ++k)
        directed[(static_cast<std::uint64_t>(region[i][k]) << 32) |
                 static_cast<std::uint32_t>(region[i][(k + 1) % 3])] = {i, k};
    std::vector<bool> touched(region.size(), false);
    int passFlips = 0;
    for (int i = 0; i < static_cast<int>(region.size()); ++i) {
      for (int k = 0; k < 3 && !touched[i]; ++k) {
        const int a = region[i][k], b = region[i][(k + 1) % 3], c = region[i][(k + 2) % 3];
        const auto it = directed.find((static_cast<std::uint64_t>(b) << 32) | static_cast<std::uint32_t>(a));
        if (it == directed.end() || touched[it->second.first] || it->second.first == i) continue;
        const int j = it->second.first;
        const int d = region[j][(it->second.second + 2) % 3];  // region[j] = (b, a, d)
        if (c == d || edges.at(undirectedKey(a, b)) != 2 || edges.count(undirectedKey(c, d)))
          continue;
        if (!flipRaisesSmallestAngle(positions[a], positions[b], positions[c], positions[d]))
          continue;
        edges.erase(undirectedKey(a, b));
        edges[undirectedKey(c, d)] = 2;
        region[i] = {a, d, c};
        region[j] = {d, b, c};
        touched[i] = touched[j] = true;
        ++passFlips;
      }
    }
    flips += passFlips;
    if (passFlips == 0) break;
  }
  return flips;
}

int slideBoundarySamples(const BoundaryIndex& index, std::vector<LoopSamples>& samples,
                         const std::vector<Triangle>& region,
                         std::vector<Eigen::Vector3d>& positions,
                         const std::vector<std::array<int, 4>>& squares) {
  constexpr int kCandidates = 16, kPasses = 2;
  constexpr double kClearance = 0.3;  // least distance to a neighbour, in sample spacings
  // A slide may not let the loop stray farther than this many spacings from the sample's edges
  // (or than it does before the slide).
  constexpr double kChordDeviation = 0.25;
  std::unordered_map<int, std::vector<int>> triangles;  // sample vertex -> its region triangles
  for (const auto& loop : samples)
    for (const int v : loop.vertex) triangles[v];
  std::vector<Eigen::Vector3d> normal(region.size());
  for (std::size_t i = 0; i < region.size(); ++i) {
    normal[i] = areaNormal(positions, region[i]);
    for (const int v : region[i])
      if (const auto it = triangles.find(v); it != triangles.end())
        it->second.push_back(static_cast<int>(i));
  }
  // N = 4: per region triangle the square it is half of, or −1.
  std::vector<int> squareOf(region.size(), -1);
  if (!squares.empty()) {
    std::map<Triangle, int> halves;
    for (std::size_t q = 0; q < squares.size(); ++q) {
      const auto& [c0, c1, c2, c3] = squares[q];
      halves[canonicalTriangle({c0, c1, c2})] = halves[canonicalTriangle({c0, c2, c3})] =
          static_cast<int>(q);
    }
    for (std::size_t i = 0; i < region.size(); ++i)
      if (const auto it = halves.find(canonicalTriangle(region[i])); it != halves.end())
        squareOf[i] = it->second;
  }
  // Over the vertex's polygons (its triangles, or the squares they are halves of): the largest
  // angleBadness (a square's: its worst corner's deviation from 90° over kQuadCornerWindow), and
  // (between positions with the same largest one) the sum of the squared deviations of the
  // angles from their ideal; nullopt when a triangle turns against its former normal.
  struct Badness {
    double worst = 0.0, sumOfSquares = 0.0;
    bool betterThan(const Badness& other) const {
      constexpr double kTie = 1e-9;
      return worst < other.worst - kTie ||
             (worst <= other.worst + kTie && sumOfSquares < other.sumOfSquares - kTie);
    }
  };
  const auto badness = [&](int v) -> std::optional<Badness> {
    Badness b;
    std::vector<int> judged;  // the squares at v already judged
    for (const int i : triangles.at(v)) {
      if (!(areaNormal(positions, region[i]).dot(normal[i]) > 0.0)) return std::nullopt;
      if (const int q = squareOf[i]; q >= 0) {
        if (std::find(judged.begin(), judged.end(), q) != judged.end()) continue;
        judged.push_back(q);
        std::array<Eigen::Vector3d, 4> corners;
        for (int k = 0; k < 4; ++k) corners[k] = positions[squares[q][k]];
        b.worst = std::max(b.worst, worstCornerDeviation(corners) / kQuadCornerWindow);
        for (std::size_t k = 0; k < 4; ++k)
          b.sumOfSquares += std::pow(cornerDeviation(corners, k), 2);
        continue;
      }
      const auto corners = cornersOf(positions, region[i]);
      b.worst = std::max(b.worst, angleBadness(angleRange(corners)));
      b.sumOfSquares += squaredAngleDeviation(corners);
    }
    return b;
  };
  int moves = 0;
  for (int pass = 0; pass < kPasses; ++pass)
    for (auto& loop : samples) {
      const int count = static_cast<int>(loop.vertex.size());
      const double length = index.loopLength(loop.loop);
      if (count < 3) continue;
      for (int k = 0; k < count; ++k) {
        if (loop.corner[k]) continue;
        const int v = loop.vertex[k];
        // Neighbours' arcs unwrapped around arc[k].
        double before = loop.arc[(k + count - 1) % count], after = loop.arc[(k + 1) % count];
        if (before > loop.arc[k]) before -= length;
        if (after < loop.arc[k]) after += length;
        const double lower = before + kClearance * loop.spacing;
        const double upper = after - kClearance * loop.spacing;
        if (!(lower < upper)) continue;
        const Eigen::Vector3d original = positions[v];
        const std::optional<Badness> start = badness(v);
        if (!start) continue;
        // How far the loop strays from the sample's two edges, with the sample at s.
        const auto chordDeviation = [&](double s) {
          return std::max(index.farthestFromChord(loop.loop, before, s).distance,
                          index.farthestFromChord(loop.loop, s, after).distance);
        };
        const double allowed =
            std::max(kChordDeviation * loop.spacing, chordDeviation(loop.arc[k]));
        double bestArc = loop.arc[k];
        Badness best = *start;
        for (int c = 0; c <= kCandidates; ++c) {
          const double s = lower + (upper - lower) * c / kCandidates;
          if (chordDeviation(s) > allowed) continue;
          const double wrapped = index.wrappedArc(loop.loop, s);
          positions[v] = index.pointAt(loop.loop, wrapped);
          const std::optional<Badness> b = badness(v);
          if (b && b->betterThan(best)) best = *b, bestArc = wrapped;
        }
        positions[v] = bestArc == loop.arc[k] ? original : index.pointAt(loop.loop, bestArc);
        if (bestArc != loop.arc[k]) ++moves;
        loop.arc[k] = bestArc;
      }
    }
  return moves;
}

long long flipBoundarySlivers(TriMesh& mesh, double belowDegrees, double aboveDegrees,
                              OpenMesh::FPropHandleT<bool> fixed) {
  constexpr int kPasses = 3;
  const auto point = [&](OpenMesh::VertexHandle v) { return toEigen(mesh.point(v)); };
  const auto isFixed = [&](OpenMesh::FaceHandle f) {
    return fixed.is_valid() && mesh.property(fixed, f);
  };
  long long flips = 0;
  for (int pass = 0; pass < kPasses; ++pass) {
    long long passFlips = 0;
    for (const auto e : mesh.edges()) {
      if (e.is_boundary()) continue;
      // Faces (a, b, c) and (b, a, d).
      const auto h = e.h0();
      const auto a = h.from(), b = h.to(), c = h.next().to(), d = e.h1().next().to();
      if (!(a.is_boundary() || b.is_boundary() || c.is_boundary() || d.is_boundary())) continue;
      if (isFixed(h.face()) || isFixed(e.h1().face())) continue;
      if (!(flipRaisesSmallestAngle(point(a), point(b), point(c), point(d), belowDegrees) ||
            flipLowersLargestAngle(point(a), point(b), point(c), point(d), aboveDegrees)) ||
          !mesh.is_flip_ok(e))
        continue;
      mesh.flip(e);
      ++passFlips;
    }
    flips += passFlips;
    if (passFlips == 0) break;
  }
  return flips;
}

long long collapseBoundarySlivers(TriMesh& mesh, double belowDegrees, double straightWithin,
                                  OpenMesh::FPropHandleT<bool> fixed) {
  constexpr int kPasses = 3;
  const auto point = [&](OpenMesh::VertexHandle v) { return toEigen(mesh.point(v)); };
  const auto touchesFixed = [&](OpenMesh::SmartVertexHandle v) {
    if (!fixed.is_valid()) return false;
    for (const auto f : v.faces())
      if (mesh.property(fixed, f)) return true;
    return false;
  };
  const auto smallestAngle = [&](OpenMesh::SmartFaceHandle f) {
    return angleRange(facePositions(mesh, f, OpenMesh::VertexHandle(), Eigen::Vector3d::Zero()))[0];
  };
  // A boundary vertex may move only along a boundary edge, and only where the boundary runs
  // straight through it or the boundary without it (the chord from its other boundary
  // neighbour) stays within kChordDeviation of its edges' mean length: a lip curled at a
  // fraction of an edge length, not a corner (0.3: the Stanford bunny subdivided to 1.1M faces
  // kept a 17.9° triangle at 0.25, its boundary vertex 0.27 edge lengths off the chord).
  constexpr double kChordDeviation = 0.3;
  const auto mayMoveAlong = [&](OpenMesh::SmartHalfedgeHandle h) {
    const auto v = h.from();
    double interiorAngle = 0.0, length = 0.0;
    for (const auto g : v.incoming_halfedges()) {
      length += (point(g.from()) - point(v)).norm();
      if (!g.is_boundary())
        interiorAngle += angleAt(point(v), point(g.from()), point(g.next().to()));
    }
    if (std::abs(interiorAngle - 180.0) <= straightWithin) return true;
    // A convex corner turning by more than twice that is a corner of the input: it stays.
    if (interiorAngle < 180.0 - 2.0 * straightWithin) return false;
    const auto out = v.halfedge();  // the boundary halfedge leaving v
    const auto other = out.to() == h.to() ? out.prev().from() : out.to();
    const Eigen::Vector3d a = point(other), chord = point(h.to()) - a;
    const double t = std::clamp((point(v) - a).dot(chord) / chord.squaredNorm(), 0.0, 1.0);
    return (point(v) - (a + t * chord)).norm() <= kChordDeviation * length / v.valence();
  };
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  long long collapses = 0;
  for (int pass = 0; pass < kPasses; ++pass) {
    long long passCollapses = 0;
    for (const auto f : mesh.faces()) {
      if (f.deleted() || !(smallestAngle(f) < belowDegrees)) continue;
      bool atBoundary = false;
      for (const auto v : f.vertices()) atBoundary = atBoundary || v.is_boundary();
      if (!atBoundary) continue;
      // Candidates: an edge of f collapsed either way, keeping the boundary on the boundary (an
      // interior vertex onto any neighbour, a boundary vertex only along a boundary edge).
      OpenMesh::SmartHalfedgeHandle best;
      double bestGain = 0.0;
      for (const auto edge : f.halfedges())
        for (const auto h : {edge, edge.opp()}) {
          const auto from = h.from();
          if (from.is_boundary() && !(h.edge().is_boundary() && mayMoveAlong(h))) continue;
          if (touchesFixed(from) || !mesh.is_collapse_ok(h)) continue;
          double before = 180.0;
          for (const auto g : from.faces()) before = std::min(before, smallestAngle(g));
          // from's remaining triangles once it sits on h.to() (0 when one turns too far).
          const double gain = fanAngleRange(mesh, from, point(h.to()), h.to())[0] - before;
          if (gain > bestGain) bestGain = gain, best = h;
        }
      if (!best.is_valid()) continue;
      mesh.collapse(best);
      ++passCollapses;
    }
    collapses += passCollapses;
    if (passCollapses == 0) break;
  }
  if (collapses > 0) mesh.garbage_collection();
  mesh.release_vertex_status();
  mesh.release_edge_status();
  mesh.release_face_status();
  return collapses;
}

SliverRepairs repairBoundarySlivers(TriMesh& mesh, double sliverDegrees, double obtuseDegrees,
                                    double straightWithin, OpenMesh::FPropHandleT<bool> fixed) {
  SliverRepairs done;
  done.collapses = collapseBoundarySlivers(mesh, sliverDegrees, straightWithin, fixed);
  done.flips = flipBoundarySlivers(mesh, sliverDegrees, obtuseDegrees, fixed);
  return done;
}

}  // namespace hexcover::extract_detail
