#include "dba/common/memory.h"

#include <gtest/gtest.h>
#include <sys/mman.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace dba {
namespace {

TEST(Memory, PeakGrowsWithATouchedAllocation) {
  const int64_t before = PeakResidentBytes();
  ASSERT_GT(before, 0);
  std::vector<char> big(before + (64 << 20), 1);  // touches every page
  const int64_t current = CurrentResidentBytes();
  const int64_t after = PeakResidentBytes();
  EXPECT_GE(after, static_cast<int64_t>(big.size()));
  EXPECT_GE(current, static_cast<int64_t>(big.size()));
  // The kernel syncs each thread's page counts into the high-water mark
  // every 64 faults, so the peak may trail the current size by a few pages
  // (seen under AddressSanitizer: 8 KiB).
  EXPECT_LE(current, after + (4 << 20));
}

// Kilobytes of AnonHugePages over this process's mappings.
int64_t AnonHugeKilobytes() {
  std::FILE* f = std::fopen("/proc/self/smaps_rollup", "r");
  if (f == nullptr) return -1;
  char line[256];
  int64_t kb = -1;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::strncmp(line, "AnonHugePages:", 14) == 0) std::sscanf(line + 14, "%ld", &kb);
  }
  std::fclose(f);
  return kb;
}

TEST(Memory, AdvisedMemoryIsBackedByHugePages) {
  std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  std::getline(mode_file, mode);
  // Only where huge pages come on request: with "always" they would come
  // without the advice, with "never" not at all.
  if (mode.find("[madvise]") == std::string::npos || AnonHugeKilobytes() < 0) {
    GTEST_SKIP() << "transparent huge pages are not on request here (" << mode << ")";
  }
  // 16 MiB at an arbitrary (page, not 2 MiB) alignment: at least 6 whole
  // huge pages inside it.
  const size_t bytes = size_t{18} << 20;
  char* map = static_cast<char*>(
      mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
  ASSERT_NE(map, MAP_FAILED);
  char* data = map + 4096;
  const int64_t before = AnonHugeKilobytes();
  ASSERT_TRUE(AdviseHugePages(data, int64_t{16} << 20));
  std::memset(data, 1, size_t{16} << 20);
  const int64_t after = AnonHugeKilobytes();
  munmap(map, bytes);
  // The kernel may fall back to small pages when it has no free 2 MiB
  // block; on an idle machine with memory to spare it has.
  EXPECT_GE(after - before, 6 * 2048) << "mode " << mode;
  // A range holding no whole huge page is advice about nothing: fine.
  EXPECT_TRUE(AdviseHugePages(data, 4096));
}

}  // namespace
}  // namespace dba
