// Terminal progress of long phases; see progress.h.
#include "dba/common/progress.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace dba {
namespace {

std::atomic<bool> enabled{false};

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

constexpr double kInterval = 0.25;  // seconds between updates

// Seconds before a phase shows at all: 1, or DBA_PROGRESS_DELAY (tests).
double FirstAfter() {
  static const double delay = [] {
    const char* v = std::getenv("DBA_PROGRESS_DELAY");
    return v != nullptr ? std::atof(v) : 1.0;
  }();
  return delay;
}

}  // namespace

void EnableProgress(bool on) { enabled = on && ::isatty(STDERR_FILENO) == 1; }
bool ProgressEnabled() { return enabled; }

ProgressPhase::ProgressPhase(const char* name) : name_(name), on_(enabled) {
  if (on_) start_ = last_ = Now();
}

ProgressPhase::~ProgressPhase() {
  if (printed_) std::fprintf(stderr, "\r\033[K");
}

void ProgressPhase::Report(double fraction) {
  if (!on_) return;
  const double now = Now();
  if (now - start_ < FirstAfter() || (printed_ && now - last_ < kInterval)) return;
  last_ = now;
  const double elapsed = now - start_;
  if (fraction > 0.01 && fraction < 1.0) {
    std::fprintf(stderr, "\r\033[K%s %3.0f%% (%.0f s, about %.0f s left)", name_, 100.0 * fraction,
                 elapsed, elapsed * (1.0 - fraction) / fraction);
  } else {
    std::fprintf(stderr, "\r\033[K%s (%.0f s)", name_, elapsed);
  }
  std::fflush(stderr);
  printed_ = true;
}

}  // namespace dba
