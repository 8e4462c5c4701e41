// The age of this process: seconds from its start to now, for a run's clock
// whose phases add up to the wall time a parent measures (the report's
// `seconds`, session/solve_report.h).
//
// The start is the kernel's record of the process's creation
// (/proc/self/stat's field 22, starttime, in clock ticks since boot, against
// CLOCK_BOOTTIME, the clock it is kept in): the moment a shell,
// /usr/bin/time or mpirun forked it, before exec, the dynamic loader and the
// libraries' constructors, and kept across an exec. dba starts itself again
// once with the libraries' environment (tools/dba_main.cc); counted from the
// kernel's record, that second start is part of the start-up, which a
// start time handed on through the environment would leave out together
// with the first exec's loading.
//
// Precision: the record is in whole ticks (sysconf(_SC_CLK_TCK), 100 a
// second on Linux): the start is taken at the middle of what it leaves open,
// [tick, min(next tick, now)], within half a tick (5 ms).
//
// Thread safety: any thread.
#pragma once

#include <string>

#include "dba/common/timer.h"

namespace dba {

// The process's age in seconds; -1 where /proc/self/stat cannot be read or
// parsed (not Linux).
double ProcessAgeSeconds();

// The same from the text of a /proc/PID/stat, at `boot_seconds` on
// CLOCK_BOOTTIME with `ticks_per_second`; -1 where the text has no field 22.
double ProcessAgeSeconds(const std::string& stat, double boot_seconds, long ticks_per_second);

// A timer started at the process's start (started now where the start is
// not known).
Timer SinceProcessStart();

}  // namespace dba
