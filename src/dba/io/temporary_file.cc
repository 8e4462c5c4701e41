// Atomic output through a temporary file; see temporary_file.h.
#include "dba/io/temporary_file.h"

#include "dba/io/temporary_registry.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace dba {

TemporaryFile::TemporaryFile(const std::string& path)
    : path_(path), tmp_(path + ".tmp." + std::to_string(::getpid())) {
  registry_slot_ = RegisterTemporary(tmp_);
  file_ = std::fopen(tmp_.c_str(), "wb");
  if (file_ == nullptr) {
    const int err = errno;
    UnregisterTemporary(registry_slot_);
    Fail("cannot create '" + tmp_ + "'", err);
  }
}

TemporaryFile::~TemporaryFile() {
  if (file_ != nullptr) std::fclose(file_);
  if (!committed_) std::remove(tmp_.c_str());
  UnregisterTemporary(registry_slot_);
}

void TemporaryFile::Fail(const std::string& what, int err) const {
  std::string message = path_ + ": " + what;
  if (err != 0) message += std::string(": ") + std::strerror(err);
  throw std::runtime_error(message);
}

void TemporaryFile::Commit() {
  errno = 0;
  if (std::fflush(file_) != 0) Fail("write failed", errno);
  if (::fsync(::fileno(file_)) != 0) Fail("fsync failed", errno);
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) Fail("close failed", errno);
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    Fail("cannot rename '" + tmp_ + "' over it", errno);
  }
  committed_ = true;
}

}  // namespace dba
