// Several files replaced together through a journal; see replace_together.h.
#include "dba/io/replace_together.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "dba/io/stale_temporaries.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

constexpr const char* kHeader = "dba-replace-together 1\n";

std::string Old(const std::string& file, const std::string& id) { return file + ".dba-old." + id; }
std::string Member(const std::string& file, const std::string& id) {
  return file + ".dba-member." + id;
}
std::string Journal(const std::string& first, const std::string& id) {
  return first + ".dba-journal." + id;
}
std::string Done(const std::string& first, const std::string& id) {
  return first + ".dba-done." + id;
}

// One file of the journal: whether it had an old version, its temporary's
// inode (what it is once renamed), both absolute paths.
struct Entry {
  bool had_old = false;
  uint64_t dev = 0, ino = 0;
  std::string file, tmp;
};

std::string Reason(const std::string& path, const std::string& what, int err) {
  std::string message = path + ": " + what;
  if (err != 0) message += std::string(": ") + std::strerror(err);
  return message;
}

// As written, made absolute (never normalised: "link/.." is the file
// system's to resolve).
std::string Absolute(const std::string& path) {
  std::error_code ec;
  return fs::absolute(path, ec).string();
}

// The file's identity is the temporary's: the rename was done.
bool Renamed(const Entry& e) {
  struct stat st {};
  return ::stat(e.file.c_str(), &st) == 0 && static_cast<uint64_t>(st.st_dev) == e.dev &&
         static_cast<uint64_t>(st.st_ino) == e.ino;
}

std::string Serialize(const std::vector<Entry>& entries) {
  std::ostringstream s;
  s << kHeader;
  for (const Entry& e : entries) {
    s << (e.had_old ? 1 : 0) << ' ' << e.dev << ' ' << e.ino << ' ' << e.file.size() << ' '
      << e.tmp.size() << '\n'
      << e.file << e.tmp << '\n';
  }
  s << "end\n";
  return s.str();
}

// The journal's entries, or nothing when it is not whole (a kill while it
// was written: nothing was renamed yet).
std::optional<std::vector<Entry>> Parse(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!text.starts_with(kHeader) || !text.ends_with("\nend\n")) return std::nullopt;
  std::istringstream s(text.substr(std::strlen(kHeader)));
  std::vector<Entry> entries;
  while (s.peek() != 'e') {
    Entry e;
    size_t file_size = 0, tmp_size = 0;
    if (!(s >> e.had_old >> e.dev >> e.ino >> file_size >> tmp_size) || s.get() != '\n' ||
        file_size > text.size() || tmp_size > text.size()) {
      return std::nullopt;
    }
    e.file.resize(file_size);
    e.tmp.resize(tmp_size);
    if (!s.read(e.file.data(), file_size) || !s.read(e.tmp.data(), tmp_size) || s.get() != '\n') {
      return std::nullopt;
    }
    entries.push_back(std::move(e));
  }
  return entries;
}

void WriteJournal(const std::string& path, const std::vector<Entry>& entries) {
  const std::string text = Serialize(entries);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  const bool ok = fd >= 0 && ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) &&
                  ::fsync(fd) == 0;
  const int err = errno;
  if (fd >= 0) ::close(fd);
  if (!ok) {
    ::unlink(path.c_str());
    throw std::runtime_error(Reason(path, "cannot write the journal of a replacement", err));
  }
}

// Puts every file back as it was before the replacement `id` and removes
// what it made: a file that is its temporary gets its old copy back (or,
// new, goes); the temporaries left, old copies and member links go.
void Undo(const std::vector<Entry>& entries, const std::string& id) {
  for (const Entry& e : entries) {
    const std::string old = Old(e.file, id);
    if (!Renamed(e)) {
      ::unlink(e.tmp.c_str());
      ::unlink(old.c_str());
    } else if (e.had_old) {
      std::rename(old.c_str(), e.file.c_str());
    } else {
      ::unlink(e.file.c_str());
    }
  }
  for (const Entry& e : entries) ::unlink(Member(e.file, id).c_str());
}

// DBA_KILL_IN_COMMIT=N (tests): SIGKILL after the N-th step.
class KillHook {
 public:
  KillHook() {
    if (const char* n = std::getenv("DBA_KILL_IN_COMMIT")) kill_at_ = std::atoi(n);
  }
  void Step() {
    if (++step_ == kill_at_) ::raise(SIGKILL);
  }

 private:
  int kill_at_ = 0, step_ = 0;
};

// After the commit: each file's old copy, then its member link, go.
void Finish(const std::vector<Entry>& entries, const std::string& id, KillHook* hook = nullptr) {
  for (const Entry& e : entries) {
    ::unlink(Old(e.file, id).c_str());
    ::unlink(Member(e.file, id).c_str());
    if (hook != nullptr) hook->Step();
  }
}

// Step 1: the entries, each old file kept under its old-copy name (a hard
// link, or where the file system has none, a copy). On failure the copies
// made and every temporary are removed.
std::vector<Entry> KeepOldFiles(const std::vector<Replacement>& files, const std::string& id) {
  std::vector<Entry> entries;
  try {
    for (const Replacement& r : files) {
      Entry e{false, 0, 0, Absolute(r.file), Absolute(r.tmp)};
      struct stat st {};
      if (::stat(e.tmp.c_str(), &st) != 0) {
        const int err = errno;
        throw std::runtime_error(Reason(r.file, "its temporary '" + r.tmp + "' is gone", err));
      }
      e.dev = static_cast<uint64_t>(st.st_dev);
      e.ino = static_cast<uint64_t>(st.st_ino);
      if (::lstat(e.file.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
        const std::string old = Old(e.file, id);
        if (::link(e.file.c_str(), old.c_str()) != 0) {
          std::error_code ec;
          fs::copy_file(e.file, old, ec);
          if (ec) {
            throw std::runtime_error(Reason(r.file, "cannot keep a copy while replacing it", ec.value()));
          }
        }
        e.had_old = true;
      }
      entries.push_back(std::move(e));
    }
  } catch (const std::runtime_error&) {
    for (const Replacement& r : files) {
      ::unlink(Old(Absolute(r.file), id).c_str());
      ::unlink(r.tmp.c_str());
    }
    throw;
  }
  return entries;
}

// Steps 2 and 3: the journal and the member links. On failure, undone.
void WriteJournalAndLinks(const std::vector<Entry>& entries, const std::string& id) {
  const std::string& first = entries[0].file;
  try {
    WriteJournal(Journal(first, id), entries);
    for (const Entry& e : entries) {
      const std::string member = Member(e.file, id);
      if (::symlink(first.c_str(), member.c_str()) != 0) {
        const int err = errno;
        throw std::runtime_error(Reason(member, "cannot make the replacement's link", err));
      }
    }
  } catch (const std::runtime_error&) {
    Undo(entries, id);
    ::unlink(Journal(first, id).c_str());
    throw;
  }
}

// A rename that failed (step 4, or the commit): everything undone, and the
// error names the files put back.
[[noreturn]] void FailAndUndo(const std::vector<Entry>& entries, const std::string& id,
                              size_t failed, const std::string& what, int err) {
  Undo(entries, id);
  ::unlink(Journal(entries[0].file, id).c_str());
  std::string undone;
  for (size_t j = 0; j < failed && j < entries.size(); ++j) {
    undone += (undone.empty() ? "" : ", ") + entries[j].file;
  }
  const std::string& file = entries[std::min(failed, entries.size() - 1)].file;
  throw std::runtime_error(Reason(file, what, err) +
                           (undone.empty() ? "" : " (put back as they were: " + undone + ")"));
}

}  // namespace

void ReplaceTogether(const std::vector<Replacement>& files) {
  if (files.empty()) return;
  if (files.size() == 1) {  // one rename: nothing to keep together
    const Replacement& r = files[0];
    if (std::rename(r.tmp.c_str(), r.file.c_str()) != 0) {
      const int err = errno;
      ::unlink(r.tmp.c_str());
      throw std::runtime_error(Reason(r.file, "cannot rename '" + r.tmp + "' over it", err));
    }
    return;
  }
  const std::string id = UniqueId();
  const std::vector<Entry> entries = KeepOldFiles(files, id);
  WriteJournalAndLinks(entries, id);
  KillHook hook;
  hook.Step();
  for (size_t i = 0; i < entries.size(); ++i) {
    if (std::rename(entries[i].tmp.c_str(), entries[i].file.c_str()) != 0) {
      const int err = errno;
      FailAndUndo(entries, id, i, "cannot rename '" + files[i].tmp + "' over it", err);
    }
    hook.Step();
  }
  const std::string& first = entries[0].file;
  if (std::rename(Journal(first, id).c_str(), Done(first, id).c_str()) != 0) {
    const int err = errno;
    FailAndUndo(entries, id, entries.size(), "cannot commit the replacement", err);
  }
  hook.Step();
  Finish(entries, id, &hook);
  ::unlink(Done(first, id).c_str());
}

void UndoOrFinishReplacement(const std::string& first_file, const std::string& id) {
  const std::string journal = Journal(first_file, id), done = Done(first_file, id);
  if (std::optional<std::vector<Entry>> entries = Parse(journal)) {
    Undo(*entries, id);
    ::unlink(journal.c_str());
  } else if (std::optional<std::vector<Entry>> finished = Parse(done)) {
    Finish(*finished, id);
    ::unlink(done.c_str());
  } else {
    ::unlink(journal.c_str());  // not whole: written when the kill came, nothing renamed
  }
}

}  // namespace dba
