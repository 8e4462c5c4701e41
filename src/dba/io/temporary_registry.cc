// Removal of live temporaries on signals; see temporary_registry.h.
#include "dba/io/temporary_registry.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

namespace dba {
namespace {

constexpr int kSlots = 64;
constexpr size_t kMaxPath = 4096;
// A slot is free (0), being written (1) or holds a path (2).
std::atomic<int> state[kSlots];
char paths[kSlots][kMaxPath];

void Cleanup(int sig) {
  for (int s = 0; s < kSlots; ++s) {
    if (state[s].load(std::memory_order_acquire) == 2) ::unlink(paths[s]);
  }
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

}  // namespace

int RegisterTemporary(const std::string& path) {
  if (path.size() >= kMaxPath) return -1;
  for (int s = 0; s < kSlots; ++s) {
    int expected = 0;
    if (state[s].compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) {
      std::memcpy(paths[s], path.c_str(), path.size() + 1);
      state[s].store(2, std::memory_order_release);
      return s;
    }
  }
  return -1;
}

void UnregisterTemporary(int slot) {
  if (slot >= 0 && slot < kSlots) state[slot].store(0, std::memory_order_release);
}

void RemoveTemporariesOnSignals() {
  struct sigaction action {};
  action.sa_handler = Cleanup;
  sigemptyset(&action.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    // A signal the caller chose to ignore stays ignored.
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    ::sigaction(sig, &action, nullptr);
  }
}

}  // namespace dba
