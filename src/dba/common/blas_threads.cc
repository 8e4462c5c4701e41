// The BLAS's threads; see blas_threads.h.
#include "dba/common/blas_threads.h"

#include <dlfcn.h>

namespace dba {
namespace {

struct OpenBlas {
  void (*set_threads)(int) = nullptr;
  int (*get_threads)() = nullptr;
  int (*shutdown)() = nullptr;
  OpenBlas() {
    set_threads = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    get_threads = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    shutdown = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "blas_thread_shutdown_"));
  }
  bool loaded() const { return set_threads && get_threads && shutdown; }
};

const OpenBlas& Blas() {
  static const OpenBlas blas;
  return blas;
}

}  // namespace

void StopBlasThreads() {
  if (!Blas().loaded()) return;
  Blas().set_threads(1);
  Blas().shutdown();
}

BlasThreads::BlasThreads(int num_threads) {
  if (!Blas().loaded()) return;
  const int current = Blas().get_threads();
  // One thread where one is set: nothing to change, restore or shut down. (A
  // restore that shut the pool down took about a millisecond, which a coarse
  // solve of the two-level preconditioner paid per PCG iteration: 5x its own
  // time.)
  if (current == num_threads && num_threads <= 1) return;
  previous_ = current;
  // A multithreaded call leaves its pool spinning beside the caller's
  // threads: shut it down after, unless the scope only lowered the count.
  raised_ = num_threads > 1 && num_threads >= current;
  Blas().set_threads(num_threads);
}

BlasThreads::~BlasThreads() {
  if (previous_ == 0) return;
  Blas().set_threads(previous_);
  // Threads this scope started would spin beside the caller's own threads.
  if (raised_) Blas().shutdown();
}

}  // namespace dba
