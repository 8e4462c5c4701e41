// Atomic output files; see atomic_output_file.h.
#include "dba/io/atomic_output_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "dba/io/temporary_registry.h"

namespace dba {

AtomicOutputFile::AtomicOutputFile(const std::string& path)
    : path_(path), tmp_(path + ".tmp." + std::to_string(::getpid())) {
  registry_slot_ = RegisterTemporary(tmp_);
  file_ = std::fopen(tmp_.c_str(), "wb");
  if (file_ == nullptr) {
    const int err = errno;
    UnregisterTemporary(registry_slot_);
    Fail("cannot create '" + tmp_ + "'", err);
  }
  std::setvbuf(file_, nullptr, _IOFBF, size_t{1} << 20);
}

AtomicOutputFile::~AtomicOutputFile() {
  if (file_ != nullptr) std::fclose(file_);
  if (!committed_) std::remove(tmp_.c_str());
  UnregisterTemporary(registry_slot_);
}

void AtomicOutputFile::Fail(const std::string& what, int err) const {
  std::string message = path_ + ": " + what;
  if (err != 0) message += std::string(": ") + std::strerror(err);
  throw std::runtime_error(message);
}

void AtomicOutputFile::Write(const void* data, size_t size) {
  if (std::fwrite(data, 1, size, file_) != size) Fail("write failed", errno);
}

void AtomicOutputFile::Finish() {
  errno = 0;
  if (std::fflush(file_) != 0) Fail("write failed", errno);
  if (::fsync(::fileno(file_)) != 0) Fail("fsync failed", errno);
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) Fail("close failed", errno);
}

void AtomicOutputFile::Rename() {
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    Fail("cannot rename '" + tmp_ + "' over it", errno);
  }
  committed_ = true;
}

void CommitTogether(std::initializer_list<AtomicOutputFile*> files) {
  for (AtomicOutputFile* f : files) f->Finish();
  for (AtomicOutputFile* f : files) f->Rename();
}

void WriteFileAtomically(const std::string& path, std::string_view contents) {
  AtomicOutputFile out(path);
  out.Write(contents);
  out.Commit();
}

}  // namespace dba
