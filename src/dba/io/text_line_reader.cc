// Line reader over the text of io/text_pieces; see text_line_reader.h.
#include "dba/io/text_line_reader.h"

#include <omp.h>

#include <algorithm>
#include <cstring>

#include "dba/common/error.h"

namespace dba {
namespace {

constexpr size_t kInitialBuffer = size_t{1} << 20;  // decoded text buffer

}  // namespace

TextLineReader::TextLineReader(const std::string& path, int threads)
    : path_(path),
      source_(path, threads > 0 ? threads : omp_get_max_threads()),
      buf_(kInitialBuffer) {}

void TextLineReader::Fail(const std::string& what) const {
  throw InputError(path_, line_ + 1, what);
}

size_t TextLineReader::Fill(char* dst, size_t cap) {
  if (piece_ == nullptr || piece_at_ == piece_->text.size()) {
    try {
      piece_ = source_.Next();
    } catch (const TextDataError& e) {
      Fail(e.what());
    }
    piece_at_ = 0;
    if (piece_ == nullptr) return 0;
  }
  const size_t n = std::min(cap, piece_->text.size() - piece_at_);
  std::memcpy(dst, piece_->text.data() + piece_at_, n);
  piece_at_ += n;
  return n;
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
