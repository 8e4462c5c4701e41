// DBA_INJECT_FAULT=RANK:STEP:N (for the test suite's mpirun scripts): rank
// RANK throws at its N-th reaching of fault point STEP (common/fault_seam.h);
// "RANK:N" means "RANK:form:N". Installed by the program's main before any
// work; without the variable there is no hook.
#include "fault_injection.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "dba/common/fault_seam.h"

namespace {

void InjectFault(int rank, const char* step, int count) {
  const char* spec = std::getenv("DBA_INJECT_FAULT");
  if (spec == nullptr) return;
  int fault_rank = -1, fault_count = -1;
  char fault_step[16] = "form";
  const bool parsed =
      std::sscanf(spec, "%d:%15[a-z]:%d", &fault_rank, fault_step, &fault_count) == 3 ||
      std::sscanf(spec, "%d:%d", &fault_rank, &fault_count) == 2;
  if (parsed && fault_rank == rank && fault_count == count && std::strcmp(fault_step, step) == 0) {
    throw std::runtime_error("injected fault (DBA_INJECT_FAULT=" + std::string(spec) + ") at " +
                             step + " " + std::to_string(count));
  }
}

}  // namespace

void InstallFaultInjectionFromEnvironment() {
  if (std::getenv("DBA_INJECT_FAULT") != nullptr) dba::SetFaultHook(InjectFault);
}
