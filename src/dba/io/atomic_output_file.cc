// Atomic output files; see atomic_output_file.h.
#include "dba/io/atomic_output_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "dba/io/replace_together.h"
#include "dba/io/stale_temporaries.h"
#include "dba/io/temporary_registry.h"

namespace dba {
namespace {

thread_local OutputTransaction* current_transaction = nullptr;

std::string Reason(const std::string& path, const std::string& what, int err) {
  std::string message = path + ": " + what;
  if (err != 0) message += std::string(": ") + std::strerror(err);
  return message;
}

// The new file takes the mode (and, where allowed, the owner) of the file
// it replaces: a private file stays private.
void KeepModeOf(const std::string& file, int fd) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) return;
  ::fchmod(fd, st.st_mode & 07777);
  if (::fchown(fd, st.st_uid, st.st_gid) != 0) {
    // Not the owner: the replacement is ours, as any new file would be.
  }
}

void Release(OutputTransaction::Pending& p) {
  if (p.lock_fd >= 0) ::close(p.lock_fd);
  p.lock_fd = -1;
  UnregisterTemporary(p.registry_slot);
  p.registry_slot = -1;
}

// SIGINT, SIGTERM and SIGHUP wait while files are being swapped: their
// handler would remove the backups a failed rename needs.
class SignalsHeld {
 public:
  SignalsHeld() {
    sigset_t set;
    sigemptyset(&set);
    for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, s);
    ::pthread_sigmask(SIG_BLOCK, &set, &old_);
  }
  ~SignalsHeld() { ::pthread_sigmask(SIG_SETMASK, &old_, nullptr); }

 private:
  sigset_t old_;
};

// Renames every temporary over its file, all or none, even across a kill
// (io/replace_together.h), with SIGINT, SIGTERM and SIGHUP held.
void ReplaceAll(std::vector<OutputTransaction::Pending>& pending) {
  if (pending.empty()) return;
  const SignalsHeld held;
  std::vector<Replacement> files;
  for (const auto& p : pending) files.push_back({p.tmp, p.file});
  try {
    ReplaceTogether(files);
  } catch (const std::runtime_error&) {
    for (auto& p : pending) Release(p);
    throw;
  }
  for (auto& p : pending) Release(p);
}

}  // namespace

AtomicOutputFile::AtomicOutputFile(const std::string& path)
    : path_(path), target_(ResolveOutputTarget(path)) {
  if (target_.mode == OutputMode::kStream) {
    const int fd = ::open(target_.file.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
    if (fd < 0 || (file_ = ::fdopen(fd, "wb")) == nullptr) {
      const int err = errno;
      if (fd >= 0) ::close(fd);
      Fail("cannot open for writing", err);
    }
    std::setvbuf(file_, nullptr, _IOFBF, size_t{1} << 20);
    return;
  }
  RecoverStaleTemporaries(target_.file);
  tmp_ = TemporaryName(target_.file);
  registry_slot_ = RegisterTemporary(tmp_);
  const int fd = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0 || (file_ = ::fdopen(fd, "wb")) == nullptr) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    ::unlink(tmp_.c_str());
    UnregisterTemporary(registry_slot_);
    registry_slot_ = -1;
    Fail("cannot create '" + tmp_ + "'", err);
  }
  lock_fd_ = LockTemporary(tmp_);
  KeepModeOf(target_.file, fd);
  std::setvbuf(file_, nullptr, _IOFBF, size_t{1} << 20);
}

AtomicOutputFile::~AtomicOutputFile() {
  if (file_ != nullptr) std::fclose(file_);
  if (!committed_ && !tmp_.empty()) ::unlink(tmp_.c_str());
  if (lock_fd_ >= 0) ::close(lock_fd_);
  UnregisterTemporary(registry_slot_);
}

void AtomicOutputFile::Fail(const std::string& what, int err) const {
  throw std::runtime_error(Reason(path_, what, err));
}

void AtomicOutputFile::Write(const void* data, size_t size) {
  if (std::fwrite(data, 1, size, file_) != size) Fail("write failed", errno);
}

void AtomicOutputFile::Finish() {
  errno = 0;
  if (std::fflush(file_) != 0) Fail("write failed", errno);
  if (seekable() && ::fsync(::fileno(file_)) != 0) Fail("fsync failed", errno);
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) Fail("close failed", errno);
}

void AtomicOutputFile::Rename() {
  if (!seekable()) {
    committed_ = true;  // a stream is written in place
    return;
  }
  OutputTransaction::Pending p{tmp_, target_.file, registry_slot_, lock_fd_};
  if (OutputTransaction* t = OutputTransaction::Current()) {
    t->Add(std::move(p));
  } else {
    std::vector<OutputTransaction::Pending> one{std::move(p)};
    try {
      ReplaceAll(one);
    } catch (const std::runtime_error&) {
      registry_slot_ = lock_fd_ = -1;  // released by ReplaceAll
      throw;
    }
  }
  registry_slot_ = lock_fd_ = -1;  // the transaction's now, or released
  committed_ = true;
}

void CommitTogether(std::initializer_list<AtomicOutputFile*> files) {
  for (AtomicOutputFile* f : files) f->Finish();
  OutputTransaction together;  // nested in the run's, when one is open
  for (AtomicOutputFile* f : files) f->Rename();
  together.Commit();
}

void WriteFileAtomically(const std::string& path, std::string_view contents) {
  AtomicOutputFile out(path);
  out.Write(contents);
  out.Commit();
}

OutputTransaction::OutputTransaction() : outer_(current_transaction) {
  current_transaction = this;
}

OutputTransaction::~OutputTransaction() {
  current_transaction = outer_;
  for (Pending& p : pending_) {
    ::unlink(p.tmp.c_str());
    Release(p);
  }
}

OutputTransaction* OutputTransaction::Current() { return current_transaction; }

void OutputTransaction::Commit() {
  current_transaction = outer_;
  std::vector<Pending> pending;
  pending.swap(pending_);
  if (outer_ != nullptr) {
    for (Pending& p : pending) outer_->Add(std::move(p));
    return;
  }
  ReplaceAll(pending);
}

}  // namespace dba
