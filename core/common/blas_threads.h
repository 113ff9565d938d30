#pragma once
// The BLAS under CHOLMOD (Debian's OpenBLAS, pthread build: safe for concurrent callers) runs
// single-threaded: the worker pool already runs one job per core, and a fixed thread count keeps
// the factorizations bit-identical from run to run.

namespace hexcover {

/// Sets OpenBLAS to one thread, once per process; does nothing with another BLAS.
void useSingleThreadedBlas();

}  // namespace hexcover
