#pragma once
// The BLAS under CHOLMOD (Debian's OpenBLAS, pthread build: safe for concurrent callers) and
// CHOLMOD's own OpenMP loops run single-threaded: the worker pool already runs one job per core,
// idle OpenMP threads spinning next to the other worker cost more than they give (measured), and
// a fixed thread count keeps the factorizations bit-identical from run to run.
//
// A program that links this file also runs every OpenMP parallel region of GCC's runtime
// (libgomp's GOMP_parallel, the only region entry point CHOLMOD 3 calls) as a plain call on the
// calling thread. CHOLMOD's supernodal factorization opens two regions per supernode even with
// one thread, and libgomp then sets up a team and wakes its barrier (a futex system call) for
// each: 171,000 regions in one remesh of the Stanford bunny, about 0.1 s of its 2 s (measured).
// Inside a region so called, omp_get_num_threads() is 1 and omp_get_thread_num() 0, as in an
// inactive region: the results are the same to the last bit.

namespace hexcover {

/// Sets OpenBLAS to one thread and makes every OpenMP parallel region inactive (one thread), once
/// per process. Does nothing for a library that is not loaded.
void useSingleThreadedBlas();

}  // namespace hexcover
