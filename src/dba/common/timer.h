// Wall-clock timing. Thread safety: one Timer per thread.
#pragma once

#include <chrono>

namespace dba {

class Timer {
 public:
  Timer() : start_(std::chrono::steady_clock::now()) {}
  // A timer that started `seconds` ago (a run's clock from the process's
  // start: common/process_start.h).
  static Timer StartedAgo(double seconds) {
    Timer t;
    t.start_ -= std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(seconds));
    return t;
  }
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_)
        .count();
  }
  void Reset() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace dba
