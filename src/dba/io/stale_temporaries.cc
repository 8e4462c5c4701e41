// Stale temporaries and backups of outputs; see stale_temporaries.h.
#include "dba/io/stale_temporaries.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string_view>
#include <vector>

namespace dba {
namespace {

constexpr std::string_view kTemporary = ".tmp.";
constexpr std::string_view kBackup = ".dba-old.";

// The pid after `prefix` in `name`, or 0 when the rest is not a number.
pid_t PidAfter(std::string_view name, std::string_view prefix) {
  if (!name.starts_with(prefix) || name.size() == prefix.size()) return 0;
  const std::string_view digits = name.substr(prefix.size());
  if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string_view::npos) {
    return 0;
  }
  return static_cast<pid_t>(std::atol(std::string(digits).c_str()));
}

bool ProcessIsGone(pid_t pid) {
  return pid > 0 && pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}

// Nobody holds the temporary's lock (a writer on another machine would).
bool Unlocked(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return false;
  const bool free = ::flock(fd, LOCK_EX | LOCK_NB) == 0 || errno == ENOLCK;
  ::close(fd);
  return free;
}

void PutBack(const std::string& backup, const std::string& file) {
  struct stat a {}, b {};
  if (::stat(backup.c_str(), &a) == 0 && ::stat(file.c_str(), &b) == 0 &&
      a.st_dev == b.st_dev && a.st_ino == b.st_ino) {
    ::unlink(backup.c_str());  // not replaced yet: the old file is still there
  } else {
    ::rename(backup.c_str(), file.c_str());
  }
}

}  // namespace

std::string TemporaryName(const std::string& file) {
  return file + std::string(kTemporary) + std::to_string(::getpid());
}

std::string BackupName(const std::string& file) {
  return file + std::string(kBackup) + std::to_string(::getpid());
}

int LockTemporary(const std::string& tmp) {
  const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return -1;
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

int RecoverStaleTemporaries(const std::string& file) {
  namespace fs = std::filesystem;
  const fs::path p(file);
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
  const std::string base = p.filename().string();
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return 0;
  std::vector<std::string> temporaries, backups;
  while (const dirent* e = ::readdir(d)) {
    const std::string_view name(e->d_name);
    if (!name.starts_with(base)) continue;
    const std::string_view rest = name.substr(base.size());
    if (ProcessIsGone(PidAfter(rest, kTemporary))) temporaries.emplace_back(name);
    if (ProcessIsGone(PidAfter(rest, kBackup))) backups.emplace_back(name);
  }
  ::closedir(d);
  int found = 0;
  for (const std::string& name : temporaries) {
    const std::string path = (fs::path(dir) / name).string();
    if (Unlocked(path) && ::unlink(path.c_str()) == 0) ++found;
  }
  for (const std::string& name : backups) {
    PutBack((fs::path(dir) / name).string(), file);
    ++found;
  }
  return found;
}

}  // namespace dba
