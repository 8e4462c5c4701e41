// Atomic output: a file written under a temporary name (path.tmp.<pid>) and
// renamed over `path` only by Commit(), after flushing and fsync. Destroyed
// without Commit() (an error, an exception), it removes the temporary, so a
// failed run never leaves a half-written result; a run ended by SIGINT,
// SIGTERM or SIGHUP neither (io/temporary_registry.h).
//
// Thread safety: one owner.
#pragma once

#include <cstdio>
#include <string>

namespace dba {

class TemporaryFile {
 public:
  // Creates path.tmp.<pid>; throws std::runtime_error naming `path`.
  explicit TemporaryFile(const std::string& path);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  std::FILE* file() const { return file_; }
  int fd() const { return ::fileno(file_); }
  const std::string& path() const { return path_; }

  // Flushes, syncs, closes and renames over path(). Throws on failure (the
  // temporary is then removed by the destructor).
  void Commit();
  // Throws std::runtime_error "path: what: strerror(err)".
  [[noreturn]] void Fail(const std::string& what, int err) const;

 private:
  std::string path_, tmp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
  int registry_slot_ = -1;  // io/temporary_registry.h
};

}  // namespace dba
