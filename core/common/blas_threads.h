#pragma once
// The BLAS under CHOLMOD (Debian's OpenBLAS, pthread build: safe for concurrent callers) and
// CHOLMOD's own OpenMP loops run single-threaded: the worker pool already runs one job per core,
// idle OpenMP threads spinning next to the other worker cost more than they give (measured), and
// a fixed thread count keeps the factorizations bit-identical from run to run.

namespace hexcover {

/// Sets OpenBLAS to one thread and makes every OpenMP parallel region inactive (one thread), once
/// per process. Does nothing for a library that is not loaded.
void useSingleThreadedBlas();

}  // namespace hexcover
