# Native dependencies of individual stages (Debian 12 packages; see docs/DEPENDENCIES.md).
# Each stage adds its own lines with small edits.

# core/metrics: Embree 3 BVH point queries for exact point-to-triangle distances.
find_package(embree 3.13 REQUIRED)
target_link_libraries(hexcover_metrics PUBLIC embree)
