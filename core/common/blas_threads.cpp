#include "core/common/blas_threads.h"

// Weak: resolved when OpenBLAS is the loaded BLAS, null otherwise.
extern "C" void openblas_set_num_threads(int threads) __attribute__((weak));

namespace hexcover {

void useSingleThreadedBlas() {
  static const bool done = [] {  // thread-safe one-time initialization
    if (openblas_set_num_threads) openblas_set_num_threads(1);
    return true;
  }();
  static_cast<void>(done);
}

}  // namespace hexcover
