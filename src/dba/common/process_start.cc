// The process's start from the kernel's record; see process_start.h.
#include "dba/common/process_start.h"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace dba {

double ProcessAgeSeconds(const std::string& stat, double boot_seconds, long ticks_per_second) {
  // Field 2, the command's name in parentheses, may hold spaces and
  // parentheses: the fields after it start after the last ')'. Field 22 is
  // the 20th of those (field 3 the first).
  const size_t paren = stat.rfind(')');
  if (paren == std::string::npos || ticks_per_second <= 0) return -1.0;
  std::istringstream fields(stat.substr(paren + 1));
  std::string field;
  for (int k = 3; k <= 22; ++k) {
    if (!(fields >> field)) return -1.0;
  }
  char* end = nullptr;
  const unsigned long long ticks = std::strtoull(field.c_str(), &end, 10);
  if (end == field.c_str() || *end != '\0') return -1.0;
  const double tick = 1.0 / static_cast<double>(ticks_per_second);
  const double earliest = static_cast<double>(ticks) * tick;
  if (boot_seconds < earliest) return -1.0;  // not this clock's record
  const double latest = std::min(earliest + tick, boot_seconds);
  return boot_seconds - 0.5 * (earliest + latest);
}

double ProcessAgeSeconds() {
  std::ifstream in("/proc/self/stat");
  std::string stat;
  if (!std::getline(in, stat)) return -1.0;
  timespec now{};
  if (::clock_gettime(CLOCK_BOOTTIME, &now) != 0) return -1.0;
  return ProcessAgeSeconds(stat, static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec),
                           ::sysconf(_SC_CLK_TCK));
}

Timer SinceProcessStart() { return Timer::StartedAgo(std::max(0.0, ProcessAgeSeconds())); }

}  // namespace dba
