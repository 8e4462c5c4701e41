// Resident memory from /proc; pages given back, advised and taken; see memory.h.
#include "dba/common/memory.h"

#include <omp.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <string>
#include <utility>

namespace dba {

std::string BytesText(double bytes) {
  char text[64];
  if (bytes >= double(int64_t{1} << 30)) {
    std::snprintf(text, sizeof text, "%.2f GiB", bytes / double(int64_t{1} << 30));
  } else if (bytes >= double(1 << 20)) {
    std::snprintf(text, sizeof text, "%.1f MiB", bytes / double(1 << 20));
  } else {
    std::snprintf(text, sizeof text, "%.1f KiB", bytes / 1024.0);
  }
  return text;
}

namespace {

// The number after `key` at the start of a line of `path` (kB in /proc's
// files, bytes in a cgroup's memory.stat), 0 if none.
int64_t ReadKilobytes(const char* path, const char* key) {
  std::FILE* f = std::fopen(path, "r");
  if (f == nullptr) return 0;
  char line[256];
  int64_t kb = 0;
  const size_t key_len = std::strlen(key);
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::strncmp(line, key, key_len) == 0) {
      std::sscanf(line + key_len, "%ld", &kb);
      break;
    }
  }
  std::fclose(f);
  return kb;
}

// [begin, end): the whole `unit`-aligned stretches inside [data, data +
// bytes) (end <= begin: none).
std::pair<uintptr_t, uintptr_t> WholeUnitsInside(const void* data, int64_t bytes, uintptr_t unit) {
  const uintptr_t first = reinterpret_cast<uintptr_t>(data);
  return {(first + unit - 1) / unit * unit, (first + static_cast<uintptr_t>(bytes)) / unit * unit};
}

int64_t ReadStatusKilobytes(const char* key) { return ReadKilobytes("/proc/self/status", key); }

// A whole number from a cgroup file, -1 when absent or unlimited ("max",
// or v1's about 2^63).
int64_t ReadCgroupNumber(const std::string& path) {
  std::FILE* m = std::fopen(path.c_str(), "r");
  if (m == nullptr) return -1;
  long long v = -1;
  const int read = std::fscanf(m, "%lld", &v);
  std::fclose(m);
  return read == 1 && v >= 0 && v < (1LL << 60) ? v : -1;
}

}  // namespace

// A limit already below what the group holds leaves no room (0), not an
// unknown one; the group's other members count.
int64_t CgroupRoomBytes(const std::string& proc_cgroup, const std::string& cgroup_root) {
  std::FILE* f = std::fopen(proc_cgroup.c_str(), "r");
  if (f == nullptr) return -1;
  char line[512];
  std::string v2, v1;
  bool has_v2 = false;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    std::string l = line;
    while (!l.empty() && (l.back() == '\n' || l.back() == '\r')) l.pop_back();
    if (l.rfind("0::", 0) == 0) v2 = l.substr(3), has_v2 = true;
    const size_t at = l.find(":memory:");
    if (at != std::string::npos) v1 = l.substr(at + 8);
  }
  std::fclose(f);
  int64_t room = -1;
  auto consider = [&](const std::string& dir, const char* limit_file, const char* usage_file) {
    const int64_t limit = ReadCgroupNumber(dir + limit_file);
    if (limit < 0) return;
    // The group's usage counts its page cache; the inactive part of it is
    // reclaimed before the limit bites (as `docker stats` counts).
    const int64_t cache = ReadKilobytes((dir + "/memory.stat").c_str(), "inactive_file ");
    const int64_t used = std::max<int64_t>(0, ReadCgroupNumber(dir + usage_file) - cache);
    const int64_t here = std::max<int64_t>(0, limit - used);
    room = room < 0 ? here : std::min(room, here);
  };
  auto each_ancestor = [](std::string group, auto&& visit) {
    while (true) {
      visit(group);
      if (group.empty() || group == "/") return;
      const size_t slash = group.find_last_of('/');
      group = slash == 0 || slash == std::string::npos ? std::string() : group.substr(0, slash);
    }
  };
  if (!v1.empty()) {
    each_ancestor(v1, [&](const std::string& g) {
      consider(cgroup_root + "/memory" + g, "/memory.limit_in_bytes", "/memory.usage_in_bytes");
    });
  }
  if (has_v2) {
    each_ancestor(v2, [&](const std::string& g) {
      consider(cgroup_root + g, "/memory.max", "/memory.current");
    });
  }
  return room;
}


int64_t AddressSpaceRoomBytes() {
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return -1;
  const int64_t mapped = ReadStatusKilobytes("VmSize:") * 1024;
  return std::max<int64_t>(0, static_cast<int64_t>(limit.rlim_cur) - mapped);
}

int64_t PeakResidentBytes() { return ReadStatusKilobytes("VmHWM:") * 1024; }
int64_t CurrentResidentBytes() { return ReadStatusKilobytes("VmRSS:") * 1024; }

int64_t AvailableMemoryBytes() {
  // A test hook (README.md, "Test hooks"): the memory available, in bytes.
  if (const char* v = std::getenv("DBA_MEMORY_AVAILABLE")) return std::atoll(v);
  int64_t room = ReadKilobytes("/proc/meminfo", "MemAvailable:") * 1024;
  if (room == 0) room = -1;  // not known
  for (const int64_t other :
       {CgroupRoomBytes("/proc/self/cgroup", "/sys/fs/cgroup"), AddressSpaceRoomBytes()}) {
    if (other >= 0) room = room < 0 ? other : std::min(room, other);
  }
  return room;
}

bool ReturnPages(void* data, int64_t bytes) {
#ifdef __linux__
  static const uintptr_t page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto [begin, end] = WholeUnitsInside(data, bytes, page);
  if (end <= begin) return true;
  return madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED) == 0;
#else
  (void)data;
  (void)bytes;
  return false;
#endif
}

bool AdviseHugePages(void* data, int64_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const auto [begin, end] = WholeUnitsInside(data, bytes, uintptr_t{2} << 20);
  if (end <= begin) return true;
  return madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE) == 0;
#else
  (void)data;
  (void)bytes;
  return false;
#endif
}

void PopulatePages(void* data, int64_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  static const uintptr_t page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto [begin, end] = WholeUnitsInside(data, bytes, page);
  if (end <= begin) return;
  const uintptr_t pages = (end - begin) / page;
#pragma omp parallel
  {
    const uintptr_t threads = static_cast<uintptr_t>(omp_get_num_threads());
    const uintptr_t t = static_cast<uintptr_t>(omp_get_thread_num());
    const uintptr_t first = begin + pages * t / threads * page;
    const uintptr_t last = begin + pages * (t + 1) / threads * page;
    if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_POPULATE_WRITE);
  }
#else
  (void)data;
  (void)bytes;
#endif
}

void ZeroAndReturnPages(double* data, int64_t count) {
  static const int64_t page = sysconf(_SC_PAGESIZE) / static_cast<int64_t>(sizeof(double));
  const int64_t misalign = static_cast<int64_t>(reinterpret_cast<uintptr_t>(data) % (page * 8)) / 8;
  const int64_t head = std::min(count, misalign == 0 ? 0 : page - misalign);
  const int64_t tail = (count - head) % page;
  std::fill(data, data + head, 0.0);
  std::fill(data + count - tail, data + count, 0.0);
  // Locked memory (mlockall) or huge-page heaps refuse MADV_DONTNEED: then
  // the zeros are written.
  if (!ReturnPages(data + head, (count - head - tail) * 8)) {
    std::fill(data + head, data + count - tail, 0.0);
  }
}

}  // namespace dba
