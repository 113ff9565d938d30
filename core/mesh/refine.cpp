#include "core/mesh/refine.h"

#include <cmath>
#include <functional>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include "core/common/error.h"

namespace hexcover {

long long splitLongEdges(TriMesh& mesh, double maxLength, std::size_t maxFaces) {
  if (!(std::isfinite(maxLength) && maxLength > 0.0))
    throw Error(
        ErrorCode::InvalidOption,
        "the longest edge to keep must be finite and positive, got " + std::to_string(maxLength));
  // (length, edge): the longest first, then the lower index.
  using Entry = std::pair<double, int>;
  const auto longerFirst = [](const Entry& a, const Entry& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(longerFirst)> queue(longerFirst);
  const auto push = [&](OpenMesh::EdgeHandle e) {
    const double length = mesh.calc_edge_length(e);
    if (length > maxLength) queue.emplace(length, e.idx());
  };
  for (const auto e : mesh.edges()) push(e);
  long long splits = 0;
  while (!queue.empty() && mesh.n_faces() + 2 <= maxFaces) {
    const auto [length, index] = queue.top();
    queue.pop();
    const OpenMesh::EdgeHandle e(index);
    // A split shortens the edge it reuses: entries of an older length are stale.
    if (mesh.calc_edge_length(e) != length) continue;
    const auto h = mesh.halfedge_handle(e, 0);
    const TriMesh::Point midpoint =
        0.5 * (mesh.point(mesh.from_vertex_handle(h)) + mesh.point(mesh.to_vertex_handle(h)));
    const auto v = mesh.split_copy(e, midpoint);
    for (const auto out : mesh.voh_range(v)) push(mesh.edge_handle(out));
    ++splits;
  }
  return splits;
}

}  // namespace hexcover
