#include "core/field/connection.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/common/concurrency.h"
#include "core/common/error.h"

namespace hexcover::field {

std::vector<double> filterGaussCurvature(const TriMesh& mesh, const FieldGeometry& geometry,
                                         int steps, int threads) {
  const int nv = static_cast<int>(mesh.n_vertices());
  // The vertices are stored in breadth-first order (slot[v]), so that a vertex's neighbours
  // sit close together in memory: the steps run through the arrays instead of jumping around.
  std::vector<int> slot(nv, -1), vertexAt;
  vertexAt.reserve(nv);
  for (int seed = 0; seed < nv; ++seed) {
    if (slot[seed] >= 0) continue;
    slot[seed] = static_cast<int>(vertexAt.size());
    vertexAt.push_back(seed);
    for (std::size_t head = vertexAt.size() - 1; head < vertexAt.size(); ++head)
      for (const auto w : mesh.vv_range(OpenMesh::VertexHandle(vertexAt[head])))
        if (slot[w.idx()] < 0) {
          slot[w.idx()] = static_cast<int>(vertexAt.size());
          vertexAt.push_back(w.idx());
        }
  }
  std::vector<double> k(nv, 0.0), next(nv, 0.0);
  for (const auto vh : mesh.vertices())
    if (!mesh.is_boundary(vh) && !mesh.is_isolated(vh))
      k[slot[vh.idx()]] = geometry.angleDefect[vh.idx()];
  // The links (edges between interior vertices) of each vertex, in edge order: each vertex sums
  // its neighbours' shares in the same order for any thread count.
  std::vector<int> first(nv + 1, 0);
  const auto isLink = [&](const auto eh) {
    return !mesh.is_boundary(eh.v0()) && !mesh.is_boundary(eh.v1());
  };
  for (const auto eh : mesh.edges())
    if (isLink(eh)) ++first[slot[eh.v0().idx()] + 1], ++first[slot[eh.v1().idx()] + 1];
  std::partial_sum(first.begin(), first.end(), first.begin());
  std::vector<int> neighbour(first[nv]);
  std::vector<int> filled(first.begin(), first.end() - 1);
  for (const auto eh : mesh.edges())
    if (isLink(eh)) {
      const int a = slot[eh.v0().idx()], b = slot[eh.v1().idx()];
      neighbour[filled[a]++] = b;
      neighbour[filled[b]++] = a;
    }
  const auto degree = [&](int v) { return first[v + 1] - first[v]; };
  // share_v = K_v / (2 deg v), what v gives each neighbour per step.
  const auto shareOf = [&](int v, double kv) {
    return degree(v) > 0 ? 0.5 * kv / degree(v) : 0.0;
  };
  std::vector<double> share(nv), nextShare(nv);
  for (int v = 0; v < nv; ++v) share[v] = shareOf(v, k[v]);
  for (int step = 0; step < steps; ++step) {
    parallelFor(static_cast<std::size_t>(nv), threads, [&](std::size_t i) {
      const int v = static_cast<int>(i);
      double kv = degree(v) > 0 ? 0.5 * k[v] : k[v];
      for (int j = first[v]; j < first[v + 1]; ++j) kv += share[neighbour[j]];
      next[v] = kv;
      nextShare[v] = shareOf(v, kv);
    });
    k.swap(next);
    share.swap(nextShare);
  }
  std::vector<double> filtered(nv);
  for (int v = 0; v < nv; ++v) filtered[v] = k[slot[v]];
  return filtered;
}

int filterSteps(const TriMesh& mesh, double radius) {
  if (!(radius > 0.0) || mesh.n_edges() == 0) return 0;
  double total = 0.0;
  for (const auto eh : mesh.edges()) total += mesh.calc_edge_length(eh);
  const double mean = total / static_cast<double>(mesh.n_edges());
  if (!(mean > 0.0)) return 0;
  const double ratio = radius / mean;
  return static_cast<int>(std::min(400.0, std::ceil(2.0 * ratio * ratio)));
}

std::vector<int> vertexGraphOrder(const TriMesh& mesh) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(mesh.n_edges());
  for (const auto eh : mesh.edges()) edges.emplace_back(eh.v0().idx(), eh.v1().idx());
  return minimumDegreeOrder(static_cast<int>(mesh.n_vertices()), edges);
}

std::vector<bool> interiorVertices(const TriMesh& mesh) {
  std::vector<bool> interior(mesh.n_vertices(), false);
  for (const auto vh : mesh.vertices())
    interior[vh.idx()] = !mesh.is_boundary(vh) && !mesh.is_isolated(vh);
  return interior;
}

std::vector<bool> interiorEdges(const TriMesh& mesh) {
  std::vector<bool> interior(mesh.n_edges(), false);
  for (const auto eh : mesh.edges()) interior[eh.idx()] = !mesh.is_boundary(eh);
  return interior;
}

ConnectionCorrector::ConnectionCorrector(const TriMesh& mesh, const FieldGeometry& geometry,
                                         const std::vector<bool>& constrained,
                                         const std::vector<bool>& freeEdges,
                                         const std::vector<int>& vertexOrder)
    : mesh_(mesh), geometry_(geometry), freeEdge_(freeEdges), row_(mesh.n_vertices(), -1) {
  const int nv = static_cast<int>(mesh.n_vertices());
  const auto isConstrained = [&](int v) {
    return constrained[v] && !mesh.is_boundary(mesh.vertex_handle(v));
  };
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::vector<bool> anchored(nv, false);
  for (const auto eh : mesh.edges()) {
    if (!freeEdge_[eh.idx()] || mesh.is_boundary(eh)) continue;
    const int a = eh.v0().idx(), b = eh.v1().idx();
    if (isConstrained(a) && isConstrained(b)) {
      const int ra = root(a), rb = root(b);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    } else if (isConstrained(a)) {
      anchored[a] = true;
    } else if (isConstrained(b)) {
      anchored[b] = true;
    }
  }
  std::vector<bool> groupAnchored(nv, false);
  for (int v = 0; v < nv; ++v)
    if (isConstrained(v) && anchored[v]) groupAnchored[root(v)] = true;
  // Rows numbered along vertexOrder (by vertex index without one); a floating group pins its
  // lowest vertex (its root).
  int rows = 0;
  for (int k = 0; k < nv; ++k) {
    const int v = vertexOrder.empty() ? k : vertexOrder[k];
    if (isConstrained(v) && (groupAnchored[root(v)] || v != root(v))) row_[v] = rows++;
  }
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(rows + mesh.n_edges());
  std::vector<double> diagonal(rows, 0.0);
  for (const auto eh : mesh.edges()) {
    if (!freeEdge_[eh.idx()] || mesh.is_boundary(eh)) continue;
    const int a = row_[eh.v0().idx()], b = row_[eh.v1().idx()];
    if (a >= 0) diagonal[a] += 1.0;
    if (b >= 0) diagonal[b] += 1.0;
    if (a >= 0 && b >= 0) triplets.emplace_back(std::max(a, b), std::min(a, b), -1.0);  // lower
  }
  for (int r = 0; r < rows; ++r) triplets.emplace_back(r, r, diagonal[r]);
  Eigen::SparseMatrix<double> laplacian(rows, rows);
  laplacian.setFromTriplets(triplets.begin(), triplets.end());
  if (!solver_.compute(laplacian, vertexOrder.empty() ? RowOrder::Reorder : RowOrder::AsGiven))
    throw Error(ErrorCode::NumericalFailure,
                "field: the connection system could not be factorized (is the mesh valid?)");
}

std::vector<double> ConnectionCorrector::holonomy(const std::vector<double>& c) const {
  std::vector<double> h = geometry_.angleDefect;
  if (c.empty()) return h;
  for (const auto eh : mesh_.edges()) {
    if (mesh_.is_boundary(eh)) continue;
    h[eh.h0().to().idx()] += c[eh.idx()];  // s = +1 at to(h0), −1 at to(h1)
    h[eh.h1().to().idx()] -= c[eh.idx()];
  }
  return h;
}

std::vector<double> ConnectionCorrector::corrections(const std::vector<double>& target,
                                                     const std::vector<double>& base) const {
  const int rows = static_cast<int>(solver_.rows());
  const std::vector<double> current = holonomy(base);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(rows);
  for (int v = 0; v < static_cast<int>(row_.size()); ++v)
    if (row_[v] >= 0) rhs[row_[v]] = target[v] - current[v];
  const Eigen::VectorXd lambda = solver_.solve(rhs);
  std::vector<double> c = base.empty() ? std::vector<double>(mesh_.n_edges(), 0.0) : base;
  for (const auto eh : mesh_.edges()) {
    if (!freeEdge_[eh.idx()] || mesh_.is_boundary(eh)) continue;
    // Δ = Aᵀλ with A[to(h0), e] = +1, A[to(h1), e] = −1.
    const int a = row_[eh.h0().to().idx()], b = row_[eh.h1().to().idx()];
    c[eh.idx()] += (a >= 0 ? lambda[a] : 0.0) - (b >= 0 ? lambda[b] : 0.0);
  }
  return c;
}

}  // namespace hexcover::field
