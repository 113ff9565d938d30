#include "core/param/hexcover.h"

#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <string>
#include <type_traits>

#include "core/common/blas_threads.h"
#include "core/common/concurrency.h"
#include "core/common/error.h"
#include "core/common/normal_equations.h"
#include "core/common/sparse_cholesky.h"
#include "core/common/sparse_forward_solve.h"
#include "core/param/conformal_scale.h"
#include "core/param/cut_graph.h"
#include "core/param/integer_elimination.h"
#include "core/param/lattice.h"

namespace hexcover {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

int mod(int a, int n) { return ((a % n) + n) % n; }

// sign · R^rotation · y_pair, a term of a corner's coordinates.
struct TranslationTerm {
  int pair = -1;
  int rotation = 0;  // in [0, n)
  int sign = 1;
};

// z_wedge = R^rotation · z_master + Σ terms.
struct WedgeTransform {
  int rotation = 0;  // in [0, n)
  std::vector<TranslationTerm> terms;
};

// The cut mesh: corners grouped into wedges, each wedge's coordinates as a transform of its
// vertex's master coordinates and integer 2-vectors ("pairs": cut-edge translations, then the
// lattice positions of singular vertices), and the closure constraints among the pairs.
struct CutMesh {
  std::vector<int> halfedgeWedge;  // #H, -1 on boundary halfedges
  std::vector<std::array<int, 3>> faceWedges;  // #F, the wedges of its halfedges, in order
  std::vector<int> wedgeVertex;
  std::vector<WedgeTransform> wedgeTransform;
  std::vector<int> edgePair;       // #E, pair of the cut edge's translation or -1
  std::vector<int> vertexPair;     // #V, pair of the singular vertex's position or -1
  std::vector<bool> realGauge;     // #V, master coordinates fixed at 0 (one per component)
  int pairCount = 0;
  std::vector<IntegerCombination> rows;  // over scalars 2·pair + {0, 1}
};

// Adds sign·R^rotation·y_pair to the two rows.
void addTerm(int n, const TranslationTerm& term, std::int64_t scale,
             std::array<std::map<int, std::int64_t>, 2>& rows) {
  const Eigen::Matrix2i r = term.sign * latticeRotation(n, term.rotation);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      if (r(i, j) != 0) rows[i][2 * term.pair + j] += scale * r(i, j);
}

void appendRows(std::array<std::map<int, std::int64_t>, 2>& rows,
                std::vector<IntegerCombination>& out) {
  for (auto& row : rows) {
    IntegerCombination combination;
    for (const auto& [variable, coefficient] : row)
      if (coefficient != 0) combination.emplace_back(variable, coefficient);
    if (!combination.empty()) out.push_back(std::move(combination));
  }
}

CutMesh buildCutMesh(const TriMesh& mesh, const CutGraph& cut) {
  const int n = cut.n;
  CutMesh cm;
  cm.halfedgeWedge.assign(mesh.n_halfedges(), -1);
  cm.edgePair.assign(mesh.n_edges(), -1);
  cm.vertexPair.assign(mesh.n_vertices(), -1);
  cm.realGauge.assign(mesh.n_vertices(), false);
  for (const auto eh : mesh.edges())
    if (cut.cutEdge[eh.idx()]) cm.edgePair[eh.idx()] = cm.pairCount++;

  // Walk the corners of each vertex in the order h -> opposite(next(h)) (clockwise), starting
  // right after a cut or boundary edge, and compose the transitions of eq. (2) across cut edges.
  for (const auto vh : mesh.vertices()) {
    if (mesh.is_isolated(vh)) continue;
    const bool boundary = mesh.is_boundary(vh);
    OpenMesh::HalfedgeHandle start;
    for (const auto h : mesh.vih_range(vh)) {
      if (mesh.is_boundary(h)) continue;
      const bool afterBoundary = mesh.is_boundary(mesh.opposite_halfedge_handle(h));
      const bool afterCut = cut.cutEdge[mesh.edge_handle(h).idx()];
      if (boundary ? afterBoundary : afterCut) {
        start = h;
        break;
      }
      if (!boundary && !start.is_valid()) start = h;
    }
    WedgeTransform current;
    const auto newWedge = [&] {
      cm.wedgeVertex.push_back(vh.idx());
      cm.wedgeTransform.push_back(current);
      return static_cast<int>(cm.wedgeVertex.size()) - 1;
    };
    int wedge = newWedge();
    OpenMesh::HalfedgeHandle h = start;
    while (true) {
      cm.halfedgeWedge[h.idx()] = wedge;
      const OpenMesh::HalfedgeHandle next = mesh.next_halfedge_handle(h);
      const OpenMesh::EdgeHandle eh = mesh.edge_handle(next);
      if (mesh.is_boundary(eh)) break;
      const OpenMesh::HalfedgeHandle across = mesh.opposite_halfedge_handle(next);
      if (cut.cutEdge[eh.idx()]) {
        const int r = cut.combedMatching[eh.idx()];
        const int pair = cm.edgePair[eh.idx()];
        if (mesh.halfedge_handle(eh, 0) == next) {  // z' = R^r z + t
          current.rotation = mod(current.rotation + r, n);
          for (auto& term : current.terms) term.rotation = mod(term.rotation + r, n);
          current.terms.push_back({pair, 0, 1});
        } else {  // z' = R^{-r} (z - t)
          current.rotation = mod(current.rotation - r, n);
          for (auto& term : current.terms) term.rotation = mod(term.rotation - r, n);
          current.terms.push_back({pair, mod(-r, n), -1});
        }
      }
      if (across == start) {
        // Closure: z = R^ρ z + Σ terms. ρ = 0: the terms must cancel; ρ ≠ 0: z is the fixed point.
        std::array<std::map<int, std::int64_t>, 2> rows;
        for (const auto& term : current.terms) addTerm(n, term, 1, rows);
        if (current.rotation != 0) {
          const int pair = cm.pairCount++;
          cm.vertexPair[vh.idx()] = pair;
          const Eigen::Matrix2i a =
              Eigen::Matrix2i::Identity() - latticeRotation(n, current.rotation);
          for (int i = 0; i < 2; ++i) {
            for (auto& entry : rows[i]) entry.second = -entry.second;
            for (int j = 0; j < 2; ++j) rows[i][2 * pair + j] += a(i, j);
          }
        }
        appendRows(rows, cm.rows);
        break;
      }
      if (cut.cutEdge[eh.idx()]) wedge = newWedge();
      h = across;
    }
  }

  // Gauge, one per component: a singular vertex at the origin (preferring holonomy ±1, whose
  // fixed point is a lattice point for any integer translations), else one vertex's master.
  std::vector<int> vertexComponent(mesh.n_vertices(), -1);
  for (const auto fh : mesh.faces())
    for (const auto vh : fh.vertices()) vertexComponent[vh.idx()] = cut.faceComponent[fh.idx()];
  const auto unitHolonomy = [&](int v) {
    return cut.vertexHolonomy[v] == 1 || cut.vertexHolonomy[v] == n - 1;
  };
  std::vector<int> gauge(cut.componentCount, -1);
  for (const auto& accept : {std::function<bool(int)>([&](int v) {
                               return cm.vertexPair[v] >= 0 && unitHolonomy(v);
                             }),
                             std::function<bool(int)>([&](int v) { return cm.vertexPair[v] >= 0; }),
                             std::function<bool(int)>([](int) { return true; })})
    for (int v = 0; v < static_cast<int>(mesh.n_vertices()); ++v) {
      const int c = vertexComponent[v];
      if (c >= 0 && gauge[c] < 0 && accept(v)) gauge[c] = v;
    }
  for (const int v : gauge) {
    if (cm.vertexPair[v] >= 0) {
      cm.rows.push_back({{2 * cm.vertexPair[v], 1}});
      cm.rows.push_back({{2 * cm.vertexPair[v] + 1, 1}});
    } else {
      cm.realGauge[v] = true;
    }
  }
  cm.faceWedges.resize(mesh.n_faces());
  for (const auto fh : mesh.faces()) {
    int c = 0;
    for (const auto h : mesh.fh_range(fh)) cm.faceWedges[fh.idx()][c++] = cm.halfedgeWedge[h.idx()];
  }
  return cm;
}

// Per-face geometry in the combed frame: gradients of the three corner hat functions.
struct FaceGeometry {
  std::vector<double> area;                          // #F
  std::vector<std::array<Eigen::Vector2d, 3>> grad;  // #F × corner (halfedge order from halfedge(f))
  std::vector<std::array<Eigen::Vector2d, 3>> local; // #F × corner positions in the combed frame
};

FaceGeometry computeFaceGeometry(const TriMesh& mesh, const RosyField& field, const CutGraph& cut) {
  const int nF = static_cast<int>(mesh.n_faces());
  FaceGeometry g;
  g.area.resize(nF);
  g.grad.resize(nF);
  g.local.resize(nF);
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    std::array<Eigen::Vector3d, 3> p;
    int i = 0;
    for (const auto h : mesh.fh_range(fh)) p[i++] = toEigen(mesh.point(mesh.to_vertex_handle(h)));
    const Eigen::Vector3d cross = (p[1] - p[0]).cross(p[2] - p[0]);
    const double doubleArea = cross.norm();
    g.area[f] = 0.5 * doubleArea;
    if (!(doubleArea > 0.0)) {
      for (auto& v : g.grad[f]) v.setZero();
      for (auto& v : g.local[f]) v.setZero();
      continue;
    }
    const Eigen::Vector3d normal = cross / doubleArea;
    Eigen::Vector3d d = field.faceDirection[f] - field.faceDirection[f].dot(normal) * normal;
    if (!(d.norm() > 1e-12)) d = p[1] - p[0];
    d.normalize();
    const double angle = 2.0 * M_PI * cut.faceRotation[f] / cut.n;
    const Eigen::Vector3d x = std::cos(angle) * d + std::sin(angle) * normal.cross(d);
    const Eigen::Vector3d y = normal.cross(x);
    for (int c = 0; c < 3; ++c) {
      // ∇φ_c = n × e_c / (2A), e_c the edge opposite corner c, counter-clockwise.
      const Eigen::Vector3d e = p[(c + 2) % 3] - p[(c + 1) % 3];
      const Eigen::Vector3d gradient = normal.cross(e) / doubleArea;
      g.grad[f][c] = {gradient.dot(x), gradient.dot(y)};
      g.local[f][c] = {(p[c] - p[0]).dot(x), (p[c] - p[0]).dot(y)};
    }
  }
  return g;
}

// Column layout of the solve: the Cartesian master coordinates (u, v) of every free vertex, then
// the free integer scalars (lattice units). Each wedge's Cartesian coordinates p_w = M z_w are
// two sparse rows over these columns: p_w = Rc^ρ p_master + M Σ S_k y_k with Rc the Cartesian
// rotation. Cartesian masters keep u and v uncoupled away from the cut (the Dirichlet energy is
// the same Laplacian for both), which keeps the Cholesky factor about 5 times sparser than
// lattice-coordinate masters coupled by the Gram matrix.
struct Unknowns {
  int realCount = 0;
  int integerCount = 0;
  int scalarCount = 0;            // integer scalars 2·pair + j (more free ones may be appended)
  std::vector<int> vertexColumn;  // #V, first of two real columns or -1
  IntegerElimination elimination;
  std::vector<int> freeColumn;    // #elimination variables, column of a free one or -1
  using Row = std::vector<std::pair<int, double>>;
  std::vector<std::array<Row, 2>> wedgeRows;

  int columns() const { return realCount + integerCount; }
};

Unknowns buildUnknowns(const TriMesh& mesh, const CutMesh& cm, int n) {
  Unknowns u;
  u.vertexColumn.assign(mesh.n_vertices(), -1);
  for (const auto vh : mesh.vertices()) {
    const int v = vh.idx();
    if (mesh.is_isolated(vh) || cm.vertexPair[v] >= 0 || cm.realGauge[v]) continue;
    u.vertexColumn[v] = u.realCount;
    u.realCount += 2;
  }
  const int scalars = 2 * cm.pairCount;
  std::vector<bool> preferred(scalars, false);
  for (const int pair : cm.vertexPair)
    if (pair >= 0) preferred[2 * pair] = preferred[2 * pair + 1] = true;
  u.elimination = eliminateIntegerConstraints(scalars, cm.rows, preferred);
  u.scalarCount = scalars;
  u.freeColumn.assign(u.elimination.expression.size(), -1);
  for (const int x : u.elimination.freeVariables) u.freeColumn[x] = u.realCount + u.integerCount++;

  u.wedgeRows.resize(cm.wedgeVertex.size());
  const Eigen::Matrix2d basis = latticeBasis(n);
  std::array<std::map<int, double>, 2> acc;
  // p_w += M · e_latticeRow · coefficient · (integer scalar as a combination of free ones).
  const auto addScalar = [&](int scalar, int latticeRow, double coefficient) {
    for (const auto& [variable, c] : u.elimination.expression[scalar])
      for (int k = 0; k < 2; ++k)
        if (basis(k, latticeRow) != 0.0)
          acc[k][u.freeColumn[variable]] +=
              basis(k, latticeRow) * coefficient * static_cast<double>(c);
  };
  for (std::size_t w = 0; w < cm.wedgeVertex.size(); ++w) {
    const int v = cm.wedgeVertex[w];
    const auto& transform = cm.wedgeTransform[w];
    acc[0].clear();
    acc[1].clear();
    const Eigen::Matrix2i r = latticeRotation(n, transform.rotation);
    if (cm.vertexPair[v] >= 0) {
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
          if (r(i, j) != 0) addScalar(2 * cm.vertexPair[v] + j, i, r(i, j));
    } else if (u.vertexColumn[v] >= 0) {
      const double angle = 2.0 * M_PI * transform.rotation / n;
      const auto clean = [](double x) { return std::abs(x) < 1e-12 ? 0.0 : x; };
      const double c = clean(std::cos(angle)), s = clean(std::sin(angle));
      const Eigen::Matrix2d rc = (Eigen::Matrix2d() << c, -s, s, c).finished();
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
          if (rc(i, j) != 0.0) acc[i][u.vertexColumn[v] + j] += rc(i, j);
    }
    for (const auto& term : transform.terms) {
      const Eigen::Matrix2i m = term.sign * latticeRotation(n, term.rotation);
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
          if (m(i, j) != 0) addScalar(2 * term.pair + j, i, m(i, j));
    }
    for (int i = 0; i < 2; ++i)
      for (const auto& [column, c] : acc[i])
        if (c != 0.0) u.wedgeRows[w][i].emplace_back(column, c);
  }
  return u;
}

// Groups of integer unknowns (counted from 0) that no face couples: those of each connected
// component of the cut graph (a pair's cut edge or singular vertex lies in one), ascending within
// a group; one group of all when an unknown spans two components. With several components the
// Schur complement is block diagonal and each block is solved on its own: 400 small spheres have
// 6400 integer unknowns, whose dense S would take O(k³) per solve.
std::vector<std::vector<int>> integerGroups(const TriMesh& mesh, const CutGraph& cut,
                                            const CutMesh& cm, const Unknowns& u) {
  std::vector<int> pairComponent(cm.pairCount, -1);
  for (const auto eh : mesh.edges())
    if (const int pair = cm.edgePair[eh.idx()]; pair >= 0)
      pairComponent[pair] =
          cut.faceComponent[(eh.h0().is_boundary() ? eh.h1() : eh.h0()).face().idx()];
  for (const auto vh : mesh.vertices())
    if (const int pair = cm.vertexPair[vh.idx()]; pair >= 0 && !mesh.is_isolated(vh))
      pairComponent[pair] = cut.faceComponent[vh.faces().begin()->idx()];
  std::vector<int> integerComponent(u.integerCount, -1);
  bool separable = cut.componentCount > 1;
  const int scalars = std::min<int>(2 * cm.pairCount, u.elimination.expression.size());
  for (int scalar = 0; scalar < scalars; ++scalar)
    for (const auto& term : u.elimination.expression[scalar]) {
      const int column = u.freeColumn[term.first];
      if (column < 0) continue;
      int& component = integerComponent[column - u.realCount];
      separable = separable && (component < 0 || component == pairComponent[scalar / 2]);
      component = pairComponent[scalar / 2];
    }
  std::vector<std::vector<int>> groups(separable ? cut.componentCount : 1);
  for (int j = 0; j < u.integerCount; ++j)
    groups[separable ? std::max(0, integerComponent[j]) : 0].push_back(j);
  std::erase_if(groups, [](const std::vector<int>& group) { return group.empty(); });
  return groups;
}

// Energy (4) as least squares: rows (∂u/∂x, ∂u/∂y, ∂v/∂x, ∂v/∂y) per face in the combed frame
// over the columns of Unknowns, with targets (σ_f, 0, 0, σ_f), σ_f = s_f / h; then two rows
// √λ·(∂v/∂x + ∂u/∂y, ∂v/∂y − ∂u/∂x) = √λ·(∇v − J∇u) with target 0: the anti-conformal part of
// the Jacobian. Energy (4) is |conformal part − σ·I|² + |anti-conformal part|²; the extra rows
// weigh anisotropy (1 + 2λ) times more than a change of scale or rotation, so what the integer
// constraints force on the map is taken up by angle-preserving changes where possible.
constexpr int kRowsPerFace = 6;
constexpr int kEnergyRows = 4;  // the rows of energy (4)

struct LeastSquares {
  SparseMatrix gradient;     // 6F (+ crease rows) × columns
  Eigen::VectorXd target;    // 6F (+ crease rows)
  Eigen::VectorXd faceArea;  // F (0 for degenerate faces, which are left out)
  Eigen::VectorXd rowWeight;  // per crease row (after the 6F face rows)
};

// Creases (the field's sharp edges). A crease edge u→w seen from one of its faces f, whose field
// follows the edge, runs along a lattice direction in f's chart; the lattice coordinate across
// it, ℓ·p (b along e1, a along e2, a + b along e2 − e1; p Cartesian), is then constant along
// the edge, and when it is an integer a lattice line (a row of remesh edges) lies on the crease
// (for N = 4 the directions are e1 and e2, and ℓ is b or a).
// Three rows per crease edge and face: ℓ·(p_w − p_u) = 0 (alignment) from the start; after the
// rounding, ℓ·p_u = t and ℓ·p_w = t with t the integer nearest to the edge's mean coordinate.
// Each edge takes its own nearest line: a crease that the lattice cannot follow exactly (a
// curved one, or one where the field turns) moves to the next line where it must, instead of
// straining the whole map.
struct CreaseEdge {
  int wedgeFrom = -1, wedgeTo = -1;
  int face = -1;           // the face it is seen from
  double length = 0.0;     // on the surface
  Eigen::Vector2d across;  // ℓ
  double weight = 0.0;     // of its rows: the crease weight times its length in lattice units
};

// Crease edges further than this from a lattice direction in their face's chart are left free.
constexpr double kCreaseAngleTolerance = 10.0 * M_PI / 180.0;
constexpr int kRowsPerCrease = 3;

// The crease edges of the field's sharp edges, each seen from both of its faces (weights 0 until
// setLatticeScale).
std::vector<CreaseEdge> findCreases(const TriMesh& mesh, const CutMesh& cm,
                                    const FaceGeometry& geometry, const RosyField& field,
                                    double weight) {
  std::vector<CreaseEdge> creases;
  if (field.sharpEdges.empty() || !(weight > 0.0)) return creases;
  const int n = field.n;
  const double step = 2.0 * M_PI / n;  // lattice directions: multiples of π/3 (N = 6), π/2
  const Eigen::Matrix2d toLattice = latticeBasis(n).inverse();  // Cartesian p ↦ (a, b)
  // The lattice coordinate across direction k: b along e1, a along e2, a + b along e2 − e1.
  const std::array<Eigen::Vector2d, 3> acrossInLattice{
      Eigen::Vector2d(0.0, 1.0), Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(1.0, 1.0)};
  for (const auto eh : mesh.edges()) {
    if (!field.sharpEdges[eh.idx()]) continue;
    for (const auto h : {eh.h0(), eh.h1()}) {
      const auto fh = h.face();
      const int f = fh.idx();
      if (!(geometry.area[f] > 0.0)) continue;
      int corner = 0, cTo = -1, cFrom = -1;
      for (const auto g : mesh.fh_range(fh)) {
        if (g == h) cTo = corner;
        if (g == h.prev()) cFrom = corner;
        ++corner;
      }
      const Eigen::Vector2d d = geometry.local[f][cTo] - geometry.local[f][cFrom];
      const double angle = std::atan2(d.y(), d.x());
      const int k = mod(static_cast<int>(std::lround(angle / step)), n / 2);
      if (std::abs(std::remainder(angle - k * step, M_PI)) > kCreaseAngleTolerance) continue;
      CreaseEdge crease;
      crease.wedgeFrom = cm.halfedgeWedge[h.prev().idx()];
      crease.wedgeTo = cm.halfedgeWedge[h.idx()];
      crease.face = f;
      crease.length = d.norm();
      crease.across = toLattice.transpose() * acrossInLattice[k];
      creases.push_back(crease);
    }
  }
  return creases;
}

// The rows of the creases after the face rows `faceRows`: their triplets (their weights in
// ls.rowWeight stay 0 until setLatticeScale and setCreaseTargets).
void addCreaseRows(const Unknowns& u, const std::vector<CreaseEdge>& creases, int faceRows,
                   std::vector<Triplet>& triplets, LeastSquares& ls) {
  ls.rowWeight = Eigen::VectorXd::Zero(kRowsPerCrease * static_cast<int>(creases.size()));
  for (std::size_t i = 0; i < creases.size(); ++i) {
    const auto& crease = creases[i];
    const int first = faceRows + kRowsPerCrease * static_cast<int>(i);
    const auto add = [&](int row, int wedge, double sign) {
      for (int coordinate = 0; coordinate < 2; ++coordinate)
        for (const auto& [column, value] : u.wedgeRows[wedge][coordinate])
          triplets.emplace_back(row, column, sign * crease.across[coordinate] * value);
    };
    add(first, crease.wedgeTo, 1.0);
    add(first, crease.wedgeFrom, -1.0);
    add(first + 1, crease.wedgeFrom, 1.0);
    add(first + 2, crease.wedgeTo, 1.0);
  }
}

// Cartesian coordinates of a wedge in the solution x.
Eigen::Vector2d wedgePosition(const Unknowns& u, int wedge, const Eigen::VectorXd& x) {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  for (int coordinate = 0; coordinate < 2; ++coordinate)
    for (const auto& [column, value] : u.wedgeRows[wedge][coordinate])
      p[coordinate] += value * x[column];
  return p;
}

// Puts every crease edge on its nearest lattice line in x: targets and weights of its line rows.
void setCreaseTargets(const Unknowns& u, const std::vector<CreaseEdge>& creases,
                      const Eigen::VectorXd& x, LeastSquares& ls) {
  const int faceRows =
      static_cast<int>(ls.target.size()) - kRowsPerCrease * static_cast<int>(creases.size());
  for (std::size_t i = 0; i < creases.size(); ++i) {
    const auto& crease = creases[i];
    const double mean = 0.5 * crease.across.dot(wedgePosition(u, crease.wedgeFrom, x) +
                                                 wedgePosition(u, crease.wedgeTo, x));
    const int first = faceRows + kRowsPerCrease * static_cast<int>(i);
    ls.target[first + 1] = ls.target[first + 2] = std::round(mean);
    ls.rowWeight[kRowsPerCrease * i + 1] = ls.rowWeight[kRowsPerCrease * i + 2] = crease.weight;
  }
}

// The rows of energy (4) and the anisotropy of every face (see above), then the crease rows;
// the targets and the crease weights, which depend on the lattice scale, are 0 until
// setLatticeScale. The matrix does not depend on the scale.
LeastSquares buildLeastSquares(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u,
                               const FaceGeometry& geometry, double conformalWeight,
                               const std::vector<CreaseEdge>& creases) {
  const int nF = static_cast<int>(mesh.n_faces());
  const int rows = kRowsPerFace * nF + kRowsPerCrease * static_cast<int>(creases.size());
  const double rootWeight = std::sqrt(conformalWeight);
  LeastSquares ls;
  ls.target = Eigen::VectorXd::Zero(rows);
  ls.faceArea = Eigen::VectorXd::Zero(nF);
  std::vector<Triplet> triplets;
  triplets.reserve(static_cast<std::size_t>(nF) * 72);
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    if (!(geometry.area[f] > 0.0)) continue;
    ls.faceArea[f] = geometry.area[f];
    const int row = kRowsPerFace * f;
    int c = 0;
    for (const auto h : mesh.fh_range(fh)) {
      const auto& rows = u.wedgeRows[cm.halfedgeWedge[h.idx()]];
      const Eigen::Vector2d& g = geometry.grad[f][c++];
      for (int coordinate = 0; coordinate < 2; ++coordinate)
        for (const auto& [column, value] : rows[coordinate])
          for (int axis = 0; axis < 2; ++axis)
            triplets.emplace_back(row + 2 * coordinate + axis, column, value * g[axis]);
      if (rootWeight == 0.0) continue;
      for (const auto& [column, value] : rows[0]) {  // u
        triplets.emplace_back(row + 4, column, rootWeight * value * g[1]);
        triplets.emplace_back(row + 5, column, -rootWeight * value * g[0]);
      }
      for (const auto& [column, value] : rows[1]) {  // v
        triplets.emplace_back(row + 4, column, rootWeight * value * g[0]);
        triplets.emplace_back(row + 5, column, rootWeight * value * g[1]);
      }
    }
  }
  addCreaseRows(u, creases, kRowsPerFace * nF, triplets, ls);
  ls.gradient.resize(rows, u.columns());
  ls.gradient.setFromTriplets(triplets.begin(), triplets.end());
  return ls;
}

// The targets (σ_f, 0, 0, σ_f) of energy (4), σ_f = faceScale[f] (lattice units per surface
// length), and the crease weights (their lengths in lattice units).
void setLatticeScale(const std::vector<double>& faceScale, double creaseWeight,
                     std::vector<CreaseEdge>& creases, LeastSquares& ls) {
  for (int f = 0; f < static_cast<int>(faceScale.size()); ++f)
    if (ls.faceArea[f] > 0.0)
      ls.target[kRowsPerFace * f] = ls.target[kRowsPerFace * f + 3] = faceScale[f];
  for (std::size_t i = 0; i < creases.size(); ++i) {
    CreaseEdge& crease = creases[i];
    crease.weight = creaseWeight * crease.length * faceScale[crease.face];
    ls.rowWeight[kRowsPerCrease * i] = crease.weight;
  }
}

// A sparse symmetric positive definite factorization that keeps its symbolic analysis across
// refactorizations with the same pattern (new face weights only change values).
class SpdSolver {
 public:
  explicit SpdSolver(LinearSolver kind) : kind_(kind) {
    useSingleThreadedBlas();
    cholmod_.cholmod().print = 0;  // failures are reported through info(), never on stdout
  }

  /// The symbolic analysis (fill-reducing order included) for matrices with the pattern of `a`;
  /// factorize() does it on its first call otherwise.
  void analyze(const SparseMatrix& a) {
    if (kind_ == LinearSolver::Cholmod) analyze(cholmod_, a);
    else analyze(ldlt_, a);
  }

  void factorize(const SparseMatrix& a) {
    update_.reset();
    if (kind_ == LinearSolver::Cholmod) run(cholmod_, a);
    else run(ldlt_, a);
  }

  /// Solves from now on with A + U diag(d) Uᵀ, A the last factorized matrix (see LowRankUpdate),
  /// until the next factorize(); false, and nothing changed, without a supernodal factor.
  bool updateLowRank(const SparseMatrix& u, const Eigen::VectorXd& d, int threads) {
    const cholmod_factor* factor = supernodalFactor();
    if (!factor) return false;
    update_.emplace(*factor, u, d, threads);
    return true;
  }

  /// CHOLMOD's supernodal factor of the last factorization (without a low-rank update), null
  /// with SimplicialLDLT.
  const cholmod_factor* supernodalFactor() const {
    const cholmod_factor* factor = kind_ == LinearSolver::Cholmod ? cholmod_.factor() : nullptr;
    return factor && factor->is_super ? factor : nullptr;
  }

  /// A⁻¹ b for one or several right-hand sides, with the last factorization (b itself when
  /// nothing was factorized: the 0×0 system); several on up to `threads` threads.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b, int threads = 1) const {
    if (b.rows() == 0 || b.cols() == 0) return b;
    const cholmod_factor* factor = supernodalFactor();
    Eigen::MatrixXd x = update_                          ? update_->solve(b, threads)
                        : factor && b.cols() > 1         ? supernodalSolve(*factor, b, threads)
                        : kind_ == LinearSolver::Cholmod ? Eigen::MatrixXd(cholmod_.solve(b))
                                                         : Eigen::MatrixXd(ldlt_.solve(b));
    if (!x.allFinite())
      throw Error(ErrorCode::NumericalFailure, "the parameterization solve produced non-finite values");
    return x;
  }

 private:
  template <typename Factorization>
  void analyze(Factorization& factorization, const SparseMatrix& a) {
    // CHOLMOD orders the graph of the vertices, whose u and v columns stay together.
    if constexpr (std::is_same_v<Factorization, CholmodSupernodalFactorization<SparseMatrix>>)
      factorization.analyzePattern(a, blockFillReducingOrder(a, 2));
    else
      factorization.analyzePattern(a);
    analyzed_ = true;
  }

  template <typename Factorization>
  void run(Factorization& factorization, const SparseMatrix& a) {
    if (!analyzed_) analyze(factorization, a);
    factorization.factorize(a);
    if (factorization.info() != Eigen::Success)
      throw Error(ErrorCode::NumericalFailure,
                  "the parameterization system could not be factorized (degenerate mesh or field)");
  }

  LinearSolver kind_;
  bool analyzed_ = false;
  Eigen::SimplicialLDLT<SparseMatrix> ldlt_;
  CholmodSupernodalFactorization<SparseMatrix> cholmod_;
  std::optional<LowRankUpdate> update_;  // of cholmod_'s factor
};

// The normal equations AᵀWA x = AᵀW f of the least squares with per-face weights, split into
// the real columns r (vertex coordinates, many) and the integer columns i (few):
//   [A_rr A_ri; A_ir A_ii] [x_r; x_i] = [b_r; b_i].
// A_rr is factorized once per set of weights; the integer unknowns are solved on the dense Schur
// complement S = A_ii − A_ir A_rr⁻¹ A_ri, c = b_i − A_ir A_rr⁻¹ b_r, so the local solve, every
// greedy rounding step and the final solve cost back-substitutions instead of factorizations.
// S is kept as its diagonal blocks over independent groups of integer unknowns (integerGroups:
// one per mesh component), the only nonzero ones.
class EnergySystem {
 public:
  EnergySystem(const LeastSquares& ls, int realCount, std::vector<std::vector<int>> integerGroups,
               LinearSolver kind, int threads)
      : ls_(ls),
        normal_(ls.gradient, rowGroups(ls)),
        realCount_(realCount),
        groups_(std::move(integerGroups)),
        threads_(threads),
        solver_(kind) {
    std::size_t integers = 0;  // the groups partition the integer unknowns
    for (const auto& group : groups_) integers += group.size();
    groupOf_.resize(integers);
    localIndex_.resize(integers);
    for (std::size_t g = 0; g < groups_.size(); ++g)
      for (std::size_t k = 0; k < groups_[g].size(); ++k) {
        groupOf_[groups_[g][k]] = static_cast<int>(g);
        localIndex_[groups_[g][k]] = static_cast<int>(k);
      }
  }

  /// The symbolic analysis of A_rr, which depends on the pattern only: it can run before the
  /// targets and weights are known (setFaceWeights does it otherwise).
  void analyze() {
    if (realCount_ > 0) solver_.analyze(realBlock(normal_.pattern()));
  }

  /// Assembles and factorizes the system for the face weights (#F, > 0); with
  /// `integersFree` also the Schur complement that solveIntegers needs. Without it, weights that
  /// differ from the factorized ones in a few rows, each raised (the crease rows of the final
  /// solve), update the factorization instead (see updateFactor).
  void setFaceWeights(const Eigen::VectorXd& faceWeight, bool integersFree) {
    const Eigen::VectorXd rowWeight = rowWeights(faceWeight);
    const Eigen::VectorXd b = ls_.gradient.transpose() * rowWeight.cwiseProduct(ls_.target);
    const int r = realCount_;
    responses_.resize(0, 0);  // solved for the previous weights
    solvedResponses_.clear();
    if (!integersFree && updateFactor(rowWeight)) {
      z_ = solver_.solve(b.head(r));
      return;
    }
    const SparseMatrix a = normal_.assemble(rowWeight, threads_);
    const int k = static_cast<int>(a.cols()) - realCount_;
    ari_ = a.topRightCorner(r, k);
    z_ = b.head(r);
    if (r > 0) {  // r = 0 when every vertex is singular (a minimal cube)
      solver_.factorize(realBlock(a));
      factorRowWeight_ = rowWeight;
      factorAri_ = ari_;
      z_ = solver_.solve(z_);
    }
    if (!integersFree) return;
    c_ = b.tail(k) - ari_.transpose() * z_;
    schur_.clear();
    const SparseMatrix aii = a.bottomRightCorner(k, k);
    for (const auto& group : groups_) schur_.push_back(denseBlock(aii, group));
    if (r == 0 || k == 0) return;
    const cholmod_factor* factor = solver_.supernodalFactor();
    // Without a supernodal factor the solved columns A_rr⁻¹ A_ri are kept when they fit in
    // kResponseBudget doubles (the rounding repair then reads its responses instead of solving
    // for them).
    constexpr int kBlock = 64;
    constexpr double kResponseBudget = 32e6;  // 256 MB
    const bool keep = !factor && static_cast<double>(r) * k <= kResponseBudget;
    if (keep) responses_.resize(r, k);
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      const SparseMatrix arig = columnsOf(ari_, groups_[g]);
      if (factor) {
        // A_ir A_rr⁻¹ A_ri = Wᵀ W with W = L⁻¹ P A_ri, sparse because A_ri is (the integer
        // unknowns touch only the vertices around cuts and singularities).
        schur_[g] -= supernodalInverseForm(*factor, arig, threads_);
        continue;
      }
      // Else by blocks of kBlock integer columns (bounded memory for large groups).
      const int width = static_cast<int>(groups_[g].size());
      for (int first = 0; first < width; first += kBlock) {
        const int count = std::min(kBlock, width - first);
        const Eigen::MatrixXd y = solver_.solve(Eigen::MatrixXd(arig.middleCols(first, count)));
        schur_[g].middleCols(first, count) -= arig.transpose() * y;
        if (keep)
          for (int q = 0; q < count; ++q) responses_.col(groups_[g][first + q]) = y.col(q);
      }
    }
  }

  /// Integer unknowns (#i) of the minimizer with x_i[j] = values[j] where fixed[j] (integer
  /// columns counted from 0).
  Eigen::VectorXd solveIntegers(const std::vector<bool>& fixed, const Eigen::VectorXd& values) const {
    Eigen::VectorXd x = values;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      const auto& group = groups_[g];
      const Eigen::MatrixXd& s = schur_[g];
      std::vector<int> free, held;  // indices into the group
      for (std::size_t j = 0; j < group.size(); ++j)
        (fixed[group[j]] ? held : free).push_back(static_cast<int>(j));
      if (free.empty()) continue;
      Eigen::MatrixXd sff(free.size(), free.size());
      Eigen::VectorXd rhs(free.size());
      for (std::size_t p = 0; p < free.size(); ++p) {
        rhs[p] = c_[group[free[p]]];
        for (const int h : held) rhs[p] -= s(free[p], h) * values[group[h]];
        for (std::size_t q = 0; q < free.size(); ++q) sff(p, q) = s(free[p], free[q]);
      }
      const Eigen::VectorXd xf = sff.ldlt().solve(rhs);
      if (!xf.allFinite())
        throw Error(ErrorCode::NumericalFailure, "the parameterization's integer system is singular");
      for (std::size_t p = 0; p < free.size(); ++p) x[group[free[p]]] = xf[p];
    }
    return x;
  }

  /// Lattice descent on the rounded integer unknowns xi (#i): moves one rounding unit (integer
  /// indices) to a neighbouring lattice point (for a pair: the 6 unit Eisenstein or 4 Gauss
  /// steps; for a scalar: ±1) while that lowers the energy with the reals minimized out,
  /// E(x_i) = x_iᵀ S x_i − 2 cᵀ x_i + const, whose change for a move d is 2 dᵀ(S x_i − c) + dᵀ S d.
  /// Returns the number of moves made.
  int descendIntegers(const std::vector<std::vector<int>>& units, int n, Eigen::VectorXd& xi) const {
    const std::vector<Eigen::Vector2d> pairMoves =
        n == 6 ? std::vector<Eigen::Vector2d>{{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}}
               : std::vector<Eigen::Vector2d>{{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    const std::vector<Eigen::Vector2d> scalarMoves = {{1, 0}, {-1, 0}};
    // gradient = S x_i − c, block by block.
    Eigen::VectorXd gradient(xi.size());
    double energy = 0.0;  // x_iᵀ S x_i
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      const Eigen::VectorXd xg = xi(groups_[g]);
      const Eigen::VectorXd sx = schur_[g] * xg;
      gradient(groups_[g]) = sx - c_(groups_[g]);
      energy += xg.dot(sx);
    }
    const double tolerance = 1e-12 * (1.0 + std::abs(energy));  // round-off guard
    int moves = 0;
    constexpr int kMaxPasses = 50;
    for (int pass = 0; pass < kMaxPasses; ++pass) {
      bool moved = false;
      for (const auto& unit : units) {
        double bestChange = -tolerance;
        const Eigen::Vector2d* best = nullptr;
        for (const auto& move : unit.size() == 2 ? pairMoves : scalarMoves) {
          double change = 0.0;
          for (std::size_t a = 0; a < unit.size(); ++a) {
            change += 2.0 * move[a] * gradient[unit[a]];
            for (std::size_t b = 0; b < unit.size(); ++b)
              change += move[a] * move[b] * schurEntry(unit[a], unit[b]);
          }
          if (change < bestChange) {
            bestChange = change;
            best = &move;
          }
        }
        if (!best) continue;
        for (std::size_t a = 0; a < unit.size(); ++a) {
          xi[unit[a]] += (*best)[a];
          const int g = groupOf_[unit[a]];
          gradient(groups_[g]) += (*best)[a] * schur_[g].col(localIndex_[unit[a]]);
        }
        ++moves;
        moved = true;
      }
      if (!moved) break;
    }
    return moves;
  }

  /// The whole minimizer for given integer unknowns: x_r = A_rr⁻¹ (b_r − A_ri x_i).
  Eigen::VectorXd withReals(const Eigen::VectorXd& integers) const {
    Eigen::VectorXd x(realCount_ + integers.size());
    if (integers.size() == 0) x.head(realCount_) = z_;
    else if (responses_.cols() == integers.size()) x.head(realCount_) = z_ - responses_ * integers;
    else x.head(realCount_) = z_ - solver_.solve(ari_ * integers);
    x.tail(integers.size()) = integers;
    return x;
  }

  /// For each integer column j = columns[k] (counted over all columns): the real unknowns' part
  /// of ∂x/∂x_j for the minimizer with every integer unknown fixed, −A_rr⁻¹ A_ri e_j (its
  /// integer part is e_j): changing x_j by δ moves the minimizer by δ times this. Read from the
  /// kept columns of A_rr⁻¹ A_ri, else solved with the last factorization. The solved columns
  /// are kept until the weights change, within kResponseCacheBudget doubles (those of this call
  /// always); the pointers stay valid until the next call.
  std::vector<const Eigen::VectorXd*> realResponses(const std::vector<int>& columns) {
    constexpr double kResponseCacheBudget = 8e6;  // 64 MB
    std::vector<int> unsolved;
    for (const int column : columns)
      if (!solvedResponses_.count(column) &&
          std::find(unsolved.begin(), unsolved.end(), column) == unsolved.end())
        unsolved.push_back(column);
    const auto doubles = [&](std::size_t count) { return static_cast<double>(count) * realCount_; };
    if (doubles(solvedResponses_.size() + unsolved.size()) > kResponseCacheBudget)
      for (auto it = solvedResponses_.begin(); it != solvedResponses_.end();)
        it = std::find(columns.begin(), columns.end(), it->first) == columns.end()
                 ? solvedResponses_.erase(it)
                 : std::next(it);
    if (!unsolved.empty()) {
      Eigen::MatrixXd y(realCount_, unsolved.size());
      if (responses_.cols() > 0) {
        for (std::size_t i = 0; i < unsolved.size(); ++i)
          y.col(i) = responses_.col(unsolved[i] - realCount_);
      } else {
        for (std::size_t i = 0; i < unsolved.size(); ++i)
          y.col(i) = ari_.col(unsolved[i] - realCount_);
        y = solver_.solve(y, threads_);
      }
      for (std::size_t i = 0; i < unsolved.size(); ++i) solvedResponses_[unsolved[i]] = -y.col(i);
    }
    std::vector<const Eigen::VectorXd*> result;
    for (const int column : columns) result.push_back(&solvedResponses_.at(column));
    return result;
  }

  /// Σ_f A_f |rows_f x − target_f|² (energy (4) plus the anisotropy rows, unit face weights)
  /// plus the crease rows at their weights.
  double energy(const Eigen::VectorXd& x) const {
    const Eigen::VectorXd residual = ls_.gradient * x - ls_.target;
    return rowWeights(Eigen::VectorXd::Ones(ls_.faceArea.size())).dot(residual.cwiseAbs2());
  }

 private:
  /// Takes the row weights `rowWeight` by a low-rank update of the last factorization when they
  /// differ from its weights in at most kMaxUpdatedRows rows, each raised: for the raises d of
  /// rows U of A (their real columns U_r, integer columns U_i), A_rr + U_rᵀ D U_r is solved by
  /// Sherman–Morrison–Woodbury (LowRankUpdate: two back-substitutions per solve instead of an
  /// assembly and a factorization; the final solve of the 1.1M-face bunny, whose 50 crease edges
  /// add 100 rows, takes 2.4 s instead of 6.0-6.8 s) and A_ri += U_rᵀ D U_i. False, and nothing
  /// changed, otherwise.
  bool updateFactor(const Eigen::VectorXd& rowWeight) {
    constexpr std::size_t kMaxUpdatedRows = 256;
    if (realCount_ == 0 || factorRowWeight_.size() != rowWeight.size()) return false;
    std::vector<int> changed;
    for (Eigen::Index row = 0; row < rowWeight.size(); ++row) {
      if (rowWeight[row] == factorRowWeight_[row]) continue;
      if (rowWeight[row] < factorRowWeight_[row] || changed.size() == kMaxUpdatedRows) return false;
      changed.push_back(static_cast<int>(row));
    }
    const auto& a = normal_.matrix();
    const int k = static_cast<int>(a.cols()) - realCount_;
    std::vector<Eigen::Triplet<double>> real, integer;
    Eigen::VectorXd d(static_cast<Eigen::Index>(changed.size()));
    for (std::size_t q = 0; q < changed.size(); ++q) {
      const int row = changed[q];
      d[static_cast<Eigen::Index>(q)] = rowWeight[row] - factorRowWeight_[row];
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(a, row); it; ++it)
        (it.col() < realCount_ ? real : integer)
            .emplace_back(it.col() < realCount_ ? it.col() : it.col() - realCount_, q, it.value());
    }
    SparseMatrix ur(realCount_, d.size()), ui(k, d.size());
    ur.setFromTriplets(real.begin(), real.end());
    ui.setFromTriplets(integer.begin(), integer.end());
    if (!solver_.updateLowRank(ur, d, threads_)) return false;
    ari_ = factorAri_ + SparseMatrix(ur * d.asDiagonal() * SparseMatrix(ui.transpose()));
    return true;
  }

  /// A_rr of the normal matrix `a`, with a relative 1e-14 on its diagonal (a pattern, of zeros,
  /// keeps its values).
  SparseMatrix realBlock(const SparseMatrix& a) const {
    SparseMatrix arr = a.topLeftCorner(realCount_, realCount_);
    const double regularization = 1e-14 * arr.diagonal().cwiseAbs().maxCoeff();
    for (int j = 0; j < realCount_; ++j) arr.coeffRef(j, j) += regularization;
    return arr;
  }

  Eigen::VectorXd rowWeights(const Eigen::VectorXd& faceWeight) const {
    Eigen::VectorXd w(ls_.target.size());
    for (Eigen::Index f = 0; f < ls_.faceArea.size(); ++f)
      w.segment<kRowsPerFace>(kRowsPerFace * f).setConstant(ls_.faceArea[f] * faceWeight[f]);
    w.tail(ls_.rowWeight.size()) = ls_.rowWeight;
    return w;
  }

  /// S_ab (integer unknowns a and b): 0 across groups.
  double schurEntry(int a, int b) const {
    const int g = groupOf_[a];
    return groupOf_[b] == g ? schur_[g](localIndex_[a], localIndex_[b]) : 0.0;
  }

  /// m restricted to the rows and columns `indices`, dense.
  static Eigen::MatrixXd denseBlock(const SparseMatrix& m, const std::vector<int>& indices) {
    std::vector<int> position(m.rows(), -1);
    for (std::size_t k = 0; k < indices.size(); ++k) position[indices[k]] = static_cast<int>(k);
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(indices.size(), indices.size());
    for (std::size_t k = 0; k < indices.size(); ++k)
      for (SparseMatrix::InnerIterator it(m, indices[k]); it; ++it)
        if (position[it.row()] >= 0) block(position[it.row()], k) = it.value();
    return block;
  }

  /// The columns `indices` of m, in that order.
  static SparseMatrix columnsOf(const SparseMatrix& m, const std::vector<int>& indices) {
    if (static_cast<Eigen::Index>(indices.size()) == m.cols() &&
        std::is_sorted(indices.begin(), indices.end()))
      return m;  // all of them
    SparseMatrix out(m.rows(), static_cast<Eigen::Index>(indices.size()));
    std::vector<Triplet> triplets;
    for (std::size_t k = 0; k < indices.size(); ++k)
      for (SparseMatrix::InnerIterator it(m, indices[k]); it; ++it)
        triplets.emplace_back(static_cast<int>(it.row()), static_cast<int>(k), it.value());
    out.setFromTriplets(triplets.begin(), triplets.end());
    return out;
  }

  /// The least squares' row groups for the normal equations: each face's rows, then each
  /// crease edge's.
  static std::vector<int> rowGroups(const LeastSquares& ls) {
    std::vector<int> start;
    const int faceRows = kRowsPerFace * static_cast<int>(ls.faceArea.size());
    for (int row = 0; row < faceRows; row += kRowsPerFace) start.push_back(row);
    for (int row = faceRows; row < ls.target.size(); row += kRowsPerCrease) start.push_back(row);
    if (start.empty()) start.push_back(0);
    return start;
  }

  const LeastSquares& ls_;
  NormalEquations normal_;  // AᵀWA for the face weights of each solve
  int realCount_;
  std::vector<std::vector<int>> groups_;  // independent groups of integer unknowns
  std::vector<int> groupOf_, localIndex_;  // per integer unknown: its group, its index there
  int threads_;  ///< of the assembly, the forward solve and the responses
  SpdSolver solver_;
  SparseMatrix ari_;       // A_ri
  Eigen::VectorXd factorRowWeight_;  // the row weights of the last factorization
  SparseMatrix factorAri_;           // and its A_ri
  Eigen::VectorXd z_;      // A_rr⁻¹ b_r
  std::vector<Eigen::MatrixXd> schur_;  // S's diagonal blocks, one per group
  Eigen::MatrixXd responses_;  // A_rr⁻¹ A_ri for the current weights (empty: not kept)
  std::map<int, Eigen::VectorXd> solvedResponses_;  // columns of realResponses for these weights
  Eigen::VectorXd c_;      // c
};

// Nearest lattice point of a 2D unknown in the Euclidean metric of the plane: the best corner
// of the lattice cell around it.
Eigen::Vector2d nearestLatticePoint(const Eigen::Vector2d& z, const Eigen::Matrix2d& basis) {
  Eigen::Vector2d best(std::round(z[0]), std::round(z[1]));
  double bestDistance = (basis * (best - z)).norm();
  for (int da = 0; da < 2; ++da)
    for (int db = 0; db < 2; ++db) {
      const Eigen::Vector2d candidate(std::floor(z[0]) + da, std::floor(z[1]) + db);
      const double distance = (basis * (candidate - z)).norm();
      if (distance < bestDistance) {
        best = candidate;
        bestDistance = distance;
      }
    }
  return best;
}

// Rounding units: both scalars of a pair when both are free (rounded to the nearest lattice
// point), else single scalars (rounded to the nearest integer).
std::vector<std::vector<int>> roundingUnits(const Unknowns& u) {
  std::vector<std::vector<int>> units;
  const auto& free = u.elimination.freeVariables;
  for (std::size_t i = 0; i < free.size(); ++i) {
    const int x = free[i];
    if (x % 2 == 0 && x + 1 < u.scalarCount && i + 1 < free.size() && free[i + 1] == x + 1) {
      units.push_back({u.freeColumn[x], u.freeColumn[x + 1]});
      ++i;
    } else {
      units.push_back({u.freeColumn[x]});
    }
  }
  return units;
}

// Rounds one unit in place and returns the Euclidean distance moved (in units of h).
double roundUnit(const std::vector<int>& unit, Eigen::VectorXd& x, const Eigen::Matrix2d& basis,
                 bool apply) {
  if (unit.size() == 2) {
    const Eigen::Vector2d z(x[unit[0]], x[unit[1]]);
    const Eigen::Vector2d rounded = nearestLatticePoint(z, basis);
    if (apply) x[unit[0]] = rounded[0], x[unit[1]] = rounded[1];
    return (basis * (rounded - z)).norm();
  }
  const double rounded = std::round(x[unit[0]]);
  const double distance = std::abs(rounded - x[unit[0]]);
  if (apply) x[unit[0]] = rounded;
  return distance;
}

// Exact corner coordinates: the masters' lattice coordinates M⁻¹(u, v) snapped to multiples of
// 2^-k, integer unknowns exact, every corner computed from them with the integer transforms, so
// that the transitions hold bit-exactly (|values| < 2^52 quanta).
struct SnappedCoordinates {
  int exponent = 0;                                // quantum 2^-exponent
  std::vector<std::array<std::int64_t, 2>> wedge;  // #wedges, in units of the quantum
};

// Per elimination variable: its free unknown in x rounded to an integer (0 for the others, which
// no expression uses).
std::vector<std::int64_t> roundedFreeUnknowns(const Unknowns& u, const Eigen::VectorXd& x) {
  std::vector<std::int64_t> rounded(u.freeColumn.size(), 0);
  for (std::size_t variable = 0; variable < rounded.size(); ++variable)
    if (u.freeColumn[variable] >= 0) rounded[variable] = std::llround(x[u.freeColumn[variable]]);
  return rounded;
}

// Value of integer scalar `scalar` (2·pair + j) from the rounded free unknowns.
std::int64_t integerValue(const Unknowns& u, const std::vector<std::int64_t>& rounded, int scalar) {
  std::int64_t value = 0;
  for (const auto& [variable, c] : u.elimination.expression[scalar]) value += c * rounded[variable];
  return value;
}

// llround(v), rounding half away from zero, for |v| < 2^52 without a library call: v − trunc(v)
// is exact there.
std::int64_t roundHalfAway(double v) {
  const auto t = static_cast<std::int64_t>(v);
  const double rest = v - static_cast<double>(t);
  return t + static_cast<std::int64_t>(rest >= 0.5) - static_cast<std::int64_t>(rest <= -0.5);
}

SnappedCoordinates snapCoordinates(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u,
                                   const Eigen::VectorXd& x, int n) {
  using Vector2l = Eigen::Matrix<std::int64_t, 2, 1>;
  const Eigen::Matrix2d toLattice = latticeBasis(n).inverse();
  // Vertices without columns (isolated, deleted, paired or the gauge) stay at 0.
  std::vector<Eigen::Vector2d> master(mesh.n_vertices(), Eigen::Vector2d::Zero());
  Eigen::Vector2d largestMaster(1.0, 1.0);
  for (std::size_t v = 0; v < master.size(); ++v) {
    const int column = u.vertexColumn[v];
    if (column < 0) continue;
    master[v] = toLattice * x.segment<2>(column);
    largestMaster = largestMaster.cwiseMax(master[v].cwiseAbs());
  }
  double largest = largestMaster.maxCoeff();
  const std::vector<std::int64_t> rounded = roundedFreeUnknowns(u, x);
  std::vector<std::int64_t> pairValue(2 * cm.pairCount);
  for (int scalar = 0; scalar < 2 * cm.pairCount; ++scalar) {
    pairValue[scalar] = integerValue(u, rounded, scalar);
    largest = std::max(largest, std::abs(static_cast<double>(pairValue[scalar])));
  }
  SnappedCoordinates s;
  s.exponent = std::min(30, 48 - static_cast<int>(std::ceil(std::log2(largest))));
  const double scale = std::ldexp(1.0, s.exponent);
  for (auto& value : pairValue) value *= std::int64_t{1} << s.exponent;
  // The master coordinates in quanta (|value| ≤ 2^48): a vertex's own position, or its lattice
  // point when it has a pair.
  std::vector<Vector2l> snappedMaster(mesh.n_vertices(), Vector2l::Zero());
  for (std::size_t v = 0; v < snappedMaster.size(); ++v) {
    if (cm.vertexPair[v] >= 0)
      snappedMaster[v] = {pairValue[2 * cm.vertexPair[v]], pairValue[2 * cm.vertexPair[v] + 1]};
    else if (u.vertexColumn[v] >= 0)
      snappedMaster[v] = {roundHalfAway(master[v].x() * scale), roundHalfAway(master[v].y() * scale)};
  }
  using Rotation = Eigen::Matrix<std::int64_t, 2, 2>;
  std::vector<Rotation> rotation(n);  // R^k, k = 0 … n − 1 (the transforms' range)
  for (int k = 0; k < n; ++k) rotation[k] = latticeRotation(n, k).cast<std::int64_t>();
  s.wedge.resize(cm.wedgeVertex.size());
  for (std::size_t w = 0; w < cm.wedgeVertex.size(); ++w) {
    const auto& transform = cm.wedgeTransform[w];
    const Vector2l& m = snappedMaster[cm.wedgeVertex[w]];
    Vector2l z = transform.rotation == 0 ? m : Vector2l(rotation[transform.rotation] * m);
    for (const auto& term : transform.terms) {
      const Vector2l y(pairValue[2 * term.pair], pairValue[2 * term.pair + 1]);
      z += term.sign * (rotation[term.rotation] * y);
    }
    s.wedge[w] = {z.x(), z.y()};
  }
  return s;
}

struct Orientation {
  int flipped = 0;
  int degenerate = 0;
};

/// Fewer flipped triangles, or as many and fewer degenerate ones.
bool fewerFaults(const Orientation& a, const Orientation& b) {
  return a.flipped != b.flipped ? a.flipped < b.flipped : a.degenerate < b.degenerate;
}

Orientation countOrientation(const TriMesh& mesh, const CutMesh& cm, const SnappedCoordinates& s,
                             std::vector<bool>* flippedFaces = nullptr,
                             std::vector<bool>* degenerateFaces = nullptr) {
  Orientation o;
  if (flippedFaces) flippedFaces->assign(mesh.n_faces(), false);
  if (degenerateFaces) degenerateFaces->assign(mesh.n_faces(), false);
  for (std::size_t f = 0; f < cm.faceWedges.size(); ++f) {
    const auto& [z0, z1, z2] = cm.faceWedges[f];
    const auto &a = s.wedge[z0], &b = s.wedge[z1], &c = s.wedge[z2];
    const __int128 ax = b[0] - a[0], ay = b[1] - a[1];
    const __int128 bx = c[0] - a[0], by = c[1] - a[1];
    const __int128 det = ax * by - ay * bx;  // same sign in lattice and Cartesian coordinates
    if (det == 0) {
      ++o.degenerate;
      if (degenerateFaces) (*degenerateFaces)[f] = true;
    }
    if (det < 0) {
      ++o.flipped;
      if (flippedFaces) (*flippedFaces)[f] = true;
    }
  }
  return o;
}

// Rounding repair: fold-overs and degenerate triangles that stiffening cannot remove come from
// the rounding (typically two singularities rounded onto the same lattice point, or next to each
// other). For the integer unknowns that the corners of flipped or degenerate triangles depend
// on, try moving each to a neighbouring lattice point (its effect on the minimizer is linear: one
// back-substitution per unknown with the last factorization) and keep a move when it leaves fewer
// flipped triangles, or as many and fewer degenerate ones. At most four passes over at most 32
// units each; the trial moves are judged on up to `threads` threads, with the same result.
void repairRounding(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u, EnergySystem& system,
                    int n, int threads, Eigen::VectorXd& x, SnappedCoordinates& snapped,
                    Orientation& orientation, std::vector<bool>& flippedFaces) {
  const auto units = roundingUnits(u);
  std::map<int, int> unitOfColumn;
  for (std::size_t i = 0; i < units.size(); ++i)
    for (const int column : units[i]) unitOfColumn[column] = static_cast<int>(i);
  std::vector<bool> degenerateFaces;  // kept up to date with flippedFaces below
  countOrientation(mesh, cm, snapped, nullptr, &degenerateFaces);
  for (int pass = 0; pass < 4 && (orientation.flipped > 0 || orientation.degenerate > 0);
       ++pass) {
    std::set<int> involved;
    for (std::size_t f = 0; f < cm.faceWedges.size(); ++f) {
      if (!flippedFaces[f] && !degenerateFaces[f]) continue;
      for (const int wedge : cm.faceWedges[f])
        for (const auto& row : u.wedgeRows[wedge])
          for (const auto& [column, c] : row)
            if (const auto it = unitOfColumn.find(column); it != unitOfColumn.end())
              involved.insert(it->second);
      if (involved.size() >= 32) break;
    }
    if (involved.empty()) return;  // the faulty corners do not depend on an integer unknown
    // The units in order, each unit's moves in order: the first move that leaves fewer faults is
    // kept. The moves of kUnitWindow units are judged at once, in parallel, from the current x;
    // after a kept move judging goes on from the next unit, so the result is that of judging them
    // one by one.
    constexpr std::size_t kUnitWindow = 4;
    const std::vector<int> order(involved.begin(), involved.end());
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
      const auto candidateOf = [&](const Trial& trial) {
        const auto& unit = units[order[trial.position]];
        Eigen::VectorXd candidate = x;
        for (std::size_t k = 0; k < unit.size(); ++k) {
          candidate.head(realCount) += trial.move[k] * *responses[trial.firstResponse + k];
          candidate[unit[k]] += trial.move[k];
        }
        for (const int column : unit) candidate[column] = std::round(candidate[column]);
        return candidate;
      };
      std::vector<Orientation> outcome(trials.size());
      parallelFor(
          trials.size(), threads,
          [&](std::size_t k) {
            outcome[k] =
                countOrientation(mesh, cm, snapCoordinates(mesh, cm, u, candidateOf(trials[k]), n));
          },
          1);
      const auto better = std::find_if(outcome.begin(), outcome.end(), [&](const Orientation& o) {
        return fewerFaults(o, orientation);
      });
      if (better == outcome.end()) {
        nextUnit = end;
        continue;
      }
      const Trial& trial = trials[static_cast<std::size_t>(better - outcome.begin())];
      x = candidateOf(trial);
      snapped = snapCoordinates(mesh, cm, u, x, n);
      orientation = countOrientation(mesh, cm, snapped, &flippedFaces, &degenerateFaces);
      improved = true;
      if (orientation.flipped == 0 && orientation.degenerate == 0) return;
      nextUnit = trial.position + 1;
    }
    if (!improved) return;
  }
}

// Local fold-over relaxation: re-solves only the real unknowns of the vertices within `rings`
// edge rings of a flipped triangle (everything else held), with the faces there stiffened as in
// the global loop (weight 1 + min(5·relative misfit, 20), doubled at flipped triangles), a few
// times per region; the region doubles while triangles stay flipped. A small sparse solve per
// step instead of a refactorization of the whole system. Keeps a step only when it leaves fewer
// flipped triangles and no more degenerate ones; returns the number of local solves.
int relaxFoldsLocally(const TriMesh& mesh, const CutMesh& cm, const Unknowns& u,
                      const LeastSquares& ls, const std::vector<double>& faceScale, int n,
                      Eigen::VectorXd& x, SnappedCoordinates& snapped, Orientation& orientation,
                      std::vector<bool>& flippedFaces) {
  constexpr int kSolvesPerRegion = 4;
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
    std::vector<int> faces;  // faces whose rows involve a region column
    for (const auto fh : mesh.faces()) {
      bool touches = false;
      for (const auto vh : fh.vertices()) touches = touches || depth[vh.idx()] >= 0;
      if (touches && ls.faceArea[fh.idx()] > 0.0) faces.push_back(fh.idx());
    }
    if (columns.empty()) continue;
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

double angleAt(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d u = b - a, v = c - a;
  return std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u.dot(v));
}

}  // namespace

void ParamOptions::validate() const {
  const auto fail = [](const std::string& message) {
    throw Error(ErrorCode::InvalidOption, message);
  };
  if (!std::isfinite(edgeLength) || edgeLength < 0.0)
    fail("edge length must be a positive finite number (or 0 for automatic)");
  if (targetVertices < 0) fail("target vertex count must be positive (or 0 for automatic)");
  for (const double s : vertexSizing)
    if (!std::isfinite(s) || s <= 0.0) fail("vertex sizing values must be positive and finite");
  if (!(greedyBatchFraction > 0.0 && greedyBatchFraction <= 1.0))
    fail("greedy batch fraction must be in (0, 1]");
  if (maxStiffeningIterations < 0) fail("stiffening iterations must be ≥ 0");
  if (!(std::isfinite(conformalWeight) && conformalWeight >= 0.0))
    fail("conformal weight must be a finite number ≥ 0");
  if (!(std::isfinite(creaseWeight) && creaseWeight >= 0.0))
    fail("crease weight must be a finite number ≥ 0");
  if (threads < 1) fail("threads must be at least 1, got " + std::to_string(threads));
}

FieldOptions parameterizationFieldOptions(int n, double edgeLength, double singularityDistance,
                                          double featureAngle) {
  FieldOptions options;
  options.n = n;
  options.maxMergedIndex = kMergedIndexForLattice;
  options.singularityDistance = singularityDistance;
  options.sharpEdgeAngle = featureAngle;
  options.sharpLineLength = kCreaseLineInEdges * edgeLength;
  return options;
}

double edgeLengthForVertexCount(const TriMesh& mesh, int targetVertices, int n,
                                const std::vector<double>& vertexSizing) {
  if (targetVertices < 1)
    throw Error(ErrorCode::InvalidOption, "target vertex count must be at least 1");
  double sizedArea = 0.0;
  for (const auto fh : mesh.faces()) {
    double s = vertexSizing.empty() ? 1.0 : 0.0;
    if (!vertexSizing.empty())
      for (const auto vh : fh.vertices()) s += vertexSizing[vh.idx()] / 3.0;
    sizedArea += mesh.calc_face_area(fh) * s * s;
  }
  // Per vertex: two lattice triangles (N = 6) or one lattice square (N = 4) of area c·h².
  const double areaPerVertexOverH2 = 2.0 * latticeTriangleArea(n);
  return std::sqrt(sizedArea / (areaPerVertexOverH2 * targetVertices));
}

std::vector<double> smoothSizing(const TriMesh& mesh, const std::vector<double>& sizing,
                                 double radius) {
  const int nV = static_cast<int>(mesh.n_vertices());
  if (static_cast<int>(sizing.size()) != nV)
    throw Error(ErrorCode::InvalidOption, "sizing has " + std::to_string(sizing.size()) +
                                              " values for " + std::to_string(nV) + " vertices");
  for (const double s : sizing)
    if (!(std::isfinite(s) && s > 0.0)) throw Error(ErrorCode::InvalidOption, "sizing values must be positive and finite");
  double edgeSum = 0.0;
  for (const auto eh : mesh.edges()) edgeSum += mesh.calc_edge_length(eh);
  if (nV == 0 || mesh.n_edges() == 0 || !(radius > 0.0)) return sizing;
  const double meanEdge = edgeSum / static_cast<double>(mesh.n_edges());
  const double weight = (radius / meanEdge) * (radius / meanEdge);
  std::vector<Triplet> triplets;
  Eigen::VectorXd logSizing(nV);
  for (int v = 0; v < nV; ++v) {
    triplets.emplace_back(v, v, 1.0);
    logSizing[v] = std::log(sizing[v]);
  }
  for (const auto eh : mesh.edges()) {
    const int a = eh.v0().idx(), b = eh.v1().idx();
    triplets.emplace_back(a, a, weight);
    triplets.emplace_back(b, b, weight);
    triplets.emplace_back(a, b, -weight);
    triplets.emplace_back(b, a, -weight);
  }
  SparseMatrix system(nV, nV);
  system.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SimplicialLDLT<SparseMatrix> solver(system);
  const Eigen::VectorXd smoothed = solver.solve(logSizing);
  std::vector<double> out(nV);
  for (int v = 0; v < nV; ++v) out[v] = std::isfinite(smoothed[v]) ? std::exp(smoothed[v]) : sizing[v];
  return out;
}

std::vector<double> curvatureSizing(const std::vector<double>& absMaxCurvature, double minScale,
                                    double maxScale) {
  if (absMaxCurvature.empty()) throw Error(ErrorCode::InvalidOption, "no curvature values given");
  if (!(minScale > 0.0 && minScale <= maxScale))
    throw Error(ErrorCode::InvalidOption, "sizing range must satisfy 0 < min ≤ max");
  std::vector<double> sorted;
  for (const double k : absMaxCurvature)
    if (std::isfinite(k)) sorted.push_back(std::abs(k));
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  std::vector<double> sizing(absMaxCurvature.size(), 1.0);
  if (!(median > 0.0)) return sizing;
  for (std::size_t v = 0; v < sizing.size(); ++v) {
    const double k = std::isfinite(absMaxCurvature[v]) ? std::abs(absMaxCurvature[v]) : median;
    sizing[v] = std::clamp(k / median, minScale, maxScale);
  }
  return sizing;
}

Parameterization computeParameterization(const TriMesh& mesh, const RosyField& field,
                                         const ParamOptions& options, const RunContext& context) {
  options.validate();
  if (mesh.n_faces() == 0) throw Error(ErrorCode::InvalidMesh, "the mesh has no faces to parameterize");
  if (!options.vertexSizing.empty() && options.vertexSizing.size() != mesh.n_vertices())
    throw Error(ErrorCode::InvalidOption,
                "vertex sizing has " + std::to_string(options.vertexSizing.size()) +
                    " values for " + std::to_string(mesh.n_vertices()) + " vertices");
  const int n = field.n;
  Parameterization result;
  result.n = n;

  // The conformal scale (a solve on the whole mesh) runs on a second thread while the cut graph,
  // the unknowns, the least squares' matrix and the symbolic analysis of its normal equations,
  // none of which depends on the lattice scale, are built on this one.
  context.report("parameterization", 0.0);
  std::vector<double> conformal;
  Timings sideTimings;
  CutGraph cut;
  CutMesh cm;
  Unknowns unknowns;
  LeastSquares ls;
  FaceGeometry geometry;
  std::vector<CreaseEdge> creases;
  std::optional<EnergySystem> energySystem;
  runBoth(
      options.threads,
      [&] {
        {
          ScopedTimer timer(result.timings, "cut graph");
          cut = computeCutGraph(mesh, field);
          cm = buildCutMesh(mesh, cut);
        }
        context.throwIfCanceled();
        {
          ScopedTimer timer(result.timings, "integer constraints");
          unknowns = buildUnknowns(mesh, cm, n);
        }
        context.throwIfCanceled();
        ScopedTimer timer(result.timings, "assembly");
        geometry = computeFaceGeometry(mesh, field, cut);
        creases = findCreases(mesh, cm, geometry, field, options.creaseWeight);
        ls = buildLeastSquares(mesh, cm, unknowns, geometry, options.conformalWeight, creases);
        energySystem.emplace(ls, unknowns.realCount, integerGroups(mesh, cut, cm, unknowns),
                             options.solver, options.threads);
        energySystem->analyze();
      },
      [&] {
        if (!options.conformalScale) return;
        ScopedTimer timer(sideTimings, "conformal scale");
        conformal = conformalFaceScale(mesh, field);
      });
  result.timings.insert(result.timings.end(), sideTimings.begin(), sideTimings.end());
  EnergySystem& system = *energySystem;
  result.integerVariables = unknowns.integerCount;
  context.throwIfCanceled();

  int usedVertices = 0;
  for (const auto vh : mesh.vertices()) usedVertices += mesh.is_isolated(vh) ? 0 : 1;
  result.edgeLength = options.edgeLength;
  if (!(result.edgeLength > 0.0)) {
    // From the vertex count; the conformal scale varies the lattice unit around h, so h is
    // corrected to keep the count.
    result.edgeLength = edgeLengthForVertexCount(
        mesh, options.targetVertices > 0 ? options.targetVertices : std::max(4, usedVertices / 4),
        isLatticeOrder(n) ? n : 6, options.vertexSizing);
    if (!conformal.empty()) result.edgeLength *= std::sqrt(conformalVertexCountFactor(mesh, conformal));
  }
  std::vector<double> faceScale(mesh.n_faces(), 1.0 / result.edgeLength);
  if (!options.vertexSizing.empty())
    for (const auto fh : mesh.faces()) {
      double s = 0.0;
      for (const auto vh : fh.vertices()) s += options.vertexSizing[vh.idx()] / 3.0;
      faceScale[fh.idx()] = s / result.edgeLength;
    }
  for (std::size_t f = 0; f < conformal.size(); ++f) faceScale[f] *= conformal[f];
  setLatticeScale(faceScale, options.creaseWeight, creases, ls);
  context.report("parameterization", 0.2);

  const int columns = unknowns.columns();
  const int realCount = unknowns.realCount;
  Eigen::VectorXd faceWeight = Eigen::VectorXd::Ones(mesh.n_faces());
  Eigen::VectorXd x;
  {
    ScopedTimer timer(result.timings, "local solve");
    system.setFaceWeights(faceWeight, true);
    x = system.withReals(system.solveIntegers(std::vector<bool>(columns - realCount, false),
                                              Eigen::VectorXd::Zero(columns - realCount)));
  }
  result.localEnergy = system.energy(x);
  context.throwIfCanceled();
  context.report("parameterization", 0.4);

  const Eigen::Matrix2d basis = latticeBasis(n);
  {
    ScopedTimer timer(result.timings, "rounding");
    auto units = roundingUnits(unknowns);
    if (options.rounding == RoundingMethod::Direct) {
      for (const auto& unit : units) roundUnit(unit, x, basis, true);
    } else {
      // Greedy: round the units closest to the lattice, re-solve the rest on the Schur
      // complement (the real unknowns follow at the final solve).
      std::vector<bool> fixed(columns - realCount, false);
      while (!units.empty()) {
        std::vector<std::pair<double, std::size_t>> order;
        for (std::size_t i = 0; i < units.size(); ++i)
          order.emplace_back(roundUnit(units[i], x, basis, false), i);
        std::sort(order.begin(), order.end());
        const std::size_t count = std::max<std::size_t>(
            1, static_cast<std::size_t>(std::ceil(options.greedyBatchFraction * units.size())));
        std::vector<bool> taken(units.size(), false);
        for (std::size_t k = 0; k < count; ++k) {
          const auto& unit = units[order[k].second];
          roundUnit(unit, x, basis, true);
          for (const int column : unit) fixed[column - realCount] = true;
          taken[order[k].second] = true;
        }
        std::vector<std::vector<int>> remaining;
        for (std::size_t i = 0; i < units.size(); ++i)
          if (!taken[i]) remaining.push_back(std::move(units[i]));
        units = std::move(remaining);
        if (!units.empty())
          x.tail(columns - realCount) = system.solveIntegers(fixed, x.tail(columns - realCount));
        context.throwIfCanceled();
      }
    }
    std::vector<std::vector<int>> integerUnits = roundingUnits(unknowns);
    for (auto& unit : integerUnits)
      for (int& column : unit) column -= realCount;
    Eigen::VectorXd integers = x.tail(columns - realCount);
    if (options.latticeDescent)
      result.latticeDescentMoves = system.descendIntegers(integerUnits, n, integers);
    x.tail(columns - realCount) = integers;
  }
  {
    ScopedTimer timer(result.timings, "final solve");
    x = system.withReals(x.tail(columns - realCount));
    if (!creases.empty()) {
      setCreaseTargets(unknowns, creases, x, ls);
      system.setFaceWeights(faceWeight, false);  // the integers are fixed from here on
      x = system.withReals(x.tail(columns - realCount));
    }
  }
  context.report("parameterization", 0.7);

  // Fold-overs: stiffen distorted triangles (weight += min(5·relative misfit, 20), doubled around
  // flipped ones) and re-solve.
  SnappedCoordinates snapped = snapCoordinates(mesh, cm, unknowns, x, n);
  std::vector<bool> flippedFaces;
  Orientation orientation = countOrientation(mesh, cm, snapped, &flippedFaces);
  result.flippedBeforeStiffening = orientation.flipped;
  // Fold-overs, cheapest remedy first. Local relaxation (before and after a rounding repair) is
  // kept only when it removes every fold-over; otherwise the global stiffening below starts from
  // the rounding-repaired plain solution (a partial local change can lead it to a worse optimum).
  if (orientation.flipped > 0) {
    struct Iterate {
      Eigen::VectorXd x;
      SnappedCoordinates snapped;
      Orientation orientation;
      std::vector<bool> flippedFaces;
    };
    const auto relax = [&](Iterate& it) {
      ScopedTimer timer(result.timings, "local relaxation");
      result.localRelaxations += relaxFoldsLocally(mesh, cm, unknowns, ls, faceScale, n, it.x,
                                                   it.snapped, it.orientation, it.flippedFaces);
    };
    const auto repair = [&](Iterate& it) {
      ScopedTimer timer(result.timings, "rounding repair");
      repairRounding(mesh, cm, unknowns, system, n, options.threads, it.x, it.snapped,
                     it.orientation, it.flippedFaces);
    };
    const Iterate plain{x, snapped, orientation, flippedFaces};
    Iterate chosen = plain;  // relax, then repair and relax again
    relax(chosen);
    if (chosen.orientation.flipped > 0) {
      // Relaxation keeps only steps with fewer flipped triangles: one that kept none left
      // `plain`, and the order below (repair, then relax) would redo the same steps.
      const bool relaxedNothing = chosen.orientation.flipped == plain.orientation.flipped;
      repair(chosen);
      const Iterate repairedPlain = relaxedNothing ? chosen : Iterate{};
      if (chosen.orientation.flipped > 0) relax(chosen);
      if (chosen.orientation.flipped > 0 && relaxedNothing) {
        chosen = repairedPlain;
      } else if (chosen.orientation.flipped > 0) {  // repair, then relax
        Iterate repaired = plain;
        repair(repaired);
        chosen = repaired;
        if (repaired.orientation.flipped > 0) relax(chosen);
        if (chosen.orientation.flipped > 0) chosen = std::move(repaired);
      }
    }
    x = std::move(chosen.x);
    snapped = std::move(chosen.snapped);
    orientation = chosen.orientation;
    flippedFaces = std::move(chosen.flippedFaces);
  }
  // Degenerate triangles (zero area, no fold-over) come from the rounding: a rounding move first.
  if (orientation.flipped == 0 && orientation.degenerate > 0) {
    ScopedTimer timer(result.timings, "rounding repair");
    repairRounding(mesh, cm, unknowns, system, n, options.threads, x, snapped, orientation,
                   flippedFaces);
  }
  {
    ScopedTimer timer(result.timings, "stiffening");
    // Stop after 3 re-solves without fewer flipped triangles: what remains is not a stiffness issue.
    // Each re-solve is followed by a rounding repair (timed with the stiffening). A later re-solve
    // can fold a triangle that an earlier one had unfolded, so the best iterate (fewest flipped,
    // then fewest degenerate triangles; the later one on ties) is the result.
    int best = orientation.flipped + orientation.degenerate, sinceBest = 0;
    Eigen::VectorXd bestX = x;
    SnappedCoordinates bestSnapped = snapped;
    Orientation bestOrientation = orientation;
    while ((orientation.flipped > 0 || orientation.degenerate > 0) &&
           result.stiffeningIterations < options.maxStiffeningIterations && sinceBest < 3) {
      context.throwIfCanceled();
      const Eigen::VectorXd residual = ls.gradient * x - ls.target;
      for (int f = 0; f < static_cast<int>(mesh.n_faces()); ++f) {
        const double misfit = residual.segment<kEnergyRows>(kRowsPerFace * f).squaredNorm() /
                              (2.0 * faceScale[f] * faceScale[f]);
        faceWeight[f] += std::min(5.0 * misfit, 20.0);
      }
      // Flipped triangles and the triangles around their corners are stiffened twofold.
      std::vector<bool> stiffen(mesh.n_faces(), false);
      for (const auto fh : mesh.faces())
        if (flippedFaces[fh.idx()])
          for (const auto vh : fh.vertices())
            for (const auto gh : vh.faces()) stiffen[gh.idx()] = true;
      for (int f = 0; f < static_cast<int>(mesh.n_faces()); ++f)
        if (stiffen[f]) faceWeight[f] *= 2.0;
      system.setFaceWeights(faceWeight, false);
      x = system.withReals(x.tail(columns - realCount));
      ++result.stiffeningIterations;
      snapped = snapCoordinates(mesh, cm, unknowns, x, n);
      orientation = countOrientation(mesh, cm, snapped, &flippedFaces);
      // Stiffening moves the real unknowns; a rounding move may now remove what is left.
      if (orientation.flipped > 0 || orientation.degenerate > 0)
        repairRounding(mesh, cm, unknowns, system, n, options.threads, x, snapped, orientation,
                       flippedFaces);
      const int remaining = orientation.flipped + orientation.degenerate;
      sinceBest = remaining < best ? 0 : sinceBest + 1;
      best = std::min(best, remaining);
      if (!fewerFaults(bestOrientation, orientation)) {
        bestX = x;
        bestSnapped = snapped;
        bestOrientation = orientation;
      }
    }
    x = std::move(bestX);
    snapped = std::move(bestSnapped);
    orientation = bestOrientation;
  }
  result.flippedTriangles = orientation.flipped;
  result.degenerateTriangles = orientation.degenerate;
  result.energy = system.energy(x);

  // Result arrays.
  ScopedTimer timer(result.timings, "output");
  const double quantum = std::ldexp(1.0, -snapped.exponent);
  result.cornerCoords.assign(mesh.n_halfedges(), Eigen::Vector2d::Zero());
  for (const auto h : mesh.halfedges()) {
    const int w = cm.halfedgeWedge[h.idx()];
    if (w < 0) continue;
    result.cornerCoords[h.idx()] = {static_cast<double>(snapped.wedge[w][0]) * quantum,
                                    static_cast<double>(snapped.wedge[w][1]) * quantum};
  }
  result.edgeTransition.assign(mesh.n_edges(), EdgeTransition{});
  result.cutEdge = cut.cutEdge;
  result.faceRotation = cut.faceRotation;
  result.cutLength = cut.cutLength;
  const std::vector<std::int64_t> rounded = roundedFreeUnknowns(unknowns, x);
  for (const auto eh : mesh.edges()) {
    const int pair = cm.edgePair[eh.idx()];
    if (pair < 0) continue;
    auto& transition = result.edgeTransition[eh.idx()];
    transition.rotation = cut.combedMatching[eh.idx()];
    for (int j = 0; j < 2; ++j)
      transition.translation[j] = static_cast<int>(integerValue(unknowns, rounded, 2 * pair + j));
  }
  for (const auto& s : field.singularities) {
    ParamSingularity ps;
    ps.coords.setZero();
    ps.vertex = s.vertex;
    ps.index = s.index;
    for (const auto h : mesh.vih_range(mesh.vertex_handle(s.vertex)))
      if (!mesh.is_boundary(h)) {
        ps.coords = result.cornerCoords[h.idx()];
        break;
      }
    result.singularities.push_back(ps);
  }

  // Distortion: corner angles and log area ratio of parameter (scaled by h/s) vs surface triangles.
  double angleSum = 0.0, areaSum = 0.0;
  int angleCount = 0, areaCount = 0;
  for (const auto fh : mesh.faces()) {
    const int f = fh.idx();
    if (!(geometry.area[f] > 0.0)) continue;
    std::array<Eigen::Vector2d, 3> p;
    int c = 0;
    for (const auto h : mesh.fh_range(fh)) p[c++] = basis * result.cornerCoords[h.idx()];
    const auto& q = geometry.local[f];
    for (int k = 0; k < 3; ++k) {
      const double difference =
          std::abs(angleAt(p[k], p[(k + 1) % 3], p[(k + 2) % 3]) -
                   angleAt(q[k], q[(k + 1) % 3], q[(k + 2) % 3])) * 180.0 / M_PI;
      angleSum += difference;
      result.distortion.angleMax = std::max(result.distortion.angleMax, difference);
      ++angleCount;
    }
    const Eigen::Vector2d a = p[1] - p[0], b = p[2] - p[0];
    const double parameterArea = 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    if (parameterArea > 0.0) {
      const double ratio = parameterArea / (faceScale[f] * faceScale[f] * geometry.area[f]);
      const double logRatio = std::abs(std::log(ratio));
      areaSum += logRatio;
      result.distortion.areaMax = std::max(result.distortion.areaMax, logRatio);
      ++areaCount;
    }
  }
  result.distortion.angleMean = angleCount > 0 ? angleSum / angleCount : 0.0;
  result.distortion.areaMean = areaCount > 0 ? areaSum / areaCount : 0.0;
  context.report("parameterization", 1.0);
  return result;
}

}  // namespace hexcover
