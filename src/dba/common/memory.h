// Peak and current resident memory of this process (Linux /proc), and the
// pages of large arrays: given back, advised onto huge pages, taken early
// by all threads. Thread safety: safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dba {

// A size for people: "512.0 KiB", "3.5 MiB", "1.25 GiB".
std::string BytesText(double bytes);

// Peak resident set size (VmHWM) in bytes, 0 if unknown.
int64_t PeakResidentBytes();
// Current resident set size (VmRSS) in bytes, 0 if unknown.
int64_t CurrentResidentBytes();
// Memory this process may still take: the least of the machine's
// MemAvailable, the room its cgroups' limits leave (v1 or v2, every
// ancestor, less what each whole group holds) and the room under its
// address-space limit (RLIMIT_AS); -1 if none of them is known, 0 when a
// limit is already reached.
int64_t AvailableMemoryBytes();

// The room the cgroups named in `proc_cgroup` (/proc/self/cgroup's format)
// leave under `cgroup_root` (/sys/fs/cgroup): for each group from the
// process's own up to the root that has a limit (v2's memory.max, v1's
// memory/…/memory.limit_in_bytes), the limit less what the whole group
// holds (memory.current or memory.usage_in_bytes, less its inactive page
// cache); the least of them, at least 0; -1 when no group has a limit.
int64_t CgroupRoomBytes(const std::string& proc_cgroup, const std::string& cgroup_root);

// Address space this process may still map under its limit (RLIMIT_AS,
// `ulimit -v`): the limit less the mappings it has (VmSize); -1 when there
// is no limit. Under such a limit every mapping counts, reserved or not (a
// thread's stack, a library's buffers).
int64_t AddressSpaceRoomBytes();

// Gives the whole pages inside [data, data + bytes) back to the system
// (madvise MADV_DONTNEED): they read as zero afterwards and take memory
// again only when written. For arrays whose contents are no longer needed.
// False when the system refused (locked memory, huge-page heaps, not
// Linux): the pages then keep their contents.
bool ReturnPages(void* data, int64_t bytes);
// [data, data + count) set to zero: the whole pages given back, the partial
// ones at the ends written (all written where pages cannot be given back).
void ZeroAndReturnPages(double* data, int64_t count);

// Asks the system to back the whole 2 MiB-aligned stretches inside
// [data, data + bytes) with huge pages (madvise MADV_HUGEPAGE), before they
// are first written. Where page faults are dear (a virtual machine that
// shadows the page tables: about 4 s per GiB of 4 KiB pages here, 0.1 s per
// GiB of huge ones) and for arrays read at random (fewer TLB misses). A hint:
// false where the system refused it (no transparent huge pages, not Linux).
bool AdviseHugePages(void* data, int64_t bytes);

// Takes the pages of [data, data + bytes) now, writable, split over the
// OpenMP threads (madvise MADV_POPULATE_WRITE): a fresh array's first
// writes are page faults, which a single thread's memset takes one after
// the other (2.4 s per GiB of huge pages here, 1.0 s with two threads).
// A hint: nothing happens where the system cannot (Linux before 5.14).
void PopulatePages(void* data, int64_t bytes);

// v holds n zeros; a large fresh array's pages are taken by all threads
// first (PopulatePages), then zeroed.
template <typename T>
void AssignZeros(std::vector<T>* v, std::size_t n) {
  constexpr std::size_t kPopulateBytes = std::size_t{64} << 20;
  if (n * sizeof(T) >= kPopulateBytes && v->capacity() < n) {
    std::vector<T>().swap(*v);
    v->reserve(n);
    PopulatePages(v->data(), static_cast<int64_t>(n * sizeof(T)));
  }
  v->assign(n, T{});
}

}  // namespace dba
