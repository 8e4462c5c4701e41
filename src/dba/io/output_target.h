// What an output path names, decided before anything is written: the rule
// every output of dba follows (docs/design.md §6, "Input and output").
//
//  - a regular file, or a path that does not exist yet: written to a
//    temporary beside it and renamed over it (io/atomic_output_file.h);
//  - a symbolic link: written through: the file it leads to is replaced, the
//    link stays; a link that leads nowhere is refused;
//  - a character device or a FIFO (/dev/null, /dev/stdout on a pipe): written
//    in place, plainly;
//  - anything else is refused: a directory, a block device, a socket, and a
//    regular file reached through /proc or /dev/fd (an open descriptor's link,
//    such as /dev/stdout redirected to a file: renaming over it would take the
//    file from under the shell that opened it).
//
// Thread safety: functions touch only the paths they name.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace dba {

enum class OutputMode { kReplace, kStream };

// What makes two paths one file: its device and inode; for a path that does
// not exist yet, its deepest existing directory's and the rest of the path
// below it ("out/cameras.txt" under a directory "out" to be made).
struct FileIdentity {
  uint64_t device = 0, inode = 0;
  std::string rest;
  bool operator==(const FileIdentity&) const = default;
};

struct OutputTarget {
  std::string path;  // as named
  std::string file;  // the file written: `path` with its symbolic links resolved
  OutputMode mode = OutputMode::kReplace;
  FileIdentity identity;
};

// The target of `path`. Throws UsageError "PATH: why" where the rule refuses
// it (empty, a directory, a block device, a socket, a dangling link, a file
// behind /proc), std::runtime_error where its directory does not exist (with
// `make_directory`, a file of a COLMAP model whose directory is made when
// missing: where the directory's own directory does not exist).
OutputTarget ResolveOutputTarget(const std::string& path, bool make_directory = false);

// The identity of the existing file `path` (symbolic links followed), or
// nullopt when there is none.
std::optional<FileIdentity> ExistingFileIdentity(const std::string& path);

// The identity `path` will have: its file's, or, when it does not exist, its
// deepest existing directory's with the rest of the path (lexically normal).
// That directory is found by the file system, the path shortened as written:
// "link/../x" is x beside the directory the link leads to.
FileIdentity PathIdentity(const std::string& path);

// Checks that the target can be written, as its writer will: for a kReplace
// target a file is created beside it and removed again (a read-only file
// system, /proc, a directory without write permission all fail here), a
// stream is checked for write permission. Throws std::runtime_error naming
// `target.path` and the system's reason. A target whose directory does not
// exist yet (a COLMAP model's) is checked at its deepest existing directory.
void CheckCreatable(const OutputTarget& target);

}  // namespace dba
