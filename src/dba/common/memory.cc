// Resident memory from /proc/self/status; see memory.h.
#include "dba/common/memory.h"

#include <cstdio>
#include <cstring>

namespace dba {
namespace {

int64_t ReadStatusKilobytes(const char* key) {
  std::FILE* f = std::fopen("/proc/self/status", "r");
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

}  // namespace

int64_t PeakResidentBytes() { return ReadStatusKilobytes("VmHWM:") * 1024; }
int64_t CurrentResidentBytes() { return ReadStatusKilobytes("VmRSS:") * 1024; }

}  // namespace dba
