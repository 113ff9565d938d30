# Native dependencies of individual stages (Debian 12 packages; see docs/DEPENDENCIES.md).
# Each stage adds its own lines with small edits.

# core/geometry (closest_point.h, used by extract and metrics): Embree 3 BVH point queries for
# exact point-to-triangle distances.
find_package(embree 3.13 REQUIRED)
target_link_libraries(hexcover_geometry PUBLIC embree)

# core/common (sparse_cholesky.h, used by field and param): SuiteSparse CHOLMOD (supernodal, on
# OpenBLAS) behind Eigen's CholmodSupport.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
target_include_directories(hexcover_common PUBLIC ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(hexcover_common PUBLIC ${CHOLMOD_LIBRARY})
