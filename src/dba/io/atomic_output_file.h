// An output file that appears whole or not at all, following the rule of
// io/output_target.h: a regular file (or a new path, or the file a symbolic
// link leads to) is written under a temporary name (FILE.tmp.<pid>.<n>,
// beside it, n one per call: io/stale_temporaries.h) and renamed over it
// only by Commit(), after flushing and fsync; a
// character device or a FIFO is written in place. Destroyed without
// Commit() (an error, an exception) it removes the temporary, so a failed
// run never leaves a half-written result; a run ended by SIGINT, SIGTERM or
// SIGHUP neither (io/temporary_registry.h), and what a SIGKILL leaves is
// cleaned by the next write of the same file (io/stale_temporaries.h).
// A replaced file keeps its permissions (and, where allowed, its owner).
//
// Several files that belong together are replaced together, all or none:
// CommitTogether (a COLMAP model's three), or every file committed while an
// OutputTransaction is open on the thread (a run's outputs: -o, --report,
// --ply, ...): a rename that fails puts back what the earlier ones replaced,
// and a kill in the middle is undone or finished by the next process that
// touches any of them (io/replace_together.h).
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
#include <vector>

#include "dba/io/output_target.h"

namespace dba {

class AtomicOutputFile {
 public:
  // Resolves `path` (ResolveOutputTarget: UsageError where the rule refuses
  // it) and creates the temporary; throws std::runtime_error naming `path`.
  explicit AtomicOutputFile(const std::string& path);
  ~AtomicOutputFile();
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  std::FILE* file() const { return file_; }
  // For positioned writes (pwrite), which bypass file()'s buffer: a file is
  // written either through file() and Write() or through fd(), not both.
  // Only where seekable() (not a FIFO or a device).
  int fd() const { return ::fileno(file_); }
  bool seekable() const { return target_.mode == OutputMode::kReplace; }
  const std::string& path() const { return path_; }

  void Write(const void* data, size_t size);
  void Write(std::string_view s) { Write(s.data(), s.size()); }

  // Finish (flush, fsync, close: the data is on disk), then Rename (over the
  // target; while an OutputTransaction is open, left to its Commit). Each
  // throws on failure, and the temporary is removed.
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
  friend void CommitTogether(std::initializer_list<AtomicOutputFile*> files);
  std::string path_, tmp_;
  OutputTarget target_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
  int registry_slot_ = -1;  // io/temporary_registry.h
  int lock_fd_ = -1;        // holds the temporary's lock (io/stale_temporaries.h)
};

// Finishes every file, then renames them all, all or none.
void CommitTogether(std::initializer_list<AtomicOutputFile*> files);

// A whole file at once (a report).
void WriteFileAtomically(const std::string& path, std::string_view contents);

// The outputs of one run, replaced together. While it is open, the files
// this thread commits are finished (on disk) and wait; Commit() renames
// them all, or, when a rename fails, puts back every file the earlier ones
// replaced and throws. Destroyed without Commit() it removes them: nothing
// of the run appears. Streams (devices, FIFOs) are written when committed.
class OutputTransaction {
 public:
  OutputTransaction();
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;
  void Commit();

  // A finished temporary and the file it replaces (for AtomicOutputFile).
  struct Pending {
    std::string tmp, file;
    int registry_slot = -1, lock_fd = -1;
  };
  // The transaction open on this thread, or nullptr.
  static OutputTransaction* Current();
  void Add(Pending pending) { pending_.push_back(std::move(pending)); }

 private:
  std::vector<Pending> pending_;
  OutputTransaction* outer_ = nullptr;
};

}  // namespace dba
