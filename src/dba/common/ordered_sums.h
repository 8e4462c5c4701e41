// Sums that several OpenMP threads compute, added in thread order: the same
// bits on every run with the same number of threads. OpenMP's reduction
// clause adds the threads' partial sums in the order they finish; with three
// threads or more the last bits of a cost or a dot product then vary from
// run to run, and with them LM's and PCG's decisions.
//
//   ThreadSums<K>        a parallel region's per-thread sums (each thread
//                        Sets its own once, at its end), Total in thread order
//   ParallelSums<K>      a loop over [0, n) in OpenMP's static ranges
//                        (schedule(static)'s: the first n % t threads one
//                        more), each term adding into K sums
//
// Thread safety: Set from each thread for its own index; Total after the
// region.
#pragma once

#include <omp.h>

#include <array>
#include <cstdint>
#include <vector>

namespace dba {

template <int K>
class ThreadSums {
 public:
  explicit ThreadSums(int threads) : partial_(static_cast<size_t>(threads > 0 ? threads : 1)) {}
  void Set(int thread, const std::array<double, K>& sums) { partial_[thread] = sums; }
  std::array<double, K> Total() const {
    std::array<double, K> total{};
    for (const std::array<double, K>& p : partial_) {
      for (int k = 0; k < K; ++k) total[k] += p[k];
    }
    return total;
  }

 private:
  std::vector<std::array<double, K>> partial_;
};

// add(i, sums) adds term i into sums[0..K). Serial where !parallel.
template <int K, class Add>
std::array<double, K> ParallelSums(int64_t n, int threads, bool parallel, Add add) {
  if (!parallel || threads <= 1) {
    std::array<double, K> s{};
    for (int64_t i = 0; i < n; ++i) add(i, s.data());
    return s;
  }
  ThreadSums<K> sums(threads);
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const int64_t q = n / nt, r = n % nt;
    const int64_t begin = t * q + (t < r ? t : r);
    const int64_t end = begin + q + (t < r ? 1 : 0);
    std::array<double, K> s{};
    for (int64_t i = begin; i < end; ++i) add(i, s.data());
    sums.Set(t, s);
  }
  return sums.Total();
}

}  // namespace dba
