// Atomic whole-file write; see atomic_file.h.
#include "dba/io/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace dba {

void WriteFileAtomically(const std::string& path, std::string_view contents) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  auto fail = [&](const char* what) {
    const int err = errno;
    if (f != nullptr) std::fclose(f);
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": " + what + ": " + std::strerror(err));
  };
  if (f == nullptr) fail("cannot create temporary file");
  if (std::fwrite(contents.data(), 1, contents.size(), f) != contents.size() ||
      std::fflush(f) != 0) {
    fail("write failed");
  }
  if (::fsync(::fileno(f)) != 0) fail("fsync failed");
  const int rc = std::fclose(f);
  f = nullptr;
  if (rc != 0) fail("close failed");
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("rename failed");
}

}  // namespace dba
