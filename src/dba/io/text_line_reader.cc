// Streaming line reader over plain or bzip2 text; see text_line_reader.h.
#include "dba/io/text_line_reader.h"

#include <bzlib.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>

#include "dba/common/error.h"

namespace dba {

struct TextLineReader::Stream {
  bz_stream s{};
};

TextLineReader::Stream& TextLineReader::strm() { return *stream_; }

namespace {

constexpr size_t kInputChunk = size_t{1} << 18;  // raw bytes per fread
constexpr size_t kInitialBuffer = size_t{1} << 20;  // decoded text buffer

std::string Bz2ErrorText(int code) {
  switch (code) {
    case BZ_DATA_ERROR: return "corrupt bzip2 data (checksum or format error)";
    case BZ_DATA_ERROR_MAGIC: return "corrupt bzip2 data (bad stream header)";
    case BZ_MEM_ERROR: return "out of memory while decompressing bzip2 data";
    default: return "bzip2 decompression failed (libbz2 error " +
                    std::to_string(code) + ")";
  }
}

}  // namespace

TextLineReader::TextLineReader(const std::string& path)
    : path_(path), in_(kInputChunk), stream_(std::make_unique<Stream>()), buf_(kInitialBuffer) {
  file_ = std::fopen(path.c_str(), "rb");
  if (file_ == nullptr) {
    throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  }
  try {
    RefillInput();
  } catch (...) {
    std::fclose(file_);
    throw;
  }
  bz2_ = strm().s.avail_in >= 3 && std::memcmp(strm().s.next_in, "BZh", 3) == 0;
}

TextLineReader::~TextLineReader() {
  if (in_stream_) BZ2_bzDecompressEnd(&strm().s);
  if (file_ != nullptr) std::fclose(file_);
}

void TextLineReader::Fail(const std::string& what) const {
  throw InputError(path_, line_ + 1, what);
}

void TextLineReader::RefillInput() {
  size_t n = std::fread(in_.data(), 1, in_.size(), file_);
  if (n < in_.size()) {
    if (std::ferror(file_)) Fail(std::string("read error: ") + std::strerror(errno));
    in_eof_ = true;
  }
  strm().s.next_in = in_.data();
  strm().s.avail_in = static_cast<unsigned>(n);
}

size_t TextLineReader::Fill(char* dst, size_t cap) {
  cap = std::min<size_t>(cap, UINT_MAX);
  if (!bz2_) {
    if (strm().s.avail_in == 0 && !in_eof_) RefillInput();
    size_t n = std::min<size_t>(cap, strm().s.avail_in);
    std::memcpy(dst, strm().s.next_in, n);
    strm().s.next_in += n;
    strm().s.avail_in -= static_cast<unsigned>(n);
    return n;
  }
  for (;;) {
    if (strm().s.avail_in == 0 && !in_eof_) RefillInput();
    if (!in_stream_) {
      if (strm().s.avail_in == 0) return 0;  // every stream complete, end of file
      strm().s.bzalloc = nullptr;
      strm().s.bzfree = nullptr;
      strm().s.opaque = nullptr;
      int rc = BZ2_bzDecompressInit(&strm().s, 0, 0);
      if (rc != BZ_OK) Fail(Bz2ErrorText(rc));
      in_stream_ = true;
    }
    strm().s.next_out = dst;
    strm().s.avail_out = static_cast<unsigned>(cap);
    int rc = BZ2_bzDecompress(&strm().s);
    size_t produced = cap - strm().s.avail_out;
    if (rc == BZ_STREAM_END) {
      BZ2_bzDecompressEnd(&strm().s);
      in_stream_ = false;
      stream_ended_ = true;
    } else if (rc == BZ_DATA_ERROR_MAGIC && stream_ended_) {
      Fail("trailing data after the bzip2 stream is not bzip2");
    } else if (rc != BZ_OK) {
      Fail(Bz2ErrorText(rc));
    } else if (produced == 0 && strm().s.avail_in == 0 && in_eof_) {
      Fail("truncated bzip2 data: unexpected end of file inside a stream");
    }
    if (produced > 0) return produced;
  }
}

bool TextLineReader::ReadLine(std::string_view* line) {
  size_t scan = begin_;  // bytes before `scan` are known to hold no '\n'
  for (;;) {
    const char* base = buf_.data();
    const void* nl = std::memchr(base + scan, '\n', end_ - scan);
    size_t len;
    if (nl != nullptr) {
      len = static_cast<const char*>(nl) - (base + begin_);
      unterminated_ = false;
    } else if (eof_) {
      if (begin_ == end_) return false;
      len = end_ - begin_;
      unterminated_ = true;
    } else {
      if (end_ - begin_ > kMaxLineBytes) {
        Fail("line longer than " + std::to_string(kMaxLineBytes >> 20) +
             " MiB (no line end: not a text problem file?)");
      }
      // Keep the partial line at the front, grow if it fills the buffer.
      size_t partial = end_ - begin_;
      std::memmove(buf_.data(), base + begin_, partial);
      begin_ = 0;
      end_ = partial;
      scan = partial;
      if (end_ == buf_.size()) buf_.resize(2 * buf_.size());
      size_t n = Fill(buf_.data() + end_, buf_.size() - end_);
      if (n == 0) eof_ = true;
      end_ += n;
      continue;
    }
    std::string_view view(base + begin_, len);
    begin_ = std::min(end_, begin_ + len + 1);
    if (!view.empty() && view.back() == '\r') view.remove_suffix(1);
    *line = view;
    ++line_;
    return true;
  }
}

}  // namespace dba
