// The BLAS's threads; see blas_threads.h.
#include "dba/common/blas_threads.h"

#include <dlfcn.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

#include "dba/common/memory.h"

namespace dba {
namespace {

struct OpenBlas {
  void (*set_threads)(int) = nullptr;
  int (*get_threads)() = nullptr;
  int (*shutdown)() = nullptr;
  // The calling thread's work buffer: mapped by the first alloc, kept
  // mapped (and reused) after a free.
  void* (*memory_alloc)(int) = nullptr;
  void (*memory_free)(void*) = nullptr;
  OpenBlas() {
    set_threads = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    get_threads = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    shutdown = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "blas_thread_shutdown_"));
    memory_alloc = reinterpret_cast<void* (*)(int)>(dlsym(RTLD_DEFAULT, "blas_memory_alloc"));
    memory_free = reinterpret_cast<void (*)(void*)>(dlsym(RTLD_DEFAULT, "blas_memory_free"));
  }
  bool loaded() const { return set_threads && get_threads && shutdown; }
};

// OpenBLAS's functions, looked up again until found: the BLAS loads with
// CHOLMOD (OpenLibraryWithBlas), after the program's start.
OpenBlas Blas() {
  static std::mutex mutex;
  static OpenBlas blas;
  const std::lock_guard<std::mutex> lock(mutex);
  if (!blas.loaded()) blas = OpenBlas();
  return blas;
}

std::atomic<bool> program_owns_blas{false};

// What OpenBLAS maps, and retries forever when a limit on the address space
// refuses it: a 128 MiB buffer for the calling thread (once).
constexpr int64_t kBlasBufferBytes = int64_t{129} << 20;
// What the factorization maps before BLAS first runs: CHOLMOD's OpenMP team
// (4 threads in Debian's SuiteSparse 5, whatever -t says) starts 3 threads,
// 8 MiB of stack each (their malloc arenas are given up quietly when
// refused). Measured: 2 of them took 80 MiB between the check and the
// buffer, and OpenBLAS spun under ulimit -v 300000.
constexpr int64_t kCholmodTeamBytes = int64_t{32} << 20;
std::atomic<bool> main_buffer_taken{false};

// Maps the calling thread's BLAS buffer now, while the room is known to
// hold it; OpenBLAS keeps it for the calls that follow.
void TakeMainBuffer() {
  const OpenBlas blas = Blas();
  if (blas.memory_alloc == nullptr || blas.memory_free == nullptr) return;
  blas.memory_free(blas.memory_alloc(1));
}

}  // namespace

void StopBlasThreads() {
  program_owns_blas = true;
  const OpenBlas blas = Blas();
  if (!blas.loaded()) return;
  blas.set_threads(1);
  blas.shutdown();
}

SharedLibrary OpenLibraryWithBlas(const std::string& soname, const std::string& purpose) {
  const bool owned = program_owns_blas.load();
  if (owned && AddressSpaceRoomBytes() >= 0) ::setenv("OPENBLAS_NUM_THREADS", "1", 1);
  SharedLibrary library(soname, purpose, /*global=*/true);
  if (owned) StopBlasThreads();
  return library;
}

int BlasThreadsThatFit(int num_threads) {
  const int64_t room = AddressSpaceRoomBytes();
  if (room < 0) return num_threads;
  if (main_buffer_taken.load()) return 1;
  const int64_t need = kBlasBufferBytes + kCholmodTeamBytes;
  if (room < need) {
    throw std::runtime_error(
        "the address-space limit (ulimit -v, RLIMIT_AS) leaves " + std::to_string(room >> 20) +
        " MiB; the BLAS under the sparse factorization needs " + std::to_string(need >> 20) +
        " MiB and would wait for it forever: raise the limit, or solve with --linear-solver "
        "pcg");
  }
  TakeMainBuffer();
  main_buffer_taken = true;
  return 1;
}

BlasThreads::BlasThreads(int num_threads) {
  const OpenBlas blas = Blas();
  if (!blas.loaded()) return;
  num_threads = BlasThreadsThatFit(num_threads);
  const int current = blas.get_threads();
  // One thread where one is set: nothing to change, restore or shut down. (A
  // restore that shut the pool down took about a millisecond, which a coarse
  // solve of the two-level preconditioner paid per PCG iteration: 5x its own
  // time.)
  if (current == num_threads && num_threads <= 1) return;
  previous_ = current;
  // A multithreaded call leaves its pool spinning beside the caller's
  // threads: shut it down after, unless the scope only lowered the count.
  raised_ = num_threads > 1 && num_threads >= current;
  blas.set_threads(num_threads);
}

BlasThreads::~BlasThreads() {
  if (previous_ == 0) return;
  const OpenBlas blas = Blas();
  blas.set_threads(previous_);
  // Threads this scope started would spin beside the caller's own threads.
  if (raised_) blas.shutdown();
}

}  // namespace dba
