#include "core/param/cut_mesh.h"

#include <cmath>
#include <functional>
#include <map>

#include "core/param/lattice.h"

namespace hexcover::param_detail {
namespace {

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

}  // namespace

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
          current.rotation = wrapIndex(current.rotation + r, n);
          for (auto& term : current.terms) term.rotation = wrapIndex(term.rotation + r, n);
          current.terms.push_back({pair, 0, 1});
        } else {  // z' = R^{-r} (z - t)
          current.rotation = wrapIndex(current.rotation - r, n);
          for (auto& term : current.terms) term.rotation = wrapIndex(term.rotation - r, n);
          current.terms.push_back({pair, wrapIndex(-r, n), -1});
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
  for (const auto& accept :
       {std::function<bool(int)>([&](int v) { return cm.vertexPair[v] >= 0 && unitHolonomy(v); }),
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

Eigen::Vector2d wedgePosition(const Unknowns& u, int wedge, const Eigen::VectorXd& x) {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  for (int coordinate = 0; coordinate < 2; ++coordinate)
    for (const auto& [column, value] : u.wedgeRows[wedge][coordinate])
      p[coordinate] += value * x[column];
  return p;
}

std::int64_t integerValue(const Unknowns& u, const std::vector<std::int64_t>& rounded, int scalar) {
  std::int64_t value = 0;
  for (const auto& [variable, c] : u.elimination.expression[scalar]) value += c * rounded[variable];
  return value;
}

}  // namespace hexcover::param_detail
