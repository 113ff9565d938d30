#include "core/extract/surface_fit.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "core/common/concurrency.h"
#include "core/extract/fan_geometry.h"
#include "core/geometry/closest_point.h"
#include "core/geometry/sharp_edges.h"

namespace hexcover::extract_detail {
namespace {

using Vec3 = Eigen::Vector3d;
using SVH = OpenMesh::SmartVertexHandle;

/// Snapped corners move at most this many local edge lengths.
constexpr double kSnapReach = 0.7;
/// Angles that a snapped corner's triangles must keep (degrees).
constexpr double kSnapMinAngle = 25.0;
constexpr double kSnapMaxAngle = 115.0;
/// Crease samples lie at most kCreaseSampleSpacing mean edge lengths apart inside the input's
/// crease edges; one that the remesh cuts off pulls a corner within kCreaseSnapReach local edge
/// lengths of its edge onto the edge's closest point.
constexpr double kCreaseSampleSpacing = 0.5;
constexpr double kCreaseSnapReach = 0.2;
/// Fractions of the way to the feature point that a snap tries, in order.
constexpr std::array<double, 3> kSnapFractions{1.0, 0.7, 0.45};
/// A triangle with an angle outside [kPoorMinAngle, kPoorMaxAngle] is poor: its corners are
/// smoothed.
constexpr double kPoorMinAngle = 25.0;
constexpr double kPoorMaxAngle = 110.0;
/// Smoothing may raise a fan's local deviation up to this many local edge lengths (flat regions:
/// the projection onto the input moves the fan by far less).
constexpr double kSmoothingDeviation = 0.1;
/// Relaxation moves only vertices whose triangles' angles deviate from 60° by more than this RMS
/// (degrees), in up to kRelaxPasses passes of one descent step each: kRelaxFirstStep local edge
/// lengths, halved up to kRelaxSteps − 1 times; the gradient by forward differences of
/// kGradientStep local edge lengths; at least kRelaxChunk vertices per thread.
constexpr double kRelaxMinRms = 2.0;
constexpr int kRelaxPasses = 3;
constexpr double kRelaxFirstStep = 0.1;
constexpr int kRelaxSteps = 8;
constexpr double kGradientStep = 1e-4;
constexpr std::size_t kRelaxChunk = 64;
/// A relaxed fan may deviate from the input by up to this many local edge lengths (and no more
/// than the largest fan deviation before relaxation), from the input's crease vertices by up to
/// kRelaxCreaseDeviation (or, either way, by no more than it did).
constexpr double kRelaxDeviation = 0.2;
constexpr double kRelaxCreaseDeviation = 0.1;
/// Smoothing's trial moves besides the centroid: directions, and steps in local edge lengths.
constexpr int kTrialDirections = 8;
constexpr std::array<double, 3> kTrialSteps{0.1, 0.2, 0.35};
/// Balancing moves vertices whose fan deviates from the input by more than kBalanceMinDeviation
/// local edge lengths along their fan's normal, by at most kBalanceReach local edge lengths, in
/// kBalancePasses passes; golden-section search in kBalanceSearchSteps steps, the fan sampled on
/// a barycentric grid of kBalanceDivisions divisions.
constexpr double kBalanceMinDeviation = 0.05;
constexpr double kBalanceShareOfLargest = 0.5;
constexpr double kBalanceReach = 0.5;
constexpr int kBalancePasses = 4;
constexpr int kBalanceSearchSteps = 8;
constexpr int kBalanceDivisions = 3;
/// The goal window of the angles (degrees): last in the fit, the corners of triangles with an
/// angle outside it move to the best of smoothing's trial positions, in up to kOutlierPasses
/// passes, when no deviation rises (the fan's sampled on kOutlierDivisions divisions).
constexpr double kGoalMinAngle = 30.0;
constexpr double kGoalMaxAngle = 100.0;
constexpr int kOutlierPasses = 4;
constexpr int kOutlierDivisions = 6;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

bool beyondGoalWindow(const std::array<double, 2>& range) {
  return range[0] < kGoalMinAngle || range[1] > kGoalMaxAngle;
}

/// How far (degrees) the smallest and the largest angle of a range reach beyond the goal window.
std::array<double, 2> goalExcess(const std::array<double, 2>& range) {
  return {std::max(kGoalMinAngle - range[0], 0.0), std::max(range[1] - kGoalMaxAngle, 0.0)};
}

class SurfaceFit {
 public:
  SurfaceFit(const TriMesh& input, const ClosestPointQuery& inputQuery, TriMesh& remesh,
             double creaseAngle, int threads, const std::vector<int>& squarePartner,
             const std::vector<char>& copied)
      : remesh_(remesh),
        partner_(squarePartner),
        threads_(threads),
        inputQuery_(inputQuery),
        fixed_(remesh.n_vertices(), 0),
        moved_(remesh.n_vertices(), 0) {
    for (const auto v : remesh_.vertices())
      fixed_[v.idx()] =
          remesh_.is_boundary(v) || remesh_.is_isolated(v) || (!copied.empty() && copied[v.idx()]);
    locked_ = fixed_;
    double lengthSum = 0.0;
    for (const auto e : remesh_.edges()) lengthSum += remesh_.calc_edge_length(e);
    meanEdgeLength_ =
        remesh_.n_edges() > 0 ? lengthSum / static_cast<double>(remesh_.n_edges()) : 0.0;
    std::vector<char> onCrease(input.n_vertices(), 0);
    std::vector<double> dihedral;
    if (creaseAngle > 0.0) {
      dihedral = dihedralAngles(input);
      for (const auto e : input.edges())
        if (dihedral[e.idx()] >= creaseAngle) onCrease[e.v0().idx()] = onCrease[e.v1().idx()] = 1;
    }
    for (const auto v : input.vertices())
      if (!input.is_isolated(v)) {
        inputPoints_.push_back(toEigen(input.point(v)));
        creasePoint_.push_back(onCrease[v.idx()]);
      }
    inputVertexCount_ = inputPoints_.size();
    // Crease samples: evenly spaced inside every crease edge, at most kCreaseSampleSpacing mean
    // edge lengths apart.
    const double spacing = kCreaseSampleSpacing * meanEdgeLength_;
    if (spacing > 0.0 && !dihedral.empty())
      for (const auto e : input.edges()) {
        if (dihedral[e.idx()] < creaseAngle) continue;
        const Vec3 a = toEigen(input.point(e.v0())), b = toEigen(input.point(e.v1()));
        const int samples = static_cast<int>((b - a).norm() / spacing);
        for (int i = 1; i <= samples; ++i) {
          inputPoints_.push_back(a + (b - a) * (static_cast<double>(i) / (samples + 1)));
          creasePoint_.push_back(0);
          creaseSegment_.emplace_back(a, b);
        }
      }
    featurePointCount_ = inputPoints_.size();
    for (const auto f : input.faces()) {
      Vec3 centroid = Vec3::Zero();
      for (const auto v : f.vertices()) centroid += toEigen(input.point(v)) / 3.0;
      inputPoints_.push_back(centroid);
    }
  }

  /// Assigns the input points to their closest remesh triangles, then one round of feature
  /// snapping (see surface_fit.h; none when snapDistance ≤ 0); returns the number of moves.
  long long snapFeatures(double snapDistance) {
    assignInputPoints();
    if (snapDistance <= 0.0) return 0;
    struct Candidate {
      double distance;
      int point;
    };
    std::vector<Candidate> candidates;
    for (std::size_t i = 0; i < featurePointCount_; ++i)
      if (nearest_[i].distance >
          snapDistance * std::min(faceEdgeLength(nearest_[i].face), meanEdgeLength_))
        candidates.push_back({nearest_[i].distance, static_cast<int>(i)});
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
      return a.distance > b.distance || (a.distance == b.distance && a.point < b.point);
    });
    // A move changes the fan of the vertex and its neighbours' triangles: points whose closest
    // triangle touches a moved vertex wait for the next round's distances.
    std::vector<char> touched(remesh_.n_vertices(), 0);
    long long moves = 0;
    for (const auto& candidate : candidates) {
      const auto face = remesh_.face_handle(nearest_[candidate.point].face);
      // An input vertex is the target of every corner; a crease sample stands for its crease
      // edge, whose closest point to the corner is the target.
      const bool crease = static_cast<std::size_t>(candidate.point) >= inputVertexCount_;
      const auto targetOf = [&](SVH v) -> Vec3 {
        if (!crease) return inputPoints_[candidate.point];
        const auto& [a, b] = creaseSegment_[candidate.point - inputVertexCount_];
        const double t = std::clamp((position(v) - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        return a + t * (b - a);
      };
      struct Corner {
        double distance;
        SVH v;
        Vec3 target;
      };
      std::vector<Corner> corners;
      bool stale = false;
      for (const auto v : OpenMesh::make_smart(face, remesh_).vertices()) {
        stale = stale || touched[v.idx()];
        const Vec3 target = targetOf(v);
        corners.push_back({(position(v) - target).norm(), v, target});
      }
      if (stale) continue;
      std::sort(corners.begin(), corners.end(), [](const Corner& a, const Corner& b) {
        return a.distance < b.distance || (a.distance == b.distance && a.v.idx() < b.v.idx());
      });
      const double reach = (crease ? kCreaseSnapReach : kSnapReach) * faceEdgeLength(face.idx());
      for (const auto& [distance, v, target] : corners) {
        if (locked_[v.idx()] || distance > reach) continue;
        // Onto the point, or failing that part of the way (projected onto the input) while the
        // fan keeps its angles and comes closer to the input.
        const double deviation = fanDeviation(v, position(v));
        const auto acceptable = [&](const Vec3& p) {
          if (!partner_.empty())
            return cornerBadness(v, p) <= 1.0 && fanDeviation(v, p) < deviation;
          const auto range = fanAngleRange(remesh_, v, p);
          return range[0] >= kSnapMinAngle && range[1] <= kSnapMaxAngle &&
                 fanDeviation(v, p) < deviation;
        };
        std::optional<Vec3> moveTo;
        const int hint = assignedInputFace(v);
        for (const double fraction : kSnapFractions) {
          const Vec3 partWay = position(v) + fraction * (target - position(v));
          const Vec3 p = fraction == 1.0 ? target : inputQuery_.closest(partWay, hint).point;
          if (acceptable(p)) {
            moveTo = p;
            break;
          }
        }
        if (!moveTo) continue;
        remesh_.set_point(v, toOpenMesh(*moveTo));
        moved_[v.idx()] = 1;
        locked_[v.idx()] = *moveTo == target;  // a part-way move may go on in the next round
        touched[v.idx()] = 1;
        for (const auto w : v.vertices()) touched[w.idx()] = 1;
        ++moves;
        break;
      }
    }
    return moves;
  }

  /// One pass of smoothing of poor triangles (see surface_fit.h), after snapFeatures (whose
  /// assignment of input points it uses); returns the number of moves.
  long long smoothPoorTriangles() {
    std::vector<char> poorCorner(remesh_.n_vertices(), 0);
    for (const auto f : remesh_.faces()) {
      const auto range =
          angleRange(facePositions(remesh_, f, OpenMesh::VertexHandle(), Vec3::Zero()));
      if (range[0] < kPoorMinAngle || range[1] > kPoorMaxAngle)
        for (const auto v : f.vertices()) poorCorner[v.idx()] = !locked_[v.idx()];
    }
    long long moves = 0;
    for (const auto v : remesh_.vertices()) {
      if (!poorCorner[v.idx()]) continue;
      const Vec3 current = position(v);
      const double allowed =
          std::max(fanDeviation(v, current), kSmoothingDeviation * vertexEdgeLength(v));
      double best = fanAngleBadness(remesh_, v, current);
      Vec3 bestPosition = current;
      const int hint = assignedInputFace(v);
      for (const Vec3& trial : trialPositions(v)) {
        const Vec3 candidate = inputQuery_.closest(trial, hint).point;
        const double badness = fanAngleBadness(remesh_, v, candidate);
        if (badness < best && fanDeviation(v, candidate) <= allowed) {
          best = badness;
          bestPosition = candidate;
        }
      }
      if (bestPosition != current) {
        remesh_.set_point(v, toOpenMesh(bestPosition));
        moved_[v.idx()] = 1;
        ++moves;
      }
    }
    return moves;
  }

  /// Relaxation (see surface_fit.h); returns the number of moves.
  long long relax() {
    assignInputPoints();
    const std::vector<double> deviation = movableFanDeviations();
    const double largest = *std::max_element(deviation.begin(), deviation.end());
    // Vertices of one class share no triangle, so their steps are independent: each class moves
    // in parallel, and the result does not depend on the thread count.
    const std::vector<std::vector<int>> classes = independentClasses();
    std::vector<char> active(remesh_.n_vertices(), 1);
    long long moves = 0;
    for (int pass = 0; pass < kRelaxPasses; ++pass) {
      if (pass > 0) assignInputPoints();
      std::vector<char> movedNow(remesh_.n_vertices(), 0);
      for (const auto& members : classes)
        parallelFor(
            members.size(), threads_,
            [&](std::size_t k) {
              const SVH v(members[k], &remesh_);
              if (!active[v.idx()]) return;
              if (const auto p = descentStep(v, largest)) {
                remesh_.set_point(v, toOpenMesh(*p));
                movedNow[v.idx()] = 1;
              }
            },
            kRelaxChunk);
      // The next pass visits the moved vertices and their neighbours: their fans changed.
      std::fill(active.begin(), active.end(), 0);
      long long passMoves = 0;
      for (const auto v : remesh_.vertices()) {
        if (!movedNow[v.idx()]) continue;
        moved_[v.idx()] = 1;
        active[v.idx()] = 1;
        for (const auto w : v.vertices()) active[w.idx()] = 1;
        ++passMoves;
      }
      moves += passMoves;
      if (passMoves == 0) break;
    }
    return moves;
  }

  /// The outlier-angle moves (see surface_fit.h), last; returns the number of moves.
  long long openOutlierAngles() {
    long long moves = 0;
    for (int pass = 0; pass < kOutlierPasses; ++pass) {
      assignInputPoints();
      std::vector<char> outlierCorner(remesh_.n_vertices(), 0);
      for (const auto f : remesh_.faces())
        if (beyondGoalWindow(
                angleRange(facePositions(remesh_, f, OpenMesh::VertexHandle(), Vec3::Zero()))))
          for (const auto v : f.vertices()) outlierCorner[v.idx()] = movable(v);
      // A move changes its neighbours' fans, and the input points assigned to them: those wait
      // for the next pass's assignment.
      std::vector<char> touched(remesh_.n_vertices(), 0);
      long long passMoves = 0;
      for (const auto v : remesh_.vertices()) {
        if (!outlierCorner[v.idx()] || touched[v.idx()]) continue;
        const Vec3 current = position(v);
        // A move must not take either end of the fan's angle range farther beyond the goal
        // window and must bring one end closer; the best has the least excess, then the least
        // Σ (α − 60°)².
        const auto excess = [&](const Vec3& p) { return goalExcess(fanAngleRange(remesh_, v, p)); };
        const std::array<double, 2> before = excess(current);
        std::optional<std::pair<double, double>> best;  // (excess, Σ (α − 60°)²) of bestPosition
        Vec3 bestPosition = current;
        DeviationBounds bounds(*this, v, fanDeviation(v, current, kOutlierDivisions),
                               creaseDeviation(v, current, kInfinity), kOutlierDivisions);
        // Nor may the input points whose closest remesh triangle is in the fan (a ridge's
        // vertices, say) end up farther from it: the fan's deviation is a maximum over all of it.
        const double pointsBefore =
            assignedPointDeviation(v, fanTriangles(v, current), false, kInfinity);
        const auto keepsPoints = [&](const Vec3& p) {
          return assignedPointDeviation(v, fanTriangles(v, p), false, pointsBefore) <= pointsBefore;
        };
        const int hint = assignedInputFace(v);
        for (const Vec3& trial : trialPositions(v)) {
          const Vec3 candidate = inputQuery_.closest(trial, hint).point;
          const std::array<double, 2> after = excess(candidate);
          if (after[0] > before[0] || after[1] > before[1] ||
              !(after[0] + after[1] < before[0] + before[1]))
            continue;
          const std::pair score{after[0] + after[1], fanAngleVariance(v, candidate)};
          if ((best && !(score < *best)) || !keepsPoints(candidate) || !bounds.admit(candidate))
            continue;
          best = score;
          bestPosition = candidate;
        }
        if (!best) continue;
        remesh_.set_point(v, toOpenMesh(bestPosition));
        moved_[v.idx()] = 1;
        for (const auto w : v.vertices()) touched[w.idx()] = 1;
        ++passMoves;
      }
      moves += passMoves;
      if (passMoves == 0) break;
    }
    return moves;
  }

  /// Balancing (see surface_fit.h); returns the number of moves.
  long long balance() {
    // Only fans that deviate by at least kBalanceShareOfLargest of the largest fan deviation
    // (and kBalanceMinDeviation local edge lengths) are balanced: the two-sided distance is a
    // maximum, and a line search costs a few hundred closest-point queries.
    assignInputPoints();
    std::vector<double> deviation = movableFanDeviations();
    const double largest = *std::max_element(deviation.begin(), deviation.end());
    const double threshold = kBalanceShareOfLargest * largest;
    // The angles may stray to the snap window (quads: corners within kQuadCornerWindow of 90°,
    // badness 1), or no farther than they are.
    const double windowBadness =
        partner_.empty() ? angleBadness({kSnapMinAngle, kSnapMaxAngle}) : 1.0;
    long long moves = 0;
    std::vector<char> visit(remesh_.n_vertices(), 1);
    for (int pass = 0; pass < kBalancePasses; ++pass) {
      if (pass > 0) assignInputPoints();
      std::vector<char> nextVisit(remesh_.n_vertices(), 0);
      for (const auto v : remesh_.vertices()) {
        if (!visit[v.idx()] || !movable(v)) continue;
        const Vec3 current = position(v);
        const double length = vertexEdgeLength(v);
        // Later passes visit the neighbours of moves, whose deviation changed.
        if (pass > 0) deviation[v.idx()] = fanDeviation(v, current);
        if (deviation[v.idx()] < std::max(threshold, kBalanceMinDeviation * length)) continue;
        const double before = fanDeviation(v, current, kBalanceDivisions);
        const Vec3 normal = fanNormal(v);
        if (normal.isZero()) continue;
        const auto [t, after] = searchLine(v, current, normal, kBalanceReach * length);
        const Vec3 candidate = current + t * normal;
        if (!(after < before) ||
            cornerBadness(v, candidate) > std::max(cornerBadness(v, current), windowBadness))
          continue;
        remesh_.set_point(v, toOpenMesh(candidate));
        moved_[v.idx()] = 1;
        for (const auto w : v.vertices()) nextVisit[w.idx()] = 1;
        ++moves;
      }
      visit.swap(nextVisit);
    }
    return moves;
  }

 private:
  TriMesh& remesh_;
  /// N = 4: per remesh face the other triangle of its lattice square, or −1 (squarePartners);
  /// empty for the triangle lattice.
  const std::vector<int>& partner_;
  int threads_;  ///< for relaxation and the assignment of input points (same result for any count)
  const ClosestPointQuery& inputQuery_;
  std::vector<char> fixed_;   ///< per remesh vertex: boundary, isolated or copied (never moves)
  std::vector<char> locked_;  ///< per remesh vertex: fixed or snapped all the way (snap, smoothing)
  std::vector<char> moved_;   ///< per remesh vertex: moved since the last assignInputPoints
  /// The snaps' targets (the first featurePointCount_): the input's vertices (the first
  /// inputVertexCount_), then the crease samples; then the input's face centroids.
  std::vector<Vec3> inputPoints_;
  std::size_t inputVertexCount_ = 0;
  std::size_t featurePointCount_ = 0;
  /// Per feature point: an input vertex on a crease (an edge whose dihedral angle is at least
  /// the crease angle), which relaxation keeps close; crease samples are not.
  std::vector<char> creasePoint_;
  /// Per crease sample: its crease edge (the snap's target is the edge's closest point).
  std::vector<std::pair<Vec3, Vec3>> creaseSegment_;
  double meanEdgeLength_ = 0.0;  ///< of the remesh as extracted
  /// Per input point: its closest remesh triangle (refreshed by assignInputPoints).
  std::vector<ClosestPointQuery::Result> nearest_;
  /// Per remesh face: the input points whose closest remesh triangle it is.
  std::vector<std::vector<int>> facePoints_;

  Vec3 position(OpenMesh::VertexHandle v) const { return toEigen(remesh_.point(v)); }

  /// Unit mean of the normals of v's triangles, or zero when they cancel.
  Vec3 fanNormal(SVH v) const {
    Vec3 normal = Vec3::Zero();
    for (const auto f : v.faces())
      normal += triangleNormal(facePositions(remesh_, f, OpenMesh::VertexHandle(), Vec3::Zero()));
    return normal.norm() > 0.0 ? Vec3(normal.normalized()) : Vec3::Zero();
  }

  /// Golden-section search of the offset t in [−reach, reach] that minimizes the deviation of v's
  /// fan with v at from + t·direction; returns t and that deviation.
  std::pair<double, double> searchLine(SVH v, const Vec3& from, const Vec3& direction,
                                       double reach) const {
    // A new point's deviation is only compared with the kept point's, so its measure may stop
    // once it exceeds that: the point then loses and its value is never read again.
    const auto at = [&](double t, double stopAbove) {
      return fanDeviation(v, from + t * direction, kBalanceDivisions, stopAbove);
    };
    const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
    double lo = -reach, hi = reach;
    double x1 = hi - ratio * (hi - lo), x2 = lo + ratio * (hi - lo);
    double f1 = at(x1, kInfinity), f2 = at(x2, f1);
    for (int step = 0; step < kBalanceSearchSteps; ++step) {
      if (f1 < f2) {
        hi = x2, x2 = x1, f2 = f1;
        x1 = hi - ratio * (hi - lo), f1 = at(x1, f2);
      } else {
        lo = x1, x1 = x2, f1 = f2;
        x2 = lo + ratio * (hi - lo), f2 = at(x2, f1);
      }
    }
    return f1 < f2 ? std::pair{x1, f1} : std::pair{x2, f2};
  }

  /// Sum over v's triangles of the squared deviations of their angles from 60° with v at p.
  double fanAngleVariance(SVH v, const Vec3& p) const {
    double sum = 0.0;
    for (const auto f : v.faces()) sum += squaredAngleDeviation(facePositions(remesh_, f, v, p));
    return sum;
  }

  /// Per remesh vertex: the local deviation of its fan, 0 for fixed vertices.
  std::vector<double> movableFanDeviations() const {
    std::vector<double> deviation(remesh_.n_vertices(), 0.0);
    parallelFor(remesh_.n_vertices(), threads_, [&](std::size_t i) {
      const SVH v(static_cast<int>(i), &remesh_);
      if (movable(v)) deviation[i] = fanDeviation(v, position(v));
    });
    return deviation;
  }

  /// Not fixed (on the boundary, isolated or copied): relaxation and balancing move such
  /// vertices, snapped ones too (relaxation's deviation bounds keep them near their features).
  bool movable(SVH v) const { return !fixed_[v.idx()]; }

  /// The movable vertices in classes of which no two share a triangle, or for N = 4 a quad
  /// (greedy colouring in index order).
  std::vector<std::vector<int>> independentClasses() const {
    std::vector<int> colour(remesh_.n_vertices(), -1);
    std::vector<std::vector<int>> classes;
    std::vector<char> taken;
    for (const auto v : remesh_.vertices()) {
      if (!movable(v)) continue;
      taken.assign(classes.size(), 0);
      for (const auto w : v.vertices())
        if (colour[w.idx()] >= 0) taken[colour[w.idx()]] = 1;
      // N = 4: relaxation reads the whole quad at v, whose far corner is no neighbour of v.
      if (!partner_.empty())
        for (const auto f : v.faces())
          if (const int g = partner_[f.idx()]; g >= 0)
            for (const auto w : remesh_.fv_range(remesh_.face_handle(g)))
              if (colour[w.idx()] >= 0) taken[colour[w.idx()]] = 1;
      const auto c =
          static_cast<std::size_t>(std::find(taken.begin(), taken.end(), 0) - taken.begin());
      if (c == classes.size()) classes.emplace_back();
      colour[v.idx()] = static_cast<int>(c);
      classes[c].push_back(v.idx());
    }
    return classes;
  }

  /// Calls visit(corners) for each polygon at v with v at p, corners counter-clockwise: the quad
  /// of a lattice square (N = 4: a face and its partner_) or a triangle.
  template <typename Visit>
  void forEachPolygon(SVH v, const Vec3& p, const Visit& visit) const {
    const auto at = [&](OpenMesh::VertexHandle w) { return w == v ? p : position(w); };
    std::vector<int> squares;  // the squares visited, by their first face
    for (const auto f : v.faces()) {
      const int g = partner_.empty() ? -1 : partner_[f.idx()];
      if (g < 0) {
        visit(facePositions(remesh_, f, v, p));
        continue;
      }
      const int square = std::min(f.idx(), g);
      if (std::find(squares.begin(), squares.end(), square) != squares.end()) continue;
      squares.push_back(square);
      // f's edge shared with g, x -> y, gets g's third corner between its ends.
      for (const auto h : f.halfedges())
        if (h.opp().face().idx() == g)
          visit(std::array<Vec3, 4>{at(h.from()), at(h.opp().next().to()), at(h.to()),
                                    at(h.next().to())});
    }
  }

  /// Relaxation's objective at v with v at p: Σ (α − 60°)² over its triangles' angles, or with
  /// lattice squares (N = 4) Σ (α − 90°)² over their quads' corners (60° in a triangle).
  double cornerVariance(SVH v, const Vec3& p) const {
    if (partner_.empty()) return fanAngleVariance(v, p);
    double sum = 0.0;
    forEachPolygon(v, p, [&](const auto& corners) {
      for (std::size_t k = 0; k < corners.size(); ++k) {
        const double d = cornerDeviation(corners, k);
        sum += d * d;
      }
    });
    return sum;
  }

  /// angleBadness of v's triangles with v at p; with lattice squares (N = 4) the largest deviation
  /// of a polygon corner from its ideal relative to kQuadCornerWindow (1.5 when a triangle turns by
  /// more than 60°, as for triangles).
  double cornerBadness(SVH v, const Vec3& p) const {
    if (partner_.empty()) return fanAngleBadness(remesh_, v, p);
    if (fanAngleRange(remesh_, v, p) == std::array<double, 2>{0.0, 180.0}) return 1.5;
    double worst = 0.0;
    forEachPolygon(
        v, p, [&](const auto& corners) { worst = std::max(worst, worstCornerDeviation(corners)); });
    return worst / kQuadCornerWindow;
  }

  /// One relaxation step of v (see surface_fit.h): down the gradient, in v's tangent plane, of
  /// the sum of squared deviations of its triangles' angles from 60° (forward differences),
  /// kRelaxFirstStep local edge lengths halved until the sum drops, projected onto the input.
  /// Nothing when v's angles are within kRelaxMinRms of 60° already, when the step would raise
  /// their badness, or when it would take the fan beyond its deviation bounds (`largest`: the
  /// largest fan deviation before relaxation).
  std::optional<Vec3> descentStep(SVH v, double largest) const {
    const Vec3 current = position(v);
    const double variance = cornerVariance(v, current);
    if (variance < kRelaxMinRms * kRelaxMinRms * 3.0 * v.valence()) return std::nullopt;
    const Vec3 normal = fanNormal(v);
    if (normal.isZero()) return std::nullopt;
    const Vec3 u = normal.unitOrthogonal(), w = normal.cross(u);
    const double length = vertexEdgeLength(v);
    const double h = kGradientStep * length;
    const Vec3 gradient = (cornerVariance(v, current + h * u) - variance) / h * u +
                          (cornerVariance(v, current + h * w) - variance) / h * w;
    if (!(gradient.norm() > 0.0)) return std::nullopt;
    const Vec3 direction = -gradient.normalized();
    const double badness = cornerBadness(v, current);
    DeviationBounds bounds(*this, v, std::min(largest, kRelaxDeviation * length),
                           kRelaxCreaseDeviation * length, 1);
    double step = kRelaxFirstStep * length;
    const int hint = assignedInputFace(v);
    for (int k = 0; k < kRelaxSteps; ++k, step *= 0.5) {
      const Vec3 candidate = inputQuery_.closest(current + step * direction, hint).point;
      if (!(cornerVariance(v, candidate) < variance)) continue;
      if (cornerBadness(v, candidate) > badness) return std::nullopt;
      if (bounds.admit(candidate)) return candidate;
    }
    return std::nullopt;
  }

  /// Deviation bounds of a move of v: its fan's local deviation (sampled with `divisions`, see
  /// fanDeviation) within `limit`, the input's crease vertices within `creaseLimit` of the fan;
  /// or, either way, no larger than with v where it is (measured once, when needed).
  class DeviationBounds {
   public:
    DeviationBounds(const SurfaceFit& fit, SVH v, double limit, double creaseLimit, int divisions)
        : fit_(fit),
          v_(v),
          current_(fit.position(v)),
          limit_(limit),
          creaseLimit_(creaseLimit),
          divisions_(divisions) {}

    bool admit(const Vec3& p) {
      const auto deviationAt = [&](const Vec3& q, double stop) {
        return fit_.fanDeviation(v_, q, divisions_, stop);
      };
      const auto creaseDeviationAt = [&](const Vec3& q, double stop) {
        return fit_.creaseDeviation(v_, q, stop);
      };
      return noWorse(deviationAt, p, limit_, deviationBefore_) &&
             noWorse(creaseDeviationAt, p, creaseLimit_, creaseDeviationBefore_);
    }

   private:
    /// measure(p, stopAbove) no larger than `limit`, or than with v where it is.
    template <typename Measure>
    bool noWorse(const Measure& measure, const Vec3& p, double limit,
                 std::optional<double>& before) const {
      if (measure(p, limit) <= limit) return true;
      if (!before) before = measure(current_, kInfinity);
      return *before > limit && measure(p, *before) <= *before;
    }

    const SurfaceFit& fit_;
    SVH v_;
    Vec3 current_;
    double limit_, creaseLimit_;
    int divisions_;  ///< of the fan's sampling (fanDeviation)
    std::optional<double> deviationBefore_, creaseDeviationBefore_;
  };

  /// Where smoothing tries to put v (before projection onto the input): a quarter to all of the
  /// way to its neighbours' centroid, and kTrialDirections directions in its tangent plane at
  /// kTrialSteps fractions of its mean edge length.
  std::vector<Vec3> trialPositions(SVH v) const {
    const Vec3 current = position(v);
    Vec3 centroid = Vec3::Zero();
    double count = 0.0;
    for (const auto w : v.vertices()) centroid += position(w), count += 1.0;
    centroid /= count;
    std::vector<Vec3> trials;
    for (const double t : {1.0, 0.75, 0.5, 0.25})
      trials.push_back(current + t * (centroid - current));
    const Vec3 normal = fanNormal(v);
    if (normal.isZero()) return trials;
    const Vec3 u = normal.unitOrthogonal(), w = normal.cross(u);
    const double length = vertexEdgeLength(v);
    for (int k = 0; k < kTrialDirections; ++k) {
      const double angle = 2.0 * M_PI * k / kTrialDirections;
      for (const double step : kTrialSteps)
        trials.push_back(current + step * length * (std::cos(angle) * u + std::sin(angle) * w));
    }
    return trials;
  }

  /// Mean edge length of a remesh face.
  double faceEdgeLength(int face) const {
    double sum = 0.0;
    for (const auto h : OpenMesh::make_smart(remesh_.face_handle(face), remesh_).halfedges())
      sum += remesh_.calc_edge_length(h);
    return sum / 3.0;
  }

  /// Mean length of a remesh vertex's edges.
  double vertexEdgeLength(SVH v) const {
    double sum = 0.0, count = 0.0;
    for (const auto h : v.outgoing_halfedges()) sum += remesh_.calc_edge_length(h), count += 1.0;
    return count > 0.0 ? sum / count : 0.0;
  }

  /// Closest remesh triangle of every input point, from a BVH of the remesh as it is now. After
  /// the first call only the points whose triangle has a moved corner are queried again (moves
  /// elsewhere can only bring a triangle closer: the distances are upper bounds).
  void assignInputPoints() {
    const ClosestPointQuery remeshQuery(remesh_);
    const bool all = nearest_.empty();
    nearest_.resize(inputPoints_.size());
    parallelFor(inputPoints_.size(), threads_, [&](std::size_t i) {
      bool changed = all;
      if (!all)
        for (const auto v :
             OpenMesh::make_smart(remesh_.face_handle(nearest_[i].face), remesh_).vertices())
          changed = changed || moved_[v.idx()];
      // The connectivity never changes: the previous closest triangle seeds the search.
      if (changed) nearest_[i] = remeshQuery.closest(inputPoints_[i], all ? -1 : nearest_[i].face);
    });
    std::fill(moved_.begin(), moved_.end(), 0);
    facePoints_.assign(remesh_.n_faces(), {});
    for (std::size_t i = 0; i < inputPoints_.size(); ++i)
      facePoints_[nearest_[i].face].push_back(static_cast<int>(i));
  }

  /// Largest distance to v's fan (its triangles `fan`, in the order of v.faces()) of the input
  /// points whose closest remesh triangle is in it; with `creasesOnly` only of the input's crease
  /// vertices. Stops early with a value above `stopAbove` once the largest exceeds it.
  double assignedPointDeviation(SVH v, const std::vector<std::array<Vec3, 3>>& fan,
                                bool creasesOnly, double stopAbove) const {
    const auto distance = [](const Vec3& q, const std::array<Vec3, 3>& t) {
      return (closestPointOnTriangle(q, t[0], t[1], t[2]) - q).norm();
    };
    double deviation = 0.0;
    std::size_t k = 0;
    for (const auto f : v.faces()) {
      const auto& own = fan[k++];
      for (const int i : facePoints_[f.idx()]) {
        if (creasesOnly && !isCreasePoint(i)) continue;
        const Vec3& q = inputPoints_[i];
        // The distance to the point's own triangle bounds its distance to the fan: when that is
        // no more than the largest so far, the point cannot raise it.
        if (distance(q, own) <= deviation) continue;
        double d = kInfinity;
        for (const auto& t : fan) d = std::min(d, distance(q, t));
        deviation = std::max(deviation, d);
        if (deviation > stopAbove) return deviation;
      }
    }
    return deviation;
  }

  /// An input face whose centroid's closest remesh triangle is one of v's, or −1.
  int assignedInputFace(SVH v) const {
    for (const auto f : v.faces())
      for (const int i : facePoints_[f.idx()])
        if (static_cast<std::size_t>(i) >= featurePointCount_)
          return i - static_cast<int>(featurePointCount_);
    return -1;
  }

  bool isCreasePoint(int i) const {
    return static_cast<std::size_t>(i) < featurePointCount_ && creasePoint_[i];
  }

  /// Largest distance from the input's crease vertices whose closest remesh triangle is in v's
  /// fan to the fan (v at p); early stop as in assignedPointDeviation.
  double creaseDeviation(SVH v, const Vec3& p, double stopAbove) const {
    return assignedPointDeviation(v, fanTriangles(v, p), true, stopAbove);
  }

  /// v's triangles with v at p, in the order of v.faces().
  std::vector<std::array<Vec3, 3>> fanTriangles(SVH v, const Vec3& p) const {
    std::vector<std::array<Vec3, 3>> fan;
    for (const auto f : v.faces()) fan.push_back(facePositions(remesh_, f, v, p));
    return fan;
  }

  /// Local deviation between v's fan (v at p) and the input (see surface_fit.h). With
  /// `divisions` > 1 the fan's triangles are sampled on a barycentric grid of that many
  /// divisions instead of at their centroids and v's edge midpoints. Stops early with a value
  /// above `stopAbove` once the deviation exceeds it.
  double fanDeviation(SVH v, const Vec3& p, int divisions = 1, double stopAbove = kInfinity) const {
    const std::vector<std::array<Vec3, 3>> fan = fanTriangles(v, p);
    double deviation = assignedPointDeviation(v, fan, false, stopAbove);
    if (deviation > stopAbove) return deviation;
    // The moving parts of the fan: v, its triangles' centroids and the midpoints of v's edges.
    // Queries start from the input face nearest p, which makes them short; that one's from an
    // input face whose centroid is assigned to the fan (the result does not depend on it).
    const auto self = inputQuery_.closest(p, assignedInputFace(v));
    deviation = std::max(deviation, self.distance);
    // A sample no farther from the input face nearest the previous sample, or from the one
    // nearest p, than the largest distance so far cannot raise it: the exact search runs only
    // for the others.
    int near = self.face;
    const auto raiseBy = [&](const Vec3& q) {
      if (inputQuery_.distanceToFace(q, near) <= deviation) return;
      if (near != self.face && inputQuery_.distanceToFace(q, self.face) <= deviation) return;
      const auto closest = inputQuery_.closest(q, near);
      near = closest.face;
      deviation = std::max(deviation, closest.distance);
    };
    if (divisions > 1) {
      for (const auto& t : fan)
        for (int i = 0; i <= divisions; ++i)
          for (int j = 0; i + j <= divisions; ++j) {
            const int k = divisions - i - j;
            if (i == divisions || j == divisions || k == divisions) continue;
            const int weightAtV = t[0] == p ? i : t[1] == p ? j : k;
            if (weightAtV == 0) continue;  // on the edge opposite v: does not move
            raiseBy((i * t[0] + j * t[1] + k * t[2]) / divisions);
            if (deviation > stopAbove) return deviation;
          }
      return deviation;
    }
    std::vector<Vec3> samples;
    for (const auto& t : fan) samples.push_back((t[0] + t[1] + t[2]) / 3.0);
    for (const auto w : v.vertices()) samples.push_back(0.5 * (p + position(w)));
    for (const Vec3& q : samples) {
      if (deviation > stopAbove) break;
      raiseBy(q);
    }
    return deviation;
  }
};

}  // namespace

SurfaceFitCounts fitRemeshToSurface(const TriMesh& input, const ClosestPointQuery& inputQuery,
                                    TriMesh& remesh, const SurfaceFitOptions& options,
                                    const std::vector<int>& squarePartner,
                                    const std::vector<char>& copied) {
  SurfaceFitCounts counts;
  if (input.n_faces() == 0 || remesh.n_faces() == 0) return counts;
  SurfaceFit fit(input, inputQuery, remesh, options.creaseAngle, options.threads, squarePartner,
                 copied);
  // Smoothing and the outlier-angle moves judge triangles by their angles: not the halves of
  // lattice squares.
  const bool shapeTriangles = squarePartner.empty();
  for (int round = 0; round < options.rounds; ++round) {
    const long long snapped = fit.snapFeatures(options.featureSnapDistance);
    const long long smoothed = shapeTriangles ? fit.smoothPoorTriangles() : 0;
    counts.snapped += snapped;
    counts.smoothed += smoothed;
    if (snapped + smoothed == 0) break;
  }
  counts.relaxed = fit.relax();
  if (options.balanceDeviation) counts.balanced = fit.balance();
  if (options.openOutlierAngles && shapeTriangles) counts.outliers = fit.openOutlierAngles();
  return counts;
}

}  // namespace hexcover::extract_detail
