// DBA_DCHECK(condition): an internal invariant, checked in debug builds
// (NDEBUG not defined, or DBA_CHECKS defined) and compiled out of release
// builds, where the condition is not evaluated. A failure prints the file,
// the line and the condition and aborts: it is a bug in dba, never bad
// input (bad input is an InputError or UsageError, common/error.h).
// Thread safety: any thread.
#pragma once

#include <cstdio>
#include <cstdlib>

#if !defined(NDEBUG) || defined(DBA_CHECKS)
#define DBA_DCHECK(condition)                                                         \
  do {                                                                                \
    if (!(condition)) {                                                               \
      std::fprintf(stderr, "%s:%d: internal check failed: %s\n", __FILE__, __LINE__, \
                   #condition);                                                       \
      std::abort();                                                                   \
    }                                                                                 \
  } while (false)
#else
#define DBA_DCHECK(condition) \
  do {                        \
  } while (false && (condition))
#endif
