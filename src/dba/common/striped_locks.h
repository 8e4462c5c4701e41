// A fixed set of spinlocks addressed by a hash of an index, so that many
// threads can update disjoint rows of a shared matrix without one mutex per
// row. Thread safety: that is its job.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>

namespace dba {

class StripedLocks {
 public:
  explicit StripedLocks(int num_stripes = 4096)
      : mask_(num_stripes - 1), flags_(new std::atomic_flag[num_stripes]) {
    for (int i = 0; i < num_stripes; ++i) flags_[i].clear();
  }
  void Lock(int64_t index) {
    std::atomic_flag& f = flags_[index & mask_];
    while (f.test_and_set(std::memory_order_acquire)) {
      while (f.test(std::memory_order_relaxed)) {
      }
    }
  }
  void Unlock(int64_t index) {
    flags_[index & mask_].clear(std::memory_order_release);
  }

 private:
  int64_t mask_;  // num_stripes must be a power of two
  std::unique_ptr<std::atomic_flag[]> flags_;
};

}  // namespace dba
