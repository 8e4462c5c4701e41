// A shared library opened at run time; see shared_library.h.
#include "dba/common/shared_library.h"

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>

#include "dba/common/memory.h"

namespace dba {
namespace {

std::atomic<int64_t> libraries_resident{0};

}  // namespace

int64_t SharedLibrariesResidentBytes() { return libraries_resident.load(); }

SharedLibrary::SharedLibrary(const std::string& soname, const std::string& purpose, bool global)
    : soname_(soname) {
  const int64_t before = CurrentResidentBytes();
  handle_ = ::dlopen(soname.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL));
  if (handle_ != nullptr) libraries_resident += std::max<int64_t>(0, CurrentResidentBytes() - before);
  if (handle_ == nullptr) {
    const char* why = ::dlerror();
    // Mapped late, a library can find the address space used up by then.
    const int64_t room = AddressSpaceRoomBytes();
    throw std::runtime_error(purpose + " needs the shared library " + soname + ", which did not load: " +
                             (why != nullptr ? why : "no reason given") +
                             (room < 0 ? "" : " (under an address-space limit, ulimit -v, that leaves " +
                                                  std::to_string(room >> 20) + " MiB)"));
  }
}

void* SharedLibrary::Address(const char* name) const {
  ::dlerror();
  void* address = ::dlsym(handle_, name);
  if (address == nullptr) {
    throw std::runtime_error("the shared library " + soname_ + " has no symbol " + name +
                             " (another version than dba was built with?)");
  }
  return address;
}

}  // namespace dba
