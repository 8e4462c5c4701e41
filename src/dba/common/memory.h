// Peak and current resident memory of this process (Linux /proc).
// Thread safety: safe.
#pragma once

#include <cstdint>

namespace dba {

// Peak resident set size (VmHWM) in bytes, 0 if unknown.
int64_t PeakResidentBytes();
// Current resident set size (VmRSS) in bytes, 0 if unknown.
int64_t CurrentResidentBytes();
// Memory this process may still take: the machine's MemAvailable, or less
// where a cgroup (v2) limit leaves less room; 0 if unknown.
int64_t AvailableMemoryBytes();

}  // namespace dba
