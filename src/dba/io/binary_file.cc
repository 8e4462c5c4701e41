// A binary file being read; see binary_file.h.
#include "dba/io/binary_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "dba/common/error.h"
#include "dba/common/memory.h"

namespace dba {
namespace {

static_assert(std::endian::native == std::endian::little,
              "dba's binary formats (.dba, COLMAP .bin) assume a little-endian host");

constexpr size_t kBufferSize = size_t{1} << 20;

}  // namespace

BinaryFile::BinaryFile(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY);
  if (fd_ < 0) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  const off_t end = ::lseek(fd_, 0, SEEK_END);
  if (end < 0) {
    const int err = errno;
    ::close(fd_);
    throw InputError(path, 0, std::string("cannot seek: ") + std::strerror(err));
  }
  size_ = static_cast<uint64_t>(end);
}

BinaryFile::~BinaryFile() { ::close(fd_); }

[[noreturn]] void BinaryFile::FailRead(int64_t offset, const char* what, long n) const {
  throw InputError(path_, 0,
                   std::string("truncated or unreadable while reading ") + what + " at byte " +
                       std::to_string(offset) +
                       (n < 0 ? std::string(": ") + std::strerror(errno) : ""));
}

int64_t BinaryFile::ReadDirectAt(int64_t offset, char* data, int64_t bytes) const {
#ifdef O_DIRECT
  // Whole blocks of kDirectAlign at aligned file offsets into an aligned
  // buffer, each chunk's part in [offset, offset + bytes) copied out. The
  // file is the one open as fd_ (reopened through /proc, not by its path,
  // which may name another file by now).
  constexpr int64_t kDirectAlign = 4096;
  constexpr int64_t kChunk = int64_t{32} << 20;
  const std::string self = "/proc/self/fd/" + std::to_string(fd_);
  const int fd = ::open(self.c_str(), O_RDONLY | O_DIRECT);
  if (fd < 0) return 0;
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  // On huge pages: taken afresh at each call (glibc maps a block this size).
  void* raw = std::aligned_alloc(size_t{2} << 20, kChunk);
  if (raw == nullptr) return 0;
  std::unique_ptr<char, decltype(&std::free)> buffer(static_cast<char*>(raw), &std::free);
  AdviseHugePages(raw, kChunk);
  const int64_t end = offset + bytes;
  int64_t at = offset / kDirectAlign * kDirectAlign;
  while (at < end) {
    const int64_t want = std::min(kChunk, (end - at + kDirectAlign - 1) / kDirectAlign * kDirectAlign);
    const ssize_t n = ::pread(fd, buffer.get(), static_cast<size_t>(want), at);
    if (n < 0 && errno == EINTR) continue;
    const int64_t from = std::max(at, offset);
    // Refused (the file system takes no direct reads), failed, at the end,
    // or short: what is left goes through the buffered path.
    if (n <= 0 || at + n <= from) break;
    const int64_t to = std::min(at + static_cast<int64_t>(n), end);
    std::memcpy(data + (from - offset), buffer.get() + (from - at), static_cast<size_t>(to - from));
    at += n;
    if (n % kDirectAlign != 0) break;
  }
  return std::clamp<int64_t>(at - offset, 0, bytes);
#else
  (void)offset, (void)data, (void)bytes;
  return 0;
#endif
}

void BinaryFile::ReadAt(int64_t offset, void* data, int64_t bytes, const char* what) const {
  char* p = static_cast<char*>(data);
  constexpr int64_t kDirectBytes = int64_t{64} << 20;
  if (bytes >= kDirectBytes) {
    const int64_t done = ReadDirectAt(offset, p, bytes);
    p += done, offset += done, bytes -= done;
  }
  while (bytes > 0) {
    const ssize_t n =
        ::pread(fd_, p, static_cast<size_t>(std::min<int64_t>(bytes, 1 << 30)), offset);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) FailRead(offset, what, n);
    p += n;
    offset += n;
    bytes -= n;
  }
}

void BinaryFile::Fail(const std::string& what) const {
  throw InputError(path_, 0, "at byte " + std::to_string(offset_) + ": " + what);
}

std::string BinaryFile::Entry() const {
  if (kind_ == nullptr) return "";
  std::string s = std::string(kind_) + " #" + std::to_string(index_);
  if (has_id_) s += " (id " + std::to_string(id_) + ")";
  return s + " ";
}

void BinaryFile::Refill() {
  if (!buffer_) buffer_.reset(new char[kBufferSize]);
  pos_ = 0;
  end_ = 0;
  const size_t want = static_cast<size_t>(std::min<uint64_t>(kBufferSize, remaining()));
  while (end_ < want) {
    const ssize_t n = ::pread(fd_, buffer_.get() + end_, want - end_,
                              static_cast<off_t>(offset_ + end_));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) Fail("read error or file shrank while reading");
    end_ += static_cast<size_t>(n);
  }
}

void BinaryFile::Read(void* out, size_t n, const char* what) {
  if (n > remaining()) {
    Fail("file truncated: " + Entry() + what + " needs " + std::to_string(n) + " bytes, only " +
         std::to_string(remaining()) + " left (file size " + std::to_string(size_) + ")");
  }
  char* dst = static_cast<char*>(out);
  while (n > 0) {
    if (pos_ == end_) Refill();
    const size_t k = std::min(n, end_ - pos_);
    std::memcpy(dst, buffer_.get() + pos_, k);
    pos_ += k, dst += k, n -= k, offset_ += k;
  }
}

std::string BinaryFile::String(const char* what) {
  std::string s;
  for (;;) {
    if (remaining() == 0) Fail("file truncated: " + Entry() + what + " has no terminating NUL byte");
    if (pos_ == end_) Refill();
    const char* begin = buffer_.get() + pos_;
    const void* nul = std::memchr(begin, '\0', end_ - pos_);
    const size_t k = nul != nullptr ? static_cast<const char*>(nul) - begin : end_ - pos_;
    s.append(begin, k);
    pos_ += k, offset_ += k;
    if (nul != nullptr) {
      ++pos_, ++offset_;
      return s;
    }
  }
}

uint64_t BinaryFile::Count(const char* what, uint64_t entry_bytes) {
  const uint64_t at = offset_;
  const uint64_t n = Get<uint64_t>(what);
  if (entry_bytes > 0 && n > remaining() / entry_bytes) {
    throw InputError(path_, 0,
                     "at byte " + std::to_string(at) + ": " + Entry() + what + " is " +
                         std::to_string(n) + " but only " + std::to_string(remaining()) +
                         " bytes follow (at least " + std::to_string(entry_bytes) +
                         " per entry): file truncated or corrupt");
  }
  return n;
}

void BinaryFile::ExpectEnd(const char* after) {
  kind_ = nullptr;
  if (remaining() != 0) Fail(std::to_string(remaining()) + " unexpected bytes after " + after);
}

}  // namespace dba
