#include "core/param/fold_repair.h"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "core/common/concurrency.h"
#include "core/param/lattice.h"
#include "core/param/rounding.h"

namespace hexcover::param_detail {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

// llround(v), rounding half away from zero, for |v| < 2^52 without a library call: v − trunc(v)
// is exact there.
std::int64_t roundHalfAway(double v) {
  const auto t = static_cast<std::int64_t>(v);
  const double rest = v - static_cast<double>(t);
  return t + static_cast<std::int64_t>(rest >= 0.5) - static_cast<std::int64_t>(rest <= -0.5);
}

/// Lattice coordinates up to which the quantum is the finest, 2^-30 (see CornerSnapper).
constexpr double kLargestForFinestQuantum = 262144.0;  // 2^18

/// The exact corner coordinates of one solution x (see snapCoordinates), corner by corner: the
/// quantum and the integer values are found for the whole mesh, a wedge's coordinates when asked.
/// `Solution` is read unknown by unknown (x[column]).
template <typename Solution>
class CornerSnapper {
 public:
  using Vector2l = Eigen::Matrix<std::int64_t, 2, 1>;

  /// `masterBound`, when known: a bound of the masters' lattice coordinates |M⁻¹(u, v)|. At most
  /// kLargestForFinestQuantum it gives the quantum without reading every master; else, or
  /// without it, they are read.
  CornerSnapper(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u, const Solution& x, int n,
                std::optional<double> masterBound = std::nullopt)
      : cm_(cm), u_(u), x_(x), toLattice_(latticeBasis(n).inverse()), rotation_(n) {
    double largest = 1.0;
    if (masterBound && *masterBound <= kLargestForFinestQuantum) {
      largest = std::max(largest, *masterBound);
    } else {
      // Vertices without columns (isolated, deleted, paired or the gauge) stay at 0.
      master_.assign(mesh.n_vertices(), Eigen::Vector2d::Zero());
      for (std::size_t v = 0; v < master_.size(); ++v) {
        if (u.vertexColumn[v] < 0) continue;
        master_[v] = masterOf(static_cast<int>(v));
        largest = std::max(largest, master_[v].cwiseAbs().maxCoeff());
      }
    }
    const std::vector<std::int64_t> rounded = roundedFreeUnknowns(u, x);
    pairValue_.resize(2 * cm.pairCount);
    for (int scalar = 0; scalar < 2 * cm.pairCount; ++scalar) {
      pairValue_[scalar] = integerValue(u, rounded, scalar);
      largest = std::max(largest, std::abs(static_cast<double>(pairValue_[scalar])));
    }
    exponent_ = std::min(30, 48 - static_cast<int>(std::ceil(std::log2(largest))));
    scale_ = std::ldexp(1.0, exponent_);
    for (auto& value : pairValue_) value *= std::int64_t{1} << exponent_;
    for (int k = 0; k < n; ++k) rotation_[k] = latticeRotation(n, k).cast<std::int64_t>();
  }

  int exponent() const { return exponent_; }

  /// Wedge w in quanta: its master's coordinates (a vertex's own position, or its lattice point
  /// when it has a pair; |value| ≤ 2^48) under the wedge's integer transform.
  std::array<std::int64_t, 2> wedge(std::size_t w) const {
    const auto& transform = cm_.wedgeTransform[w];
    const Vector2l m = snappedMaster(cm_.wedgeVertex[w]);
    Vector2l z = transform.rotation == 0 ? m : Vector2l(rotation_[transform.rotation] * m);
    for (const auto& term : transform.terms) {
      const Vector2l y(pairValue_[2 * term.pair], pairValue_[2 * term.pair + 1]);
      z += term.sign * (rotation_[term.rotation] * y);
    }
    return {z.x(), z.y()};
  }

 private:
  /// M⁻¹(u, v) of a vertex with columns.
  Eigen::Vector2d masterOf(int v) const {
    const int column = u_.vertexColumn[v];
    return toLattice_ * Eigen::Vector2d(x_[column], x_[column + 1]);
  }

  Vector2l snappedMaster(int v) const {
    if (const int pair = cm_.vertexPair[v]; pair >= 0)
      return {pairValue_[2 * pair], pairValue_[2 * pair + 1]};
    if (u_.vertexColumn[v] < 0) return Vector2l::Zero();
    const Eigen::Vector2d master = master_.empty() ? masterOf(v) : master_[v];
    return {roundHalfAway(master.x() * scale_), roundHalfAway(master.y() * scale_)};
  }

  const CutMesh& cm_;
  const Unknowns& u_;
  const Solution& x_;
  Eigen::Matrix2d toLattice_;
  std::vector<Eigen::Vector2d> master_;  ///< #V when read for the quantum, else empty
  std::vector<std::int64_t> pairValue_;  ///< 2 per pair, in quanta
  std::vector<Eigen::Matrix<std::int64_t, 2, 2>> rotation_;  ///< R^k, k = 0 … n − 1
  int exponent_ = 0;
  double scale_ = 1.0;  ///< 2^exponent
};

/// A rounding repair's trial move of x, read unknown by unknown without forming it: the real
/// unknowns plus move_k · response_k, k in order, the unit's integer unknowns moved and rounded.
class MovedSolution {
 public:
  MovedSolution(const Eigen::VectorXd& x, int realCount) : x_(x), realCount_(realCount) {}

  void add(int column, double move, const Eigen::VectorXd& response) {
    responses_.push_back({move, &response});
    moved_.push_back({column, std::round(x_[column] + move)});
  }

  /// The moved solution as a vector (the one that is kept).
  Eigen::VectorXd formed() const {
    Eigen::VectorXd moved(x_.size());
    for (Eigen::Index column = 0; column < moved.size(); ++column)
      moved[column] = (*this)[static_cast<int>(column)];
    return moved;
  }

  double operator[](int column) const {
    if (column < realCount_) {
      double value = x_[column];
      for (const auto& [move, response] : responses_) value += move * (*response)[column];
      return value;
    }
    for (const auto& [movedColumn, value] : moved_)
      if (movedColumn == column) return value;
    return x_[column];
  }

 private:
  const Eigen::VectorXd& x_;
  int realCount_;
  std::vector<std::pair<double, const Eigen::VectorXd*>> responses_;
  std::vector<std::pair<int, double>> moved_;
};

/// The sign of a parameter triangle's orientation from its corners in quanta (exact).
int orientationSign(const std::array<std::int64_t, 2>& a, const std::array<std::int64_t, 2>& b,
                    const std::array<std::int64_t, 2>& c) {
  const __int128 ax = b[0] - a[0], ay = b[1] - a[1];
  const __int128 bx = c[0] - a[0], by = c[1] - a[1];
  const __int128 det = ax * by - ay * bx;  // same sign in lattice and Cartesian coordinates
  return (det > 0) - (det < 0);
}

/// The wedges of `cm` in quanta, as snapCoordinates.
template <typename Solution>
SnappedCoordinates snapAll(const CutMesh& cm, const CornerSnapper<Solution>& snapper) {
  SnappedCoordinates s;
  s.exponent = snapper.exponent();
  s.wedge.resize(cm.wedgeVertex.size());
  for (std::size_t w = 0; w < s.wedge.size(); ++w) s.wedge[w] = snapper.wedge(w);
  return s;
}

/// Per rounding unit (unitOfColumn: the unit of each integer column, or −1): the faces with a
/// corner that depends on it (through a wedge's row) and those within kNearRings vertex rings of
/// them: where its moves flip most of the triangles they flip (repairRounding judges them there
/// first).
std::vector<std::vector<int>> facesNearUnits(const TriMesh& mesh, const CutMesh& cm,
                                             const Unknowns& u,
                                             const std::vector<int>& unitOfColumn, int unitCount) {
  constexpr int kNearRings = 2;
  std::vector<std::vector<int>> near(unitCount);
  for (std::size_t f = 0; f < cm.faceWedges.size(); ++f)
    for (const int wedge : cm.faceWedges[f])
      for (const auto& row : u.wedgeRows[wedge])
        for (const auto& [column, c] : row)
          if (const int unit = unitOfColumn[column];
              unit >= 0 && (near[unit].empty() || near[unit].back() != static_cast<int>(f)))
            near[unit].push_back(static_cast<int>(f));
  std::vector<int> seenBy(mesh.n_faces(), -1);  // the last unit that listed the face
  for (int unit = 0; unit < unitCount; ++unit) {
    std::vector<int>& faces = near[unit];
    for (const int f : faces) seenBy[f] = unit;
    for (std::size_t ring = 0, begin = 0; ring < kNearRings; ++ring) {
      const std::size_t end = faces.size();
      for (std::size_t k = begin; k < end; ++k)
        for (const auto vh : mesh.fv_range(mesh.face_handle(faces[k])))
          for (const auto g : mesh.vf_range(vh))
            if (seenBy[g.idx()] != unit) {
              seenBy[g.idx()] = unit;
              faces.push_back(g.idx());
            }
      begin = end;
    }
  }
  return near;
}

}  // namespace

SnappedCoordinates snapCoordinates(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u,
                                   const Eigen::VectorXd& x, int n) {
  return snapAll(cm, CornerSnapper<Eigen::VectorXd>(mesh, cm, u, x, n));
}

bool fewerFaults(const Orientation& a, const Orientation& b) {
  return a.flipped != b.flipped ? a.flipped < b.flipped : a.degenerate < b.degenerate;
}

Orientation countOrientation(const TriMesh& mesh, const CutMesh& cm, const SnappedCoordinates& s,
                             std::vector<bool>* flippedFaces, std::vector<bool>* degenerateFaces) {
  Orientation o;
  if (flippedFaces) flippedFaces->assign(mesh.n_faces(), false);
  if (degenerateFaces) degenerateFaces->assign(mesh.n_faces(), false);
  for (std::size_t f = 0; f < cm.faceWedges.size(); ++f) {
    const auto& [z0, z1, z2] = cm.faceWedges[f];
    const int sign = orientationSign(s.wedge[z0], s.wedge[z1], s.wedge[z2]);
    if (sign == 0) {
      ++o.degenerate;
      if (degenerateFaces) (*degenerateFaces)[f] = true;
    }
    if (sign < 0) {
      ++o.flipped;
      if (flippedFaces) (*flippedFaces)[f] = true;
    }
  }
  return o;
}

void repairRounding(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u, EnergySystem& system,
                    int n, int threads, Eigen::VectorXd& x, SnappedCoordinates& snapped,
                    Orientation& orientation, std::vector<bool>& flippedFaces) {
  const auto units = roundingUnits(u);
  const Eigen::Matrix2d toLattice = latticeBasis(n).inverse();
  const double toLatticeNorm = toLattice.cwiseAbs().rowwise().sum().maxCoeff();  // ‖M⁻¹‖∞
  std::vector<int> unitOfColumn(u.columns(), -1);
  for (std::size_t i = 0; i < units.size(); ++i)
    for (const int column : units[i]) unitOfColumn[column] = static_cast<int>(i);
  const std::vector<std::vector<int>> nearUnit =
      facesNearUnits(mesh, cm, u, unitOfColumn, static_cast<int>(units.size()));
  std::vector<bool> degenerateFaces;  // kept up to date with flippedFaces below
  countOrientation(mesh, cm, snapped, nullptr, &degenerateFaces);
  // What the trial moves are judged against, updated with x: the largest lattice coordinate of a
  // master and the faulty faces. Most moves leave more faults (98% on feline at K = 779), mostly
  // near the unit. The faulty faces and those near the unit are judged first: more flipped among
  // them than now in all already rules a move out (91% of those moves there).
  double largestMaster = 0.0;
  std::vector<int> faulty;
  const auto describeSolution = [&] {
    largestMaster = 0.0;
    for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
      if (const int column = u.vertexColumn[v]; column >= 0)
        largestMaster =
            std::max(largestMaster, (toLattice * x.segment<2>(column)).cwiseAbs().maxCoeff());
    faulty.clear();
    for (std::size_t f = 0; f < cm.faceWedges.size(); ++f)
      if (flippedFaces[f] || degenerateFaces[f]) faulty.push_back(static_cast<int>(f));
  };
  describeSolution();
  for (int pass = 0; pass < 4 && (orientation.flipped > 0 || orientation.degenerate > 0); ++pass) {
    std::set<int> involved;
    for (std::size_t f = 0; f < cm.faceWedges.size(); ++f) {
      if (!flippedFaces[f] && !degenerateFaces[f]) continue;
      for (const int wedge : cm.faceWedges[f])
        for (const auto& row : u.wedgeRows[wedge])
          for (const auto& [column, c] : row)
            if (const int unit = unitOfColumn[column]; unit >= 0) involved.insert(unit);
      if (involved.size() >= 32) break;
    }
    if (involved.empty()) return;  // the faulty corners do not depend on an integer unknown
    // The units in order, each unit's moves in order: the first move that leaves fewer faults is
    // kept. The moves of kUnitWindow units are judged at once, in parallel, from the current x;
    // after a kept move judging goes on from the next unit, so the result is that of judging them
    // one by one.
    constexpr std::size_t kUnitWindow = 4;
    const std::vector<int> order(involved.begin(), involved.end());
    // The responses of every unit of the pass in one solve with many right-hand sides, when
    // they fit in the cache: far cheaper per column than a solve per window.
    std::vector<int> passColumns;
    for (const int unit : order)
      passColumns.insert(passColumns.end(), units[unit].begin(), units[unit].end());
    if (passColumns.size() <= system.responseCapacity()) system.realResponses(passColumns);
    const int realCount = u.realCount;
    bool improved = false;
    for (std::size_t nextUnit = 0; nextUnit < order.size();) {
      struct Trial {
        std::size_t position;       // of the unit in `order`
        std::size_t firstResponse;  // index in `responses` of the unit's first unknown
        Eigen::Vector2d move;
      };
      std::vector<Trial> trials;
      std::vector<int> columns;
      const std::size_t end = std::min(order.size(), nextUnit + kUnitWindow);
      for (std::size_t position = nextUnit; position < end; ++position) {
        const auto& unit = units[order[position]];
        const std::vector<Eigen::Vector2d> moves =
            unit.size() == 2
                ? std::vector<Eigen::Vector2d>{{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}}
                : std::vector<Eigen::Vector2d>{{1, 0}, {-1, 0}};
        for (const auto& move : moves) trials.push_back({position, columns.size(), move});
        columns.insert(columns.end(), unit.begin(), unit.end());
      }
      const std::vector<const Eigen::VectorXd*> responses = system.realResponses(columns);
      const auto movedBy = [&](const Trial& trial) {
        const auto& unit = units[order[trial.position]];
        MovedSolution moved(x, realCount);
        for (std::size_t k = 0; k < unit.size(); ++k)
          moved.add(unit[k], trial.move[k], *responses[trial.firstResponse + k]);
        return moved;
      };
      // A trial's moved solution is read where needed, not formed; the quantum of its snapped
      // corners comes from a bound of its masters' lattice coordinates (see CornerSnapper).
      std::vector<double> largestResponse(responses.size());
      for (std::size_t k = 0; k < responses.size(); ++k)  // none without real unknowns
        largestResponse[k] = realCount > 0 ? responses[k]->cwiseAbs().maxCoeff() : 0.0;
      const auto judge = [&](const Trial& trial) {
        double reach = 0.0;  // bound of |Σ move_k · response_k|
        for (std::size_t k = 0; k < units[order[trial.position]].size(); ++k)
          reach += std::abs(trial.move[k]) * largestResponse[trial.firstResponse + k];
        // Beyond rounding: the bound only has to be far below kLargestForFinestQuantum.
        const double masterBound = (1.0 + 1e-9) * (largestMaster + toLatticeNorm * reach) + 1e-9;
        const MovedSolution moved = movedBy(trial);
        const CornerSnapper snapper(mesh, cm, u, moved, n, masterBound);
        const auto flippedAt = [&](int f) {
          const auto& [z0, z1, z2] = cm.faceWedges[f];
          return orientationSign(snapper.wedge(z0), snapper.wedge(z1), snapper.wedge(z2)) < 0;
        };
        Orientation near;
        for (const int f : faulty) near.flipped += flippedAt(f);
        for (const int f : nearUnit[order[trial.position]])
          if (!flippedFaces[f] && !degenerateFaces[f]) near.flipped += flippedAt(f);
        if (near.flipped > orientation.flipped) return near;
        return countOrientation(mesh, cm, snapAll(cm, snapper));
      };
      std::vector<Orientation> outcome(trials.size());
      parallelFor(
          trials.size(), threads, [&](std::size_t k) { outcome[k] = judge(trials[k]); }, 1);
      const auto better = std::find_if(outcome.begin(), outcome.end(), [&](const Orientation& o) {
        return fewerFaults(o, orientation);
      });
      if (better == outcome.end()) {
        nextUnit = end;
        continue;
      }
      const Trial& trial = trials[static_cast<std::size_t>(better - outcome.begin())];
      x = movedBy(trial).formed();
      snapped = snapCoordinates(mesh, cm, u, x, n);
      orientation = countOrientation(mesh, cm, snapped, &flippedFaces, &degenerateFaces);
      describeSolution();
      improved = true;
      if (orientation.flipped == 0 && orientation.degenerate == 0) return;
      nextUnit = trial.position + 1;
    }
    if (!improved) return;
  }
}

int relaxFoldsLocally(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u,
                      const LeastSquares& ls, const std::vector<double>& faceScale, int n,
                      Eigen::VectorXd& x, SnappedCoordinates& snapped, Orientation& orientation,
                      std::vector<bool>& flippedFaces) {
  constexpr int kSolvesPerRegion = 4;
  // A region of more than this share of the real unknowns is no longer local: its sparse solves
  // cost more than the stiffening's re-solve of the whole system, and none removed the last fold
  // in 745 regions of the clean meshes at V/8 to V/64 (208 such regions, 19 of the 27.5 s spent
  // relaxing). The 1.1M-face bunny's 162 folds are relaxed within 0.7% of its unknowns.
  constexpr double kLargestRegionShare = 0.2;
  int solves = 0;
  for (int rings = 2; rings <= 16 && orientation.flipped > 0; rings *= 2) {
    // Region: vertices within `rings` edges of a flipped triangle's corners.
    std::vector<int> depth(mesh.n_vertices(), -1);
    std::vector<int> frontier;
    for (const auto fh : mesh.faces())
      if (flippedFaces[fh.idx()])
        for (const auto vh : fh.vertices())
          if (depth[vh.idx()] < 0) {
            depth[vh.idx()] = 0;
            frontier.push_back(vh.idx());
          }
    for (int ring = 1; ring <= rings; ++ring) {
      std::vector<int> next;
      for (const int v : frontier)
        for (const auto wh : mesh.vv_range(mesh.vertex_handle(v)))
          if (depth[wh.idx()] < 0) {
            depth[wh.idx()] = ring;
            next.push_back(wh.idx());
          }
      frontier = std::move(next);
    }
    std::vector<int> localColumn(u.realCount, -1), columns;
    for (const auto vh : mesh.vertices())
      if (depth[vh.idx()] >= 0 && u.vertexColumn[vh.idx()] >= 0)
        for (int j = 0; j < 2; ++j) {
          localColumn[u.vertexColumn[vh.idx()] + j] = static_cast<int>(columns.size());
          columns.push_back(u.vertexColumn[vh.idx()] + j);
        }
    if (columns.empty()) continue;
    if (static_cast<double>(columns.size()) > kLargestRegionShare * u.realCount) break;
    std::vector<int> faces;  // faces whose rows involve a region column
    for (const auto fh : mesh.faces()) {
      bool touches = false;
      for (const auto vh : fh.vertices()) touches = touches || depth[vh.idx()] >= 0;
      if (touches && ls.faceArea[fh.idx()] > 0.0) faces.push_back(fh.idx());
    }
    std::vector<int> localRow(ls.target.size(), -1);
    for (std::size_t k = 0; k < faces.size(); ++k)
      for (int r = 0; r < kRowsPerFace; ++r)
        localRow[kRowsPerFace * faces[k] + r] = static_cast<int>(kRowsPerFace * k + r);
    std::vector<Triplet> triplets;
    for (std::size_t j = 0; j < columns.size(); ++j)
      for (SparseMatrix::InnerIterator it(ls.gradient, columns[j]); it; ++it)
        if (localRow[it.row()] >= 0)
          triplets.emplace_back(localRow[it.row()], static_cast<int>(j), it.value());
    const int rows = kRowsPerFace * static_cast<int>(faces.size());
    SparseMatrix local(rows, static_cast<int>(columns.size()));
    local.setFromTriplets(triplets.begin(), triplets.end());
    // Stiffening iterates like the global loop (each step from the last iterate, weights
    // accumulated); the best iterate is kept.
    std::vector<double> weight(faces.size(), 1.0);
    Eigen::VectorXd current = x;
    std::vector<bool> currentFlipped = flippedFaces;
    // The region's rows split as local·x_C + (the held columns' part), and the right-hand side
    // of local·y ≈ target − held part is fixed for the region.
    Eigen::VectorXd xc(columns.size());
    for (std::size_t j = 0; j < columns.size(); ++j) xc[j] = x[columns[j]];
    const Eigen::VectorXd full = ls.gradient * x;
    Eigen::VectorXd rhs(rows);
    for (std::size_t k = 0; k < faces.size(); ++k)
      rhs.segment<kRowsPerFace>(kRowsPerFace * k) =
          ls.target.segment<kRowsPerFace>(kRowsPerFace * faces[k]) -
          full.segment<kRowsPerFace>(kRowsPerFace * faces[k]);
    rhs += local * xc;
    for (int step = 0; step < kSolvesPerRegion && orientation.flipped > 0; ++step) {
      const Eigen::VectorXd residual = local * xc - rhs;
      Eigen::VectorXd rowWeight(rows);
      for (std::size_t k = 0; k < faces.size(); ++k) {
        const int f = faces[k];
        const double misfit = residual.segment<kEnergyRows>(kRowsPerFace * k).squaredNorm() /
                              (2.0 * faceScale[f] * faceScale[f]);
        weight[k] += std::min(5.0 * misfit, 20.0);
        if (currentFlipped[f]) weight[k] *= 2.0;
        rowWeight.segment<kRowsPerFace>(kRowsPerFace * k).setConstant(ls.faceArea[f] * weight[k]);
      }
      const SparseMatrix weighted = rowWeight.asDiagonal() * local;
      SparseMatrix normal = SparseMatrix(local.transpose()) * weighted;
      const double regularization = 1e-14 * normal.diagonal().cwiseAbs().maxCoeff();
      for (int j = 0; j < normal.cols(); ++j) normal.coeffRef(j, j) += regularization;
      const Eigen::SimplicialLDLT<SparseMatrix> solver(normal);
      if (solver.info() != Eigen::Success) return solves;
      const Eigen::VectorXd y = solver.solve(weighted.transpose() * rhs);
      ++solves;
      if (!y.allFinite()) return solves;
      xc = y;
      for (std::size_t j = 0; j < columns.size(); ++j) current[columns[j]] = y[j];
      SnappedCoordinates currentSnap = snapCoordinates(mesh, cm, u, current, n);
      const Orientation currentOrientation =
          countOrientation(mesh, cm, currentSnap, &currentFlipped);
      if (currentOrientation.flipped >= orientation.flipped ||
          currentOrientation.degenerate > orientation.degenerate)
        continue;
      x = current;
      snapped = std::move(currentSnap);
      orientation = currentOrientation;
      flippedFaces = currentFlipped;
    }
  }
  return solves;
}

}  // namespace hexcover::param_detail
