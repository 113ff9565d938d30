#include "core/common/blas_threads.h"

// Weak: resolved when OpenBLAS and an OpenMP runtime (through CHOLMOD) are loaded, null otherwise.
extern "C" void openblas_set_num_threads(int threads) __attribute__((weak));
extern "C" void omp_set_max_active_levels(int levels) __attribute__((weak));

/// libgomp's entry point of a parallel region (GCC's `#pragma omp parallel`), defined by the
/// program and so found before libgomp's: the region's body runs once, on this thread, without
/// a team (see blas_threads.h).
extern "C" void GOMP_parallel(void (*body)(void*), void* data, unsigned /*threads*/,
                              unsigned /*flags*/) {
  body(data);
}

namespace hexcover {

void useSingleThreadedBlas() {
  static const bool done = [] {  // thread-safe one-time initialization
    if (openblas_set_num_threads) openblas_set_num_threads(1);
    // No active parallel region in an OpenMP entry point other than GOMP_parallel above:
    // CHOLMOD asks for a fixed 4 threads, which a thread count does not override.
    if (omp_set_max_active_levels) omp_set_max_active_levels(0);
    return true;
  }();
  static_cast<void>(done);
}

}  // namespace hexcover
