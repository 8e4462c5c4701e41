// What an output path names; see output_target.h.
#include "dba/io/output_target.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "dba/common/error.h"
#include "dba/io/stale_temporaries.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

bool Under(const std::string& path, const char* dir) {
  const size_t n = std::strlen(dir);
  return path.compare(0, n, dir) == 0 && (path.size() == n || path[n] == '/');
}

// /proc, /dev/fd and /dev/std*: links to open descriptors, not to files.
bool ThroughDescriptorLinks(const std::string& path) {
  std::error_code ec;
  const std::string a = fs::absolute(path, ec).lexically_normal().string();
  return Under(a, "/proc") || Under(a, "/dev/fd") || a == "/dev/stdout" || a == "/dev/stderr" ||
         a == "/dev/stdin";
}

std::string RealPath(const std::string& path) {
  char buf[PATH_MAX];
  if (::realpath(path.c_str(), buf) == nullptr) return {};
  return buf;
}

const char* KindName(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string ParentOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// A path that does not exist: its directory must, or (`make_directory`)
// the directory that holds it.
OutputTarget NewPathTarget(const std::string& path, bool make_directory) {
  OutputTarget t{path, path, OutputMode::kReplace, PathIdentity(path)};
  const std::string parent = ParentOf(path);
  struct stat st {};
  if (::stat(parent.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
    const std::string grandparent = ParentOf(parent);
    if (!make_directory || ::stat(grandparent.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
      throw std::runtime_error(path + ": directory " +
                               (make_directory ? grandparent : parent) + " does not exist");
    }
    return t;  // written once the directory is made
  }
  const std::string real = RealPath(parent);
  if (Under(real, "/proc") || Under(real, "/sys")) {
    throw UsageError(path + ": is under " + real.substr(0, 5) +
                     ", the kernel's, where no file can be made");
  }
  if (!real.empty()) t.file = (fs::path(real) / fs::path(path).filename()).string();
  return t;
}

}  // namespace

std::optional<FileIdentity> ExistingFileIdentity(const std::string& path) {
  struct stat st {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0) return std::nullopt;
  return FileIdentity{static_cast<uint64_t>(st.st_dev), static_cast<uint64_t>(st.st_ino), {}};
}

// The path is shortened as written, never normalised first: "link/.." is
// the directory above the one the link leads to, which only the file
// system knows; only the part below the deepest existing directory (made
// of names that do not exist) is normalised.
FileIdentity PathIdentity(const std::string& path) {
  if (std::optional<FileIdentity> id = ExistingFileIdentity(path)) return *id;
  fs::path at(path), rest;
  while (!at.empty() && at.has_relative_path()) {
    rest = rest.empty() ? at.filename() : at.filename() / rest;
    at = at.parent_path();
    if (std::optional<FileIdentity> id = ExistingFileIdentity(at.empty() ? "." : at.string())) {
      id->rest = rest.lexically_normal().string();
      return *id;
    }
  }
  std::error_code ec;
  return FileIdentity{0, 0, fs::absolute(path, ec).lexically_normal().string()};
}

OutputTarget ResolveOutputTarget(const std::string& path, bool make_directory) {
  if (path.empty()) throw UsageError("an empty path names no file");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    struct stat link {};
    if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
      throw UsageError(path + ": is a symbolic link to nothing (written through, a link "
                       "must lead to a file or into a directory that exists)");
    }
    if (err != ENOENT) {
      throw std::runtime_error(path + ": " + std::strerror(err));
    }
    return NewPathTarget(path, make_directory);
  }
  const FileIdentity id{static_cast<uint64_t>(st.st_dev), static_cast<uint64_t>(st.st_ino), {}};
  if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
    return OutputTarget{path, path, OutputMode::kStream, id};
  }
  if (!S_ISREG(st.st_mode)) {
    throw UsageError(path + ": is " + KindName(st.st_mode) +
                     "; an output is a file (replaced whole), a character device or a FIFO");
  }
  const std::string real = RealPath(path);
  if (ThroughDescriptorLinks(path) || real.empty() || Under(real, "/proc") ||
      Under(real, "/sys")) {
    throw UsageError(path + ": a regular file reached through /proc or /dev/fd (an open "
                     "descriptor's link" + (real.empty() ? std::string() : " to " + real) +
                     "); name the file itself, or write to a pipe");
  }
  return OutputTarget{path, real, OutputMode::kReplace, id};
}

void CheckCreatable(const OutputTarget& target) {
  if (target.mode == OutputMode::kStream) {
    if (::access(target.file.c_str(), W_OK) != 0) {
      throw std::runtime_error(target.path + ": not writable: " + std::strerror(errno));
    }
    return;
  }
  // The deepest directory that exists: the file's own, or an ancestor of a
  // model directory still to be made.
  fs::path dir = fs::path(target.file).parent_path();
  std::error_code ec;
  while (!dir.empty() && !fs::is_directory(dir, ec)) dir = dir.parent_path();
  if (dir.empty()) dir = ".";
  // An unnamed file where the file system makes them (nothing to leave
  // behind), else a named one removed at once.
  int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
  std::string probe;
  if (fd < 0 && (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL)) {
    probe = (dir / (".dba-probe." + UniqueId())).string();
    fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  }
  if (fd < 0) {
    const int err = errno;
    throw std::runtime_error(target.path + ": cannot create a file in " + dir.string() + ": " +
                             std::strerror(err));
  }
  ::close(fd);
  if (!probe.empty()) ::unlink(probe.c_str());
}

}  // namespace dba
