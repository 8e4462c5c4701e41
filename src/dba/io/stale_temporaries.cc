// Stale temporaries and backups of outputs; see stale_temporaries.h.
#include "dba/io/stale_temporaries.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string_view>
#include <utility>
#include <vector>

#include "dba/io/replace_together.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kTemporary = ".tmp.";
constexpr std::string_view kOld = ".dba-old.";
constexpr std::string_view kMember = ".dba-member.";
constexpr std::string_view kJournal = ".dba-journal.";
constexpr std::string_view kDone = ".dba-done.";

// The pid that starts the id after `prefix` in `name` ("<pid>" or
// "<pid>.<n>"), or 0 when the rest is no such id.
pid_t PidAfter(std::string_view name, std::string_view prefix) {
  if (!name.starts_with(prefix)) return 0;
  const std::string_view id = name.substr(prefix.size());
  const std::string_view pid = id.substr(0, id.find('.'));
  const std::string_view n = pid.size() < id.size() ? id.substr(pid.size() + 1) : "0";
  for (std::string_view digits : {pid, n}) {
    if (digits.empty() || digits.size() > 18 ||
        digits.find_first_not_of("0123456789") != std::string_view::npos) {
      return 0;
    }
  }
  return pid.size() > 9 ? 0 : static_cast<pid_t>(std::atol(std::string(pid).c_str()));
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

bool Exists(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0;
}

// An old copy no journal speaks for (a kill while the copies were being
// made, or an older version's): the file was not replaced when it is the
// copy itself (a hard link), else the copy goes back.
void PutBack(const std::string& old, const std::string& file) {
  struct stat a {}, b {};
  if (::stat(old.c_str(), &a) == 0 && ::stat(file.c_str(), &b) == 0 && a.st_dev == b.st_dev &&
      a.st_ino == b.st_ino) {
    ::unlink(old.c_str());
  } else {
    ::rename(old.c_str(), file.c_str());
  }
}

// A replacement `file` took part in: undone or finished from its journal
// (beside the replacement's first file, where the member link leads).
void RecoverReplacement(const std::string& file, std::string_view kind, const std::string& id) {
  if (kind != kMember) {
    UndoOrFinishReplacement(file, id);  // `file` is the first: the journal is beside it
    return;
  }
  const std::string member = file + std::string(kMember) + id;
  std::error_code ec;
  const fs::path first = fs::read_symlink(member, ec);
  if (!ec) UndoOrFinishReplacement(first.string(), id);
  ::unlink(member.c_str());  // gone already, unless its journal was
}

}  // namespace

std::string UniqueId() {
  static std::atomic<uint64_t> next{0};
  return std::to_string(::getpid()) + "." + std::to_string(next.fetch_add(1));
}

std::string TemporaryName(const std::string& file) {
  return file + std::string(kTemporary) + UniqueId();
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

// First the replacements (their journals undo or finish every file of
// them), then the old copies no journal speaks for, then the temporaries.
int RecoverStaleTemporaries(const std::string& file) {
  const fs::path p(file);
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
  const std::string base = p.filename().string();
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return 0;
  std::vector<std::pair<std::string_view, std::string>> replacements;  // kind, id
  std::vector<std::string> olds, temporaries;
  while (const dirent* e = ::readdir(d)) {
    const std::string_view name(e->d_name);
    if (!name.starts_with(base)) continue;
    const std::string_view rest = name.substr(base.size());
    for (std::string_view kind : {kJournal, kDone, kMember}) {
      if (ProcessIsGone(PidAfter(rest, kind))) {
        replacements.emplace_back(kind, std::string(rest.substr(kind.size())));
      }
    }
    if (ProcessIsGone(PidAfter(rest, kOld))) olds.emplace_back(name);
    if (ProcessIsGone(PidAfter(rest, kTemporary))) temporaries.emplace_back(name);
  }
  ::closedir(d);
  const std::string path = (fs::path(dir) / base).string();
  for (const auto& [kind, id] : replacements) RecoverReplacement(path, kind, id);
  int found = static_cast<int>(replacements.size());
  for (const std::string& name : olds) {
    const std::string old = (fs::path(dir) / name).string();
    if (!Exists(old)) continue;  // put back or removed with its replacement
    PutBack(old, path);
    ++found;
  }
  for (const std::string& name : temporaries) {
    const std::string tmp = (fs::path(dir) / name).string();
    if (Exists(tmp) && Unlocked(tmp) && ::unlink(tmp.c_str()) == 0) ++found;
  }
  return found;
}

}  // namespace dba
