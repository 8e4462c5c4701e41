// The BLAS's threads; see blas_threads.h.
#include "dba/common/blas_threads.h"

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "dba/common/memory.h"

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

// What OpenBLAS maps, and retries forever when a limit on the address space
// refuses it: a 128 MiB buffer for the calling thread (once), and for each
// further thread its buffer, a malloc arena (64 MiB) and a stack.
constexpr int64_t kBlasBufferBytes = int64_t{129} << 20;
constexpr int64_t kBlasWorkerBytes = kBlasBufferBytes + (int64_t{80} << 20);
std::atomic<bool> main_buffer_taken{false};

}  // namespace

void StopBlasThreads() {
  if (!Blas().loaded()) return;
  Blas().set_threads(1);
  Blas().shutdown();
}

int BlasThreadsThatFit(int num_threads) {
  const int64_t room = AddressSpaceRoomBytes();
  if (room < 0) return num_threads;
  const int64_t main = main_buffer_taken.load() ? 0 : kBlasBufferBytes;
  if (room < main) {
    throw std::runtime_error(
        "the address-space limit (ulimit -v, RLIMIT_AS) leaves " + std::to_string(room >> 20) +
        " MiB; the BLAS under the sparse factorization needs " +
        std::to_string(main >> 20) + " MiB more and would wait for it forever: raise the "
        "limit, or solve with --linear-solver pcg");
  }
  return static_cast<int>(
      std::clamp<int64_t>(1 + (room - main) / kBlasWorkerBytes, 1, std::max(num_threads, 1)));
}

BlasThreads::BlasThreads(int num_threads) {
  if (!Blas().loaded()) return;
  num_threads = BlasThreadsThatFit(num_threads);
  main_buffer_taken = true;
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
