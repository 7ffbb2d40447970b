// The threads under flexure's sparse Cholesky factorizations: CHOLMOD's OpenMP teams and the
// BLAS beneath CHOLMOD's supernodes.
#pragma once

#include <mutex>

namespace flexure::optimize {

// flexure's CHOLMOD factorizations and solves (the calls that reach the BLAS), and its METIS
// orderings (METIS keeps its random generator's state in globals: GKlib's random.c), are made
// under one of these. While it is alive:
// - No other thread of the process is in such a section (a process-wide lock; nested sections
//   of one thread are fine). The BLAS that install-deps selects, OpenBLAS's serial build
//   (libopenblas0-serial, 0.3.21), takes no lock in its buffer allocation: two threads calling
//   dgemm on 16 × 16 matrices at once got a wrong product in 68 709 of 600 000 calls, and the
//   convergence study's parallel cases got results that changed with --threads (111 of 300
//   concurrent supernodal solves in the test LinearAlgebraThreads differed). OpenBLAS's pthreads
//   build is thread-safe but starts a worker thread when it is loaded, which allocates a 128 MiB
//   buffer and, when that fails (a process under ulimit -v), loops and keeps the process from
//   exiting. The factorizations are the smaller share of a study's cases; their element
//   evaluations still run in parallel.
// - CHOLMOD's OpenMP regions are inactive (OpenMP's max-active-levels = 0, a per-thread
//   setting); the caller's setting is restored after. Debian's CHOLMOD runs parts of its
//   supernodal factorization in teams of CHOLMOD_OMP_NUM_THREADS = 4 threads (fixed when it was
//   built), which on flexure's 2-core machines spin and wait on futexes for more time than they
//   save: with OMP_THREAD_LIMIT=1 the drape benchmark (scripts/bench simulate, hinge, 961
//   vertices) ran 1.3–1.4× faster. (An earlier version bounded the teams by omp_set_dynamic(1):
//   libgomp then asks the kernel for the processor count and load average at every parallel
//   region — 130 000 such pairs of system calls in 28 steps of the 10 000-vertex drape.)
// - A threaded OpenBLAS, where one is the BLAS, is set to one thread, for good: its threads would
//   compete with flexure's own, and change the order of its sums with their count (the 10 000-
//   vertex drape's final energy differed in the 12th digit between 1 and 2 OpenBLAS threads).
// The OpenMP and OpenBLAS functions are looked up at run time: without an OpenMP runtime (a
// CHOLMOD built without it) or without OpenBLAS (another BLAS) there is nothing of theirs to set.
class SingleThreadedLinearAlgebra {
 public:
  SingleThreadedLinearAlgebra();
  ~SingleThreadedLinearAlgebra();
  SingleThreadedLinearAlgebra(const SingleThreadedLinearAlgebra&) = delete;
  SingleThreadedLinearAlgebra& operator=(const SingleThreadedLinearAlgebra&) = delete;

 private:
  std::unique_lock<std::recursive_mutex> lock_;
  int levels_ = 1;
};

}  // namespace flexure::optimize
