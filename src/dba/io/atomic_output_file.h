// An output file that appears whole or not at all: written under a
// temporary name (path.tmp.<pid>) and renamed over `path` only by Commit(),
// after flushing and fsync. Destroyed without Commit() (an error, an
// exception) it removes the temporary, so a failed run never leaves a
// half-written result; a run ended by SIGINT, SIGTERM or SIGHUP neither
// (io/temporary_registry.h). Several files that belong together (a COLMAP
// model's three) are committed with CommitTogether: all are finished (on
// disk) before any is renamed, so a full disk leaves every old file whole.
//
// Writes go through stdio with a 1 MiB buffer, by Write() or by fwrite and
// friends on file() (a bzip2 stream, a binary writer).
//
// Thread safety: one owner.
#pragma once

#include <cstdio>
#include <initializer_list>
#include <string>
#include <string_view>

namespace dba {

class AtomicOutputFile {
 public:
  // Creates path.tmp.<pid>; throws std::runtime_error naming `path`.
  explicit AtomicOutputFile(const std::string& path);
  ~AtomicOutputFile();
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  std::FILE* file() const { return file_; }
  // For positioned writes (pwrite), which bypass file()'s buffer: a file is
  // written either through file() and Write() or through fd(), not both.
  int fd() const { return ::fileno(file_); }
  const std::string& path() const { return path_; }

  void Write(const void* data, size_t size);
  void Write(std::string_view s) { Write(s.data(), s.size()); }

  // Finish (flush, fsync, close: the data is on disk), then Rename (over
  // path()). Each throws on failure, and the temporary is removed.
  void Finish();
  void Rename();
  void Commit() {
    Finish();
    Rename();
  }
  // Throws std::runtime_error "path: what: strerror(err)" (no ": strerror"
  // for err 0); the temporary is removed by the destructor.
  [[noreturn]] void Fail(const std::string& what, int err) const;

 private:
  std::string path_, tmp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
  int registry_slot_ = -1;  // io/temporary_registry.h
};

// Finishes every file, then renames them all.
void CommitTogether(std::initializer_list<AtomicOutputFile*> files);

// A whole file at once (a report).
void WriteFileAtomically(const std::string& path, std::string_view contents);

}  // namespace dba
