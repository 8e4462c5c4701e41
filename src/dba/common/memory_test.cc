#include "dba/common/memory.h"

#include <gtest/gtest.h>
#include <sys/mman.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
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

// A fake /proc/self/cgroup and /sys/fs/cgroup tree under a temporary root.
struct FakeCgroups {
  std::string root = ::testing::TempDir() + "fake_cgroups_" +
                     ::testing::UnitTest::GetInstance()->current_test_info()->name();
  FakeCgroups() { std::filesystem::remove_all(root); }
  void File(const std::string& path, const std::string& text) {
    std::filesystem::create_directories(std::filesystem::path(root + path).parent_path());
    std::ofstream(root + path) << text;
  }
  int64_t Room() { return CgroupRoomBytes(root + "/proc_cgroup", root + "/sys"); }
};

TEST(Memory, CgroupRoomIsTheLeastOverEveryLimitedAncestorLessTheGroupsUse) {
  FakeCgroups v2;
  v2.File("/proc_cgroup", "0::/a/b\n");
  EXPECT_EQ(v2.Room(), -1);  // no limit anywhere
  v2.File("/sys/a/b/memory.max", "max\n");
  v2.File("/sys/a/b/memory.current", "100\n");
  v2.File("/sys/a/memory.max", "1000\n");
  v2.File("/sys/a/memory.current", "700\n");  // the group's other members count
  EXPECT_EQ(v2.Room(), 300);
  v2.File("/sys/a/memory.stat", "active_file 5\ninactive_file 200\n");  // reclaimable cache
  EXPECT_EQ(v2.Room(), 500);
  v2.File("/sys/a/b/memory.max", "50\n");  // below what the group holds: no room, not unknown
  EXPECT_EQ(v2.Room(), 0);

  FakeCgroups v1;
  v1.File("/proc_cgroup", "4:memory:/job\n0::/\n");
  v1.File("/sys/memory/job/memory.limit_in_bytes", "4096\n");
  v1.File("/sys/memory/job/memory.usage_in_bytes", "1024\n");
  v1.File("/sys/memory/memory.limit_in_bytes", "9223372036854771712\n");  // unlimited
  EXPECT_EQ(v1.Room(), 3072);
}

TEST(Memory, AvailableIsTheTestHooksFigureWhenSet) {
  setenv("DBA_MEMORY_AVAILABLE", "12345", 1);
  EXPECT_EQ(AvailableMemoryBytes(), 12345);
  unsetenv("DBA_MEMORY_AVAILABLE");
  EXPECT_GT(AvailableMemoryBytes(), 0);
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
