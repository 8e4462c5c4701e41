// The fault points' hook; see fault_seam.h.
#include "dba/common/fault_seam.h"

#include <atomic>

namespace dba {
namespace {

std::atomic<FaultHook> hook{nullptr};

}  // namespace

void SetFaultHook(FaultHook h) { hook.store(h); }

void FaultPoint(int rank, const char* step, int count) {
  if (const FaultHook h = hook.load(std::memory_order_relaxed)) h(rank, step, count);
}

}  // namespace dba
