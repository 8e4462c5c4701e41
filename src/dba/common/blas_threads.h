// The threads of the BLAS under CHOLMOD (the sparse solver, the two-level
// preconditioner's coarse factorization).
//
// Debian's OpenBLAS (libopenblas0-pthread) starts one thread per core when
// the library loads, and an idle one spins in sched_yield for 2^28 cycles
// (about 0.1 s) at start-up and after every multithreaded BLAS call before
// it sleeps. On a 2-core machine that takes a core from dba's own threads:
// problem-73-11032 from plain text took 0.22 s instead of 0.19 s (2
// threads, alternating, medians of 9). But the sparse RCS factorization
// needs BLAS's threads: on a 2,500-image survey with one BLAS thread it took
// 12.0 s instead of 7.7 s. So dba runs BLAS on one thread, except inside a
// BlasThreads scope, which stops the pool when it ends.
//
// Everything looks OpenBLAS up at run time (the BLAS behind CHOLMOD is
// chosen by Debian's alternatives, and loads with CHOLMOD, after the
// program's start) and does nothing under another BLAS or none.
// Thread safety: while no other thread uses BLAS.
#pragma once

#include <string>

#include "dba/common/shared_library.h"

namespace dba {

// For a program's start: the program owns the BLAS: one BLAS thread, and
// the pool's threads joined (blas_thread_shutdown_), now if the BLAS is
// loaded and again when OpenLibraryWithBlas loads it. Not for a library: it
// would take the host program's (numpy's) BLAS threads too.
void StopBlasThreads();

// Opens a library that brings the BLAS (CHOLMOD), its symbols global so that
// the functions here find OpenBLAS. In a program that owns the BLAS
// (StopBlasThreads), under a limit on the address space OpenBLAS loads with
// OPENBLAS_NUM_THREADS=1 (its pool would map a buffer per thread at load
// and, refused one, retry forever), and its threads are stopped after.
SharedLibrary OpenLibraryWithBlas(const std::string& soname, const std::string& purpose);

// Under a limit on the address space (RLIMIT_AS) OpenBLAS, refused a
// buffer, retries forever, and a thread maps its buffer when BLAS first runs
// on it, inside the factorization, after CHOLMOD has mapped what it needs:
// no check can see that moment. So under a limit BLAS runs on the calling
// thread alone (1), whose buffer is mapped here, while the room is known to
// hold it and what CHOLMOD maps first; std::runtime_error when it does not
// (the sparse factorization would hang). Without a limit, `num_threads`.
int BlasThreadsThatFit(int num_threads);

// `num_threads` BLAS threads for the scope (BlasThreadsThatFit's count);
// after it, the count it found,
// and after a multithreaded scope (not one that only lowered the count) the
// pool's threads joined (a later multithreaded call starts them again). A
// one-thread scope where one thread is set changes nothing.
class BlasThreads {
 public:
  explicit BlasThreads(int num_threads);
  ~BlasThreads();
  BlasThreads(const BlasThreads&) = delete;
  BlasThreads& operator=(const BlasThreads&) = delete;

 private:
  int previous_ = 0;  // 0: no OpenBLAS, or nothing changed
  bool raised_ = false;  // a multithreaded scope: shut the pool down after
};

}  // namespace dba
