#include "core/extract/front_stitching.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <tuple>
#include <utility>

#include "core/common/median.h"
#include "core/extract/boundary.h"
#include "core/extract/fan_geometry.h"

namespace hexcover::extract_detail {
namespace {

using HH = TriMesh::HalfedgeHandle;

/// The input's boundary loops (vertex positions in face order, surface on the left) and the
/// component of each.
void inputBoundaryLoops(const TriMesh& mesh, const std::vector<int>& faceComponent,
                        std::vector<std::vector<Eigen::Vector3d>>& loops,
                        std::vector<int>& loopComponent) {
  std::vector<bool> seen(mesh.n_halfedges(), false);
  for (const auto start : mesh.halfedges()) {
    if (!mesh.is_boundary(start) || seen[start.idx()]) continue;
    // Boundary halfedges run against the faces; collect, then reverse to face order.
    std::vector<Eigen::Vector3d> loop;
    HH h = start;
    do {
      seen[h.idx()] = true;
      loop.push_back(toEigen(mesh.point(mesh.from_vertex_handle(h))));
      h = mesh.next_halfedge_handle(h);
    } while (h != start);
    std::reverse(loop.begin(), loop.end());
    loops.push_back(std::move(loop));
    loopComponent.push_back(
        faceComponent[mesh.face_handle(mesh.opposite_halfedge_handle(start)).idx()]);
  }
}

/// Samples up to this many places from a corner share its move (see stitchFrontByValence).
constexpr int kCornerSpread = 2;
/// A corner moves the nearest sample at most this many sample spacings (kOutlineCornerReach at
/// an outline's corner); a corner farther from every free sample is not resolved at this edge
/// length, unless it gets a sample of its own (kOwnSampleCornerAngle, kOwnSampleCornerCut).
constexpr double kCornerReach = 0.5;
/// A corner that turns by no more than kOwnSampleCornerAngle where the loop is straight for a
/// spacing on either side (within kStraightWithin spacings of the chord: a CAD outline's corner,
/// where a scan's zigzag is not) moves the nearest sample from up to this many spacings
/// (triangles), rather than be cut off by about 0.3 spacings.
constexpr double kOutlineCornerReach = 0.75;
constexpr double kStraightWithin = 0.05;
/// A boundary corner that turns by more than this many degrees gets a sample of its own when no
/// free sample is within reach (at the price of a valence-7 front vertex), and for triangles so
/// does a blunter one that the chord between the samples around it would cut off by more than
/// kOwnSampleCornerCut spacings.
constexpr double kOwnSampleCornerAngle = 80.0;
constexpr double kOwnSampleCornerCut = 0.5;
/// A chord between two samples of a valence stitch longer than kLongChord spacings that strays
/// farther than kValenceChordDeviation spacings from the loop is split by samples between its
/// ends, into at most kMaxChordPieces, when the fan triangles of the split keep angles of at least
/// kChordFanAngle degrees.
constexpr double kLongChord = 1.5;
constexpr double kValenceChordDeviation = 0.45;
constexpr int kMaxChordPieces = 8;
constexpr double kChordFanAngle = 20.0;

/// Stitches a front to its single input loop so that every front vertex gets valence 6 (paper
/// 5.2: irregular vertices only at singularities). A front vertex with a = latticeValence lattice
/// edges is joined
/// to d = max(1, 6 − a) consecutive boundary samples; neighbouring front vertices share one, so
/// the loop gets Σ(d − 1) samples. For squares (N = 4; a counts polygon edges, the squares'
/// diagonals left out) d = max(1, 5 − a): along a straight stretch of front (d = 2) a front step
/// {f_j+1, f_j, s} and the next outer step {s, s', f_j+1} make the square (s, s', f_j+1, f_j),
/// with s at f_j's place on the loop, so the strip is a row of rectangles and every front vertex
/// keeps valence 4; at the front's corners the triangles stay for pairTriangles. The sample shared
/// by two front vertices sits at the middle of their arc positions on the loop, the others of a
/// front vertex evenly between its shared ones. Each sharp corner of the loop takes the place of
/// the nearest free sample within kCornerReach spacings, and a long chord between two samples
/// that strays from the loop gets samples between them (kLongChord). Returns false (and adds
/// nothing) for a front that runs back along the loop, corners that would reorder the samples, or
/// fewer than 3 samples.
bool stitchFrontByValence(const BoundaryIndex& index, int loop, int component,
                          const std::vector<int>& front, const std::vector<double>& frontArc,
                          const std::vector<int>& latticeValence, double spacing,
                          const ExtractOptions& options, Assembly& out,
                          std::vector<Triangle>& added, std::vector<LoopSamples>& loopSamples,
                          ExtractionReport& report) {
  const std::size_t n = front.size();
  const double length = index.loopLength(loop);
  if (frontArc.back() - frontArc.front() > length) return false;
  // Front vertex j is joined to samples first[j] .. first[j + 1] (indices modulo the count).
  const bool squares = out.latticeOrder == 4;
  const int full = squares ? 5 : 6;  // valence 6, or valence 4 and one strip edge a diagonal
  std::vector<int> first(n + 1, 0);
  for (std::size_t j = 0; j < n; ++j)
    first[j + 1] = first[j] + std::max(1, full - latticeValence[front[j]]) - 1;
  int m = first[n];
  if (m < 3) return false;

  // Unwrapped arcs: sample m is sample 0 one loop later.
  const auto arcOf = [&](std::size_t j) { return j < n ? frontArc[j] : frontArc[j - n] + length; };
  std::vector<double> sum(m + 1, 0.0), count(m + 1, 0.0);
  // The sample shared by front vertices j and j + 1 sits between them; in a row of squares at
  // f_j's place, the end of f_j's strip edge in the square (f_j, s, s', f_j+1). A front vertex
  // on a straight stretch of the front has two samples.
  const auto straight = [&](std::size_t j) { return first[j + 1] - first[j] == 1; };
  for (std::size_t j = 0; j < n; ++j) {
    const bool row = squares && straight(j) && straight((j + 1) % n);
    sum[first[j + 1]] += row ? arcOf(j) : 0.5 * (arcOf(j) + arcOf(j + 1));
    count[first[j + 1]] += 1.0;
  }
  sum[0] += sum[m] - count[m] * length;
  count[0] += count[m];
  std::vector<double> arc(m + 1, 0.0);
  for (int k = 0; k < m; ++k)
    if (count[k] > 0.0) arc[k] = sum[k] / count[k];
  arc[m] = arc[0] + length;
  for (std::size_t j = 0; j < n; ++j)
    for (int k = first[j] + 1; k < first[j + 1]; ++k)
      arc[k] = arc[first[j]] +
               (arc[first[j + 1]] - arc[first[j]]) * (k - first[j]) / (first[j + 1] - first[j]);
  const auto wrapped = [&](double a) { return index.wrappedArc(loop, a); };
  // Sharp corners are samples: the nearest sample moves onto each corner, and the samples up to
  // kCornerSpread places away follow a decreasing part of its move, so that the strip's
  // triangles around the corner share the distortion.
  std::vector<bool> corner(m, false);
  std::vector<double> shift(m, 0.0);
  // A sample of its own (a corner's, or one splitting a chord) becomes sample `at`: arc, corner
  // and shift stay parallel, and the front vertices' first samples after it move up by one.
  const auto insertSample = [&](int at, double arcAt, bool isCorner) {
    arc.insert(arc.begin() + at, arcAt);
    corner.insert(corner.begin() + at, isCorner);
    shift.insert(shift.begin() + at, 0.0);
    for (int& f : first) f += f >= at ? 1 : 0;
    ++m;
  };
  // Corners in loop order from arc[0], each on the nearest sample after the previous corner's.
  std::vector<double> turns;
  const std::vector<double> cornerArcs =
      sharpCorners(index, loop, spacing, options.sharpBoundaryAngle, &turns);
  std::vector<std::pair<double, double>> corners;  // (unwrapped arc, degrees the loop turns)
  for (std::size_t c = 0; c < cornerArcs.size(); ++c)
    corners.emplace_back(arc[0] + wrapped(cornerArcs[c] - arc[0]), turns[c]);
  std::sort(corners.begin(), corners.end());
  // An outline's corner: one turning by at most kOwnSampleCornerAngle where the loop stays
  // within kStraightWithin spacings of its chord for a spacing on either side (triangles).
  const auto straightLoop = [&](double from, double to) {
    return index.farthestFromChord(loop, from, to).distance < kStraightWithin * spacing;
  };
  const auto outlineCorner = [&](double at, double turn) {
    return !squares && !(turn > kOwnSampleCornerAngle) && straightLoop(at - spacing, at) &&
           straightLoop(at, at + spacing);
  };
  int next = 0;
  for (const auto& [at, turn] : corners) {
    int nearest = next;
    for (int k = next + 1; k < m; ++k)
      if (std::abs(arc[k] - at) < std::abs(arc[nearest] - at)) nearest = k;
    // The nearest free sample's distance from the corner (none left: infinitely far).
    const double away =
        nearest < m ? std::abs(arc[nearest] - at) : std::numeric_limits<double>::infinity();
    if (away <= kCornerReach * spacing ||
        (away <= kOutlineCornerReach * spacing && outlineCorner(at, turn))) {
      corner[nearest] = true;
      shift[nearest] = at - arc[nearest];
      next = nearest + 1;
      continue;
    }
    // No free sample within reach: a corner sharper than kOwnSampleCornerAngle,
    // or one that the chord between the samples around it would cut off by more than
    // kOwnSampleCornerCut spacings, gets a sample of its own, in the fan of the front vertex
    // whose samples bracket it, which then has valence 7 (a square plate at h = 0.1 lost two of
    // its corners: 3.2% Hausdorff distance; camelhead turned by 0.6-2.4 rad about y lost a
    // corner of 77° at its neck, cut off by 0.55 spacings: 1.05%); a blunter, shallower one is
    // not resolved at this edge length. (For squares the cut rule gave the Stanford bunny's
    // strip at K = V/4 a corner of 155° where the largest was 134°: only the angle rule.)
    const int atIndex = static_cast<int>(
        std::upper_bound(arc.begin() + std::max(next, 1), arc.begin() + m, at) - arc.begin());
    if (!(turn > kOwnSampleCornerAngle) &&
        (squares || !(index.farthestFromChord(loop, arc[atIndex - 1], arc[atIndex]).distance >
                      kOwnSampleCornerCut * spacing)))
      continue;
    insertSample(atIndex, at, true);
    next = atIndex + 1;
  }
  std::vector<double> moved(arc.begin(), arc.begin() + m);
  for (int k = 0; k < m; ++k) {
    if (corner[k]) {
      moved[k] += shift[k];
      continue;
    }
    // The nearest corner sample on either side within kCornerSpread places.
    double move = 0.0, weight = 0.0;
    for (int d = 1; d <= kCornerSpread; ++d)
      for (const int i : {(k + d) % m, (k - d + m) % m})
        if (corner[i]) {
          const double w = 1.0 - static_cast<double>(d) / (kCornerSpread + 1);
          move += w * shift[i];
          weight += 1.0;
        }
    if (weight > 0.0) moved[k] += move / weight;
  }
  for (int k = 0; k < m; ++k) {
    const double following = k + 1 < m ? moved[k + 1] : moved[0] + length;
    if (!(moved[k] < following)) return false;  // the corners would reorder the samples
  }
  std::copy(moved.begin(), moved.end(), arc.begin());
  arc[m] = arc[0] + length;
  // Samples where the front vertices fall on the loop can be far apart: a chord longer than
  // kLongChord spacings that strays from the loop by more than kValenceChordDeviation spacings
  // gets samples between its ends, evenly, in the fan of the front vertex whose step it is
  // (which has a higher valence then), unless that vertex is too far from the loop for the fan's
  // triangles to keep kChordFanAngle. Schwarz P at K = 160 and 200: chords of 2.8-3.1 spacings
  // across its openings, Hausdorff distance 5.2% and 3.9% (2.4% with the splits).
  for (int k = 0; k < m && !squares; ++k) {
    const double from = arc[k], to = arc[k + 1];
    if (to - from < kLongChord * spacing) continue;
    const auto piece = [&](int i, int pieces) { return from + (to - from) * i / pieces; };
    const auto strays = [&](int pieces) {
      for (int i = 0; i < pieces; ++i)
        if (index.farthestFromChord(loop, piece(i, pieces), piece(i + 1, pieces)).distance >
            kValenceChordDeviation * spacing)
          return true;
      return false;
    };
    // The front vertex j whose outer steps first[j] .. first[j + 1] include step k.
    const auto owner = std::upper_bound(first.begin(), first.end(), k) - first.begin() - 1;
    const auto fanKeepsAngles = [&](int pieces) {
      for (int i = 0; i < pieces; ++i)
        if (angleRange({out.positions[front[owner]], index.pointAt(loop, wrapped(piece(i, pieces))),
                        index.pointAt(loop, wrapped(piece(i + 1, pieces)))})[0] < kChordFanAngle)
          return false;
      return true;
    };
    int pieces = 1;
    while (pieces < kMaxChordPieces && strays(pieces)) ++pieces;
    if (pieces > 1 && !fanKeepsAngles(pieces)) pieces = 1;
    for (int i = 1; i < pieces; ++i) insertSample(k + i, piece(i, pieces), false);
    k += pieces - 1;
  }
  std::vector<int> sample(m);
  for (int k = 0; k < m; ++k) {
    sample[k] = out.addVertex(index.pointAt(loop, wrapped(arc[k])), component);
    out.onBoundary[sample[k]] = true;
  }
  report.boundarySamples += m;
  // Triangles in the zip's orientation (see stitchStrip): outer steps {s_k, s_k+1, f_j}, then
  // the front step {f_j+1, f_j, s}.
  for (std::size_t j = 0; j < n; ++j) {
    for (int k = first[j]; k < first[j + 1]; ++k)
      added.push_back({sample[k % m], sample[(k + 1) % m], front[j]});
    added.push_back({front[(j + 1) % n], front[j], sample[first[j + 1] % m]});
    // N = 4: the front step and the outer step of front vertex j + 1, along a straight stretch.
    const std::size_t next = (j + 1) % n;
    if (squares && straight(j) && straight(next))
      out.squares.push_back(
          {sample[first[next] % m], sample[(first[next] + 1) % m], front[next], front[j]});
  }
  // For the slides: the samples in ascending arc order in [0, length).
  LoopSamples samples{loop, spacing, {}, {}, {}};
  std::vector<int> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::rotate(order.begin(),
              std::min_element(order.begin(), order.end(),
                               [&](int a, int b) { return wrapped(arc[a]) < wrapped(arc[b]); }),
              order.end());
  for (const int k : order) {
    samples.vertex.push_back(sample[k]);
    samples.arc.push_back(wrapped(arc[k]));
    samples.corner.push_back(corner[k]);
  }
  loopSamples.push_back(std::move(samples));
  return true;
}

/// A maximal stretch of front vertices nearest to one input loop: front indices [begin, end).
struct FrontRun {
  int loop;
  std::size_t begin, end;
};

/// The runs of equal labels along a front.
std::vector<FrontRun> frontRuns(const std::vector<int>& label) {
  std::vector<FrontRun> runs;
  for (std::size_t k = 0; k < label.size(); ++k) {
    if (runs.empty() || runs.back().loop != label[k]) {
      runs.push_back({label[k], k, k + 1});
    } else {
      runs.back().end = k + 1;
    }
  }
  return runs;
}

/// Whether the runs' loops, in front order and back to the first, walk a tree of bridges (an
/// Euler tour): each step goes to a loop not reached yet or back to the loop it came from.
bool walksATree(const std::vector<FrontRun>& runs) {
  std::vector<int> path{runs.front().loop};
  std::set<int> reached{runs.front().loop};
  for (std::size_t r = 1; r <= runs.size(); ++r) {
    const int loop = runs[r % runs.size()].loop;
    if (reached.insert(loop).second) {
      path.push_back(loop);
    } else if (path.size() >= 2 && path[path.size() - 2] == loop) {
      path.pop_back();
    } else {
      return false;
    }
  }
  return path.size() == 1;
}

/// The outer side of a strip whose front runs along several input loops, and the front's
/// positions along it.
struct BridgedStrip {
  std::vector<int> outer;
  std::vector<double> outerParam, frontParam;
  double total = 0.0;
};

/// The samples of each input loop along a front (vertex indices and arc positions).
using SampledLoops = std::map<int, std::pair<std::vector<int>, std::vector<double>>>;

/// The sample of loop i (arc positions `sampleArc`) nearest along the loop to arc position `at`;
/// the lowest index among ties.
std::size_t nearestSample(const BoundaryIndex& index, int i, const std::vector<double>& sampleArc,
                          double at) {
  const auto distance = [&](std::size_t sample) {
    const double d = index.wrappedArc(i, sampleArc[sample] - at);
    return std::min(d, index.loopLength(i) - d);
  };
  std::size_t nearest = 0;
  for (std::size_t sample = 1; sample < sampleArc.size(); ++sample)
    if (distance(sample) < distance(nearest)) nearest = sample;
  return nearest;
}

/// Appends samples from, from + 1, ..., from + steps of loop i (around the loop) to the strip's
/// outer side, after a bridge from its last vertex; a whole loop (steps = its sample count) ends
/// at its first sample again, at the loop's length. Returns the outer parameter of the first.
double appendLoopSamples(const BoundaryIndex& index, int i, const SampledLoops& loops,
                         std::size_t from, std::size_t steps,
                         const std::vector<Eigen::Vector3d>& positions, BridgedStrip& strip) {
  const auto& [samples, sampleArc] = loops.at(i);
  const std::size_t size = samples.size();
  const double start = strip.outer.empty()
                           ? 0.0
                           : strip.outerParam.back() +
                                 (positions[strip.outer.back()] - positions[samples[from]]).norm();
  for (std::size_t t = 0; t <= steps; ++t) {
    const std::size_t at = (from + t) % size;
    strip.outer.push_back(samples[at]);
    strip.outerParam.push_back(
        start +
        (t == size ? index.loopLength(i) : index.wrappedArc(i, sampleArc[at] - sampleArc[from])));
  }
  return start;
}

/// The outer parameter of a front vertex at arc position `arc` on loop i, whose samples on the
/// outer side start at arc position `startArc` and parameter `start`: a vertex more than `behind`
/// ahead along the loop sits a little before the start.
double frontParameter(const BoundaryIndex& index, int i, double arc, double startArc, double start,
                      double behind) {
  double d = index.wrappedArc(i, arc - startArc);
  if (d > behind) d -= index.loopLength(i);
  return start + d;
}

/// The strip's outer side for a front whose runs walk a tree of bridges (`walksATree`). Each
/// input loop is cut once between each two of its runs, half-way along the loop from the one's
/// last front vertex to the next one's first (where the front turns to a neighbouring loop);
/// each run takes the samples between its cuts, and consecutive runs are joined by a bridge from
/// one's last sample to the next one's first. Every bridge is then walked once each way, an
/// interior edge of the strip, so the loops stay apart. Nothing when the runs do not walk a tree
/// or their cuts fall out of order.
std::optional<BridgedStrip> bridgedAlongRuns(const BoundaryIndex& index,
                                             const std::vector<FrontRun>& runs,
                                             const std::vector<double>& arc,
                                             const SampledLoops& loops,
                                             const std::vector<Eigen::Vector3d>& positions) {
  if (runs.size() < 2 || !walksATree(runs)) return std::nullopt;
  std::map<int, std::vector<std::size_t>> runsOf;  // loop -> its runs in front order
  for (std::size_t r = 0; r < runs.size(); ++r) runsOf[runs[r].loop].push_back(r);
  // Per run: the indices of its first and last sample on its loop.
  std::vector<std::size_t> from(runs.size()), to(runs.size());
  for (const auto& [i, own] : runsOf) {
    const std::vector<double>& sampleArc = loops.at(i).second;
    const std::size_t m = own.size(), size = sampleArc.size();
    std::vector<std::size_t> cut(m);  // cut[k]: before run own[k]
    for (std::size_t k = 0; k < m; ++k) {
      const double exit = arc[runs[own[(k + m - 1) % m]].end - 1];
      const double entry = arc[runs[own[k]].begin];
      cut[k] = nearestSample(index, i, sampleArc, exit + 0.5 * index.wrappedArc(i, entry - exit));
    }
    std::size_t steps = 0;  // the runs' samples tile the loop once when the cuts are in order
    for (std::size_t k = 0; k < m; ++k) steps += (cut[(k + 1) % m] + size - cut[k]) % size;
    if (m > 1 && steps != size) return std::nullopt;
    for (std::size_t k = 0; k < m; ++k) from[own[k]] = cut[k], to[own[k]] = cut[(k + 1) % m];
  }

  BridgedStrip strip;
  strip.frontParam.resize(arc.size());
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const int i = runs[r].loop;
    const std::size_t size = loops.at(i).first.size();
    const bool whole = runsOf.at(i).size() == 1;
    const std::size_t steps = whole ? size : (to[r] + size - from[r]) % size;
    const double length = index.loopLength(i);
    const double start = appendLoopSamples(index, i, loops, from[r], steps, positions, strip);
    // A front vertex a little before the run's first sample (closer to it, behind, than to the
    // run's end, ahead) sits before it.
    const double span = strip.outerParam.back() - start;
    const double behind = whole ? 0.75 * length : span + 0.5 * (length - span);
    const double startArc = loops.at(i).second[from[r]];
    for (std::size_t k = runs[r].begin; k < runs[r].end; ++k)
      strip.frontParam[k] = frontParameter(index, i, arc[k], startArc, start, behind);
  }
  strip.total = strip.outerParam.back() +
                (positions[strip.outer.back()] - positions[strip.outer.front()]).norm();
  return strip;
}

/// The strip's outer side with each loop walked once around from the sample nearest where the
/// front first reaches it, in that order, joined by bridges and the chain of bridges walked
/// back (each bridge once each way, so the loops stay apart).
BridgedStrip chainedLoops(const BoundaryIndex& index, const std::vector<int>& label,
                          const std::vector<double>& arc, const SampledLoops& loops,
                          const std::vector<Eigen::Vector3d>& positions) {
  std::vector<int> order;  // the input loops in the order the front reaches them
  std::vector<double> entryArc;
  for (std::size_t k = 0; k < label.size(); ++k)
    if (std::find(order.begin(), order.end(), label[k]) == order.end())
      order.push_back(label[k]), entryArc.push_back(arc[k]);
  BridgedStrip strip;
  std::map<int, std::pair<double, double>> offsetAndStart;  // loop -> (offset, start arc)
  std::vector<int> bridgeEnds;  // per loop in `order`: its first sample, where its bridge ends
  for (std::size_t o = 0; o < order.size(); ++o) {
    const int i = order[o];
    const auto& [samples, sampleArc] = loops.at(i);
    const std::size_t first = nearestSample(index, i, sampleArc, entryArc[o]);
    offsetAndStart[i] = {
        appendLoopSamples(index, i, loops, first, samples.size(), positions, strip),
        sampleArc[first]};
    bridgeEnds.push_back(samples[first]);
  }
  // Back along the bridges to the first loop (with only the chain's forward bridges and the
  // closing edge from the last loop to the first, three or more loops would join into one).
  double offset = strip.outerParam.back();
  for (std::size_t o = bridgeEnds.size() - 1; o-- > 1;) {
    offset += (positions[strip.outer.back()] - positions[bridgeEnds[o]]).norm();
    strip.outer.push_back(bridgeEnds[o]);
    strip.outerParam.push_back(offset);
  }
  strip.total = offset + (positions[strip.outer.back()] - positions[strip.outer.front()]).norm();
  strip.frontParam.resize(label.size());
  for (std::size_t k = 0; k < label.size(); ++k) {
    const auto [start, startArc] = offsetAndStart.at(label[k]);
    // Just before the loop's first sample.
    strip.frontParam[k] =
        frontParameter(index, label[k], arc[k], startArc, start, 0.75 * index.loopLength(label[k]));
  }
  return strip;
}

/// Whether some directed edge is in two of the triangles (a strip folded onto itself, as when
/// both sides of a bridge take the same front vertex).
bool reusesAnEdge(const std::vector<Triangle>& triangles) {
  std::set<std::pair<int, int>> edges;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k)
      if (!edges.insert({t[k], t[(k + 1) % 3]}).second) return true;
  return false;
}

/// Samples the input loops `inputs` at the front's edge length and stitches the strip between
/// them and the lattice front (step 5). With several input loops, their samples are chained into
/// one outer loop by bridge edges, each walked once each way, so the strip (a sphere with 1 + k
/// holes) is triangulated in one zip and keeps the k loops apart. Two outer loops are built:
/// along the front run by run (`bridgedAlongRuns`, when the runs walk a tree of bridges), and
/// each loop walked whole in the order the front reaches them (`chainedLoops`). The first is
/// zipped first along three or more loops, the second along two; the other is taken when the
/// zip reuses a directed edge (both sides of a bridge on one front vertex fold the strip onto
/// itself). A front along a single loop is stitched by valence when it can be
/// (stitchFrontByValence).
void stitchFront(const BoundaryIndex& index, const std::vector<int>& inputLoopComponent,
                 const std::vector<int>& inputs, std::vector<int> front,
                 const std::vector<double>& h, const std::vector<int>& latticeValence,
                 const std::vector<Eigen::Vector3d>& normals, const ExtractOptions& options,
                 Assembly& out, std::vector<Triangle>& added, std::vector<Triangle>& regular,
                 std::vector<LoopSamples>& loopSamples, ExtractionReport& report) {
  const std::size_t n = front.size();
  std::vector<double> frontH;
  for (const int v : front) frontH.push_back(h[v]);
  const double spacing = median(frontH);
  // The nearest of the input loops for each front vertex, and the arc position on it.
  std::vector<int> label(n);
  std::vector<double> arc(n);
  for (std::size_t j = 0; j < n; ++j) {
    BoundaryIndex::Hit best;
    for (const int i : inputs) {
      const auto hit = index.nearestOnLoop(out.positions[front[j]], i);
      if (hit.distance < best.distance) best = hit;
    }
    label[j] = best.loop, arc[j] = best.arc;
  }
  const auto addSamples = [&](int i) {
    std::vector<bool> corner;
    std::vector<double> sampleArc =
        sampleBoundaryLoop(index, i, spacing, options.sharpBoundaryAngle, &corner);
    std::vector<int> samples;
    for (const double s : sampleArc) {
      samples.push_back(out.addVertex(index.pointAt(i, s), inputLoopComponent[i]));
      out.onBoundary[samples.back()] = true;
    }
    report.boundarySamples += static_cast<long long>(samples.size());
    loopSamples.push_back({i, spacing, samples, sampleArc, corner});
    return std::pair{samples, sampleArc};
  };
  if (inputs.size() == 1) {
    std::vector<int> valenceFront = front;
    std::vector<double> valenceArc = arc;
    alignFrontToLoop({arc[0]}, valenceFront, valenceArc, index.loopLength(inputs[0]));
    for (std::size_t j = 1; j < n; ++j) valenceArc[j] = std::max(valenceArc[j], valenceArc[j - 1]);
    if (stitchFrontByValence(index, inputs[0], inputLoopComponent[inputs[0]], valenceFront,
                             valenceArc, latticeValence, spacing, options, out, regular,
                             loopSamples, report))
      return;
    const auto [samples, sampleArc] = addSamples(inputs[0]);
    alignFrontToLoop(sampleArc, front, arc, index.loopLength(inputs[0]));
    stitchStrip(out.positions, normals, samples, sampleArc, front, arc, index.loopLength(inputs[0]),
                added);
    return;
  }
  // Start the front where its label changes, so that each loop's first run begins a piece.
  std::size_t start = 0;
  for (std::size_t j = 0; j < n; ++j)
    if (label[j] != label[(j + n - 1) % n]) {
      start = j;
      break;
    }
  std::vector<int> rotated(n);
  std::vector<int> rotatedLabel(n);
  std::vector<double> rotatedArc(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t j = (start + k) % n;
    rotated[k] = front[j], rotatedLabel[k] = label[j], rotatedArc[k] = arc[j];
  }
  SampledLoops loops;
  for (const int i : rotatedLabel)
    if (loops.find(i) == loops.end()) loops.emplace(i, addSamples(i));
  // Two outer sides to zip: along the front's runs first when the front passes three loops or
  // more, else the loops walked whole; the other when the first folds the strip onto itself.
  const std::vector<FrontRun> runs = frontRuns(rotatedLabel);
  std::vector<BridgedStrip> sides;
  auto alongRuns = bridgedAlongRuns(index, runs, rotatedArc, loops, out.positions);
  if (alongRuns && loops.size() >= 3) sides.push_back(std::move(*alongRuns)), alongRuns.reset();
  sides.push_back(chainedLoops(index, rotatedLabel, rotatedArc, loops, out.positions));
  if (alongRuns) sides.push_back(std::move(*alongRuns));
  // When neither zip is clean, the first choice; the repair mends its folds.
  std::vector<Triangle> chosen;
  for (std::size_t k = 0; k < sides.size(); ++k) {
    std::vector<Triangle> zipped;
    stitchStrip(out.positions, normals, sides[k].outer, sides[k].outerParam, rotated,
                sides[k].frontParam, sides[k].total, zipped);
    const bool clean = !reusesAnEdge(zipped);
    if (k == 0 || clean) chosen = std::move(zipped);
    if (clean) break;
  }
  added.insert(added.end(), chosen.begin(), chosen.end());
}

/// A strip or fill edge longer than this many local spacings is split (splitLongEdges).
constexpr double kSplitEdgeInSpacings = 1.75;
/// Not when the input is farther than this many edge lengths from its midpoint: the edge passes
/// over a hole (the Stanford bunny's base at K = 2500: splits 0.2-0.4 edge lengths off the flat
/// base raised the Hausdorff distance from 0.89 to 1.52%). A curve that bends no more than an
/// arc of a circle whose radius is the edge's length stays within its sagitta, 0.134 edge lengths.
constexpr double kSplitLeavingInput = 0.125;
/// Nor when the midpoint is within this many edge lengths of an apex of its two triangles.
constexpr double kSplitApexClearance = 0.01;

/// The vertices of folds at `region` (it and `others` together): the ends of an edge in more
/// than two triangles, or of a directed edge in two. Only the edges at the region's vertices
/// are counted (the lattice elsewhere does not matter).
std::vector<bool> foldVertices(const std::vector<Triangle>& region,
                               const std::vector<Triangle>& others, std::size_t vertexCount) {
  std::vector<bool> inRegion(vertexCount, false);
  for (const auto& t : region)
    for (const int v : t) inRegion[v] = true;
  std::map<std::pair<int, int>, int> directed;
  for (const std::vector<Triangle>* set : {&region, &others})
    for (const auto& t : *set)
      for (int k = 0; k < 3; ++k)
        if (inRegion[t[k]] || inRegion[t[(k + 1) % 3]]) ++directed[{t[k], t[(k + 1) % 3]}];
  std::vector<bool> fold(vertexCount, false);
  for (const auto& [edge, count] : directed) {
    const auto opposite = directed.find({edge.second, edge.first});
    if (count > 1 || (opposite != directed.end() && opposite->second > 1))
      fold[edge.first] = fold[edge.second] = true;
  }
  return fold;
}

/// Splits the edges between two `region` triangles longer than kSplitEdgeInSpacings spacings
/// (`spacing` per vertex, `typical` for vertices without one), longest first: a new vertex at
/// the edge's midpoint, moved onto the input (`input`, built on the first split; not when null),
/// halves both triangles.
/// Where input holes sit closer together than the lattice, the strip between them is several
/// edge lengths wide, and the zip joins a hole's short edge to a front vertex far away (a
/// sphere with 40 holes of half an edge across: a 3.4° sliver at K = 850); split, the strip gets
/// interior vertices that the flips and the surface fit's relaxation shape. Triangles at a fold
/// (`others` and `region` together: an edge in more than two triangles) stay for the repair.
/// Returns the number of splits.
long long splitLongEdges(const TriMesh& mesh, std::optional<ClosestPointQuery>* input,
                         const std::vector<double>& spacing, double typical,
                         const std::vector<Triangle>& others, Assembly& out,
                         std::vector<Triangle>& region) {
  const std::vector<bool> fold = foldVertices(region, others, out.positions.size());
  const auto limit = [&](int a, int b) {
    const auto local = [&](int v) {
      return v < static_cast<int>(spacing.size()) && spacing[v] > 0.0 ? spacing[v] : typical;
    };
    return kSplitEdgeInSpacings * std::max(local(a), local(b));
  };
  const auto length = [&](int a, int b) { return (out.positions[a] - out.positions[b]).norm(); };
  std::map<std::pair<int, int>, int> triangleOf;  // directed edge -> its region triangle
  const auto setTriangle = [&](std::size_t i, const Triangle& t) {
    if (i == region.size()) region.push_back(t);
    region[i] = t;
    for (int k = 0; k < 3; ++k) triangleOf[{t[k], t[(k + 1) % 3]}] = static_cast<int>(i);
  };
  for (std::size_t i = 0; i < region.size(); ++i) setTriangle(i, region[i]);
  // Candidate edges (a < b) by length; an edge split before it is popped no longer exists.
  std::priority_queue<std::tuple<double, int, int>> queue;
  const auto consider = [&](int a, int b) {
    if (a > b) std::swap(a, b);
    if (!triangleOf.count({a, b}) || !triangleOf.count({b, a})) return;
    if (const double l = length(a, b); l > limit(a, b)) queue.emplace(l, a, b);
  };
  for (const auto& [edge, triangle] : triangleOf) consider(edge.first, edge.second);
  const auto apex = [&](int i, int a, int b) {
    const Triangle& t = region[i];
    return t[0] != a && t[0] != b ? t[0] : t[1] != a && t[1] != b ? t[1] : t[2];
  };
  const auto atFold = [&](int v) { return v < static_cast<int>(fold.size()) && fold[v]; };
  // Each split halves an edge; the bound guards against a cycle of near-degenerate splits.
  const auto maxSplits = static_cast<long long>(region.size());
  long long splits = 0;
  while (!queue.empty() && splits < maxSplits) {
    const auto [unused, a, b] = queue.top();
    queue.pop();
    const auto ab = triangleOf.find({a, b}), ba = triangleOf.find({b, a});
    if (ab == triangleOf.end() || ba == triangleOf.end()) continue;
    const int i = ab->second, j = ba->second;
    const int c = apex(i, a, b), d = apex(j, a, b);
    if (c == d || atFold(a) || atFold(b) || atFold(c) || atFold(d)) continue;
    const Eigen::Vector3d midpoint = 0.5 * (out.positions[a] + out.positions[b]);
    if (input && !*input) input->emplace(mesh);
    const Eigen::Vector3d onInput = input ? (*input)->closest(midpoint).point : midpoint;
    if ((onInput - midpoint).norm() > kSplitLeavingInput * length(a, b)) continue;
    // A flat triangle with its apex on the midpoint: halves of it would be degenerate.
    if (std::min((out.positions[c] - onInput).norm(), (out.positions[d] - onInput).norm()) <
        kSplitApexClearance * length(a, b))
      continue;
    const int m = out.addVertex(onInput, out.component[a]);
    triangleOf.erase(ab);
    triangleOf.erase(ba);
    // (a, b, c) and (b, a, d) become (a, m, c), (m, b, c), (b, m, d) and (m, a, d).
    setTriangle(i, {a, m, c});
    setTriangle(region.size(), {m, b, c});
    setTriangle(j, {b, m, d});
    setTriangle(region.size(), {m, a, d});
    ++splits;
    for (const int v : {a, b, c, d}) consider(m, v);
  }
  return splits;
}

}  // namespace

void closeBoundaries(const TriMesh& mesh, std::optional<ClosestPointQuery>* input,
                     const std::vector<int>& faceComponent, const ExtractOptions& options,
                     Assembly& out, ExtractionReport& report) {
  std::vector<std::vector<Eigen::Vector3d>> inputLoops;
  std::vector<int> inputLoopComponent;
  inputBoundaryLoops(mesh, faceComponent, inputLoops, inputLoopComponent);
  std::vector<double> h = localEdgeLength(out);
  const double typical = median(std::vector<double>(h.begin(), h.end()));
  if (typical <= 0.0) return;  // no lattice triangles at all
  const BoundaryIndex index(inputLoops, 2.0 * typical, inputLoopComponent);

  if (options.boundary == BoundaryMode::Follow && !inputLoops.empty()) {
    std::vector<bool> drop(out.positions.size(), false);
    for (std::size_t v = 0; v < out.positions.size(); ++v) {
      if (h[v] <= 0.0) continue;
      const auto hit = index.nearestInComponent(
          out.positions[v], options.boundarySnapDistance * h[v], out.component[v]);
      if (hit.loop >= 0) drop[v] = true, ++report.boundarySnapped;
    }
    removeVertices(out, drop);
    h = localEdgeLength(out);
    // Where the lattice, squeezed between two nearby input loops, touches itself at a vertex,
    // the front would pass it twice; only its largest fan stays.
    std::vector<bool> nearBoundary(out.positions.size(), false);
    for (std::size_t v = 0; v < out.positions.size(); ++v) {
      const double reach = (options.boundarySnapDistance + 2.0) * std::max(h[v], typical);
      nearBoundary[v] =
          h[v] > 0.0 &&
          index.nearestInComponent(out.positions[v], reach, out.component[v]).loop >= 0;
    }
    report.pinchedFanTriangles +=
        keepLargestFans(out.triangles, out.positions.size(), nearBoundary);
    h = localEdgeLength(out);
  }
  // Classify the loops of the lattice triangles: a front when most of its vertices are within
  // reach of the input boundary, else a gap. Each input loop is stitched to the front that has
  // the most vertices near it; a front near several loops (the lattice does not fit between
  // them) is stitched to all of them at once.
  const auto loops = traceBoundaryLoops(out.triangles);
  std::vector<std::map<int, int>> votes(loops.size());
  std::vector<bool> isFront(loops.size(), false);
  for (std::size_t l = 0; l < loops.size(); ++l) {
    int near = 0;
    for (const int v : loops[l]) {
      const double reach = (options.boundarySnapDistance + 2.0) * std::max(h[v], typical);
      const auto hit = index.nearestInComponent(out.positions[v], reach, out.component[v]);
      if (hit.loop >= 0) ++votes[l][hit.loop], ++near;
    }
    isFront[l] = 2 * near >= static_cast<int>(loops[l].size());
  }
  std::vector<int> owner(inputLoops.size(), -1);
  for (std::size_t l = 0; l < loops.size(); ++l) {
    if (!isFront[l]) continue;
    for (const auto& [i, count] : votes[l])
      if (count >= 2 && (owner[i] < 0 || count > votes[owner[i]].at(i)))
        owner[i] = static_cast<int>(l);
  }
  std::vector<std::vector<int>> assigned(loops.size());
  for (int i = 0; i < static_cast<int>(inputLoops.size()); ++i)
    if (owner[i] >= 0) assigned[owner[i]].push_back(i);

  std::vector<bool> componentHasLattice(
      *std::max_element(faceComponent.begin(), faceComponent.end()) + 1, false);
  for (const auto& t : out.triangles) componentHasLattice[out.component[t[0]]] = true;
  for (int i = 0; i < static_cast<int>(inputLoops.size()); ++i)
    if (owner[i] < 0 && componentHasLattice[inputLoopComponent[i]]) ++report.unmatchedBoundaryLoops;

  const std::vector<Eigen::Vector3d> normals = vertexNormals(out);
  const std::vector<int> latticeValence = polygonValences(out);
  const std::size_t latticeSquares = out.squares.size();  // then the strips' (N = 4)
  // Strip and fill triangles: `added` may be flipped; `regular` (stitched by valence) keeps its
  // connectivity, which gives every front vertex valence 6.
  std::vector<Triangle> added, regular;
  std::vector<LoopSamples> loopSamples;  // the samples of every stitched input loop
  std::vector<int> gaps;
  for (std::size_t l = 0; l < loops.size(); ++l) {
    if (assigned[l].empty()) {
      gaps.push_back(static_cast<int>(l));
      continue;
    }
    if (options.boundary != BoundaryMode::Follow) {
      for (const int v : loops[l]) out.onBoundary[v] = true;
      continue;
    }
    const std::size_t before = added.size() + regular.size();
    stitchFront(index, inputLoopComponent, assigned[l], loops[l], h, latticeValence, normals,
                options, out, added, regular, loopSamples, report);
    report.stripTriangles += static_cast<long long>(added.size() + regular.size() - before);
  }
  std::sort(gaps.begin(), gaps.end());
  for (const int l : gaps) fillGap(loops[l], out, added, report);
  // Samples slide along the input boundary to open up the strip's thin triangles, then flips;
  // a second slide after the flips.
  const auto strips = [&] {
    std::vector<Triangle> all = added;
    all.insert(all.end(), regular.begin(), regular.end());
    return all;
  };
  report.boundarySlides +=
      slideBoundarySamples(index, loopSamples, strips(), out.positions, out.squares);
  out.triangles.insert(out.triangles.end(), regular.begin(), regular.end());
  report.stripFlips += improveByFlips(out.positions, out.triangles, added);
  report.stripSplits += splitLongEdges(mesh, input, h, typical, out.triangles, out, added);
  report.stripFlips += improveByFlips(out.positions, out.triangles, added);
  report.boundarySlides +=
      slideBoundarySamples(index, loopSamples, strips(), out.positions, out.squares);
  out.triangles.insert(out.triangles.end(), added.begin(), added.end());
  // A strip square whose corners the slides could not bring within kQuadCornerWindow of 90°
  // stays two triangles (which pairTriangles may still pair otherwise).
  const auto far = [&](const std::array<int, 4>& square) {
    std::array<Eigen::Vector3d, 4> corners;
    for (int k = 0; k < 4; ++k) corners[k] = out.positions[square[k]];
    return worstCornerDeviation(corners) > kQuadCornerWindow;
  };
  out.squares.erase(
      std::remove_if(out.squares.begin() + static_cast<std::ptrdiff_t>(latticeSquares),
                     out.squares.end(), far),
      out.squares.end());
}

}  // namespace hexcover::extract_detail
