// Line-by-line reading of a text file that is either plain or bzip2-compressed.
//
// The format is detected from the content ("BZh" magic), not from the file
// name. The text comes from io/text_pieces: bzip2 blocks decoded on the
// run's threads a window ahead (docs/design.md §4.3), so memory stays
// bounded by the window and the longest line, and concatenated bzip2 streams
// (as written by `pbzip2` or `cat a.bz2 b.bz2`) are read as one text. Errors
// (unreadable file, corrupt or truncated bzip2 data, naming its byte) are
// thrown as dba::InputError naming the file and line.
//
// Not thread-safe: one reader per thread.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "dba/io/text_pieces.h"

namespace dba {

class TextLineReader {
 public:
  // Opens `path`; throws InputError when it cannot be opened or read.
  // bzip2 is decoded on `threads` threads (0: OpenMP's count, the run's -t).
  explicit TextLineReader(const std::string& path, int threads = 0);
  TextLineReader(const TextLineReader&) = delete;
  TextLineReader& operator=(const TextLineReader&) = delete;

  // Lines longer than this are refused (a file with no line ends, or not
  // text): memory stays bounded and the error comes in well under a second.
  static constexpr size_t kMaxLineBytes = size_t{64} << 20;

  // Reads the next line, without its terminator ("\n" or "\r\n"), into *line.
  // The view stays valid until the next call. Returns false at end of file.
  // A last line without a final newline is still returned (see
  // last_line_unterminated()). Throws InputError for a line over
  // kMaxLineBytes.
  bool ReadLine(std::string_view* line);
  // True when the line last returned ended at the end of the file without a
  // newline (a file cut short may end inside its last number).
  bool last_line_unterminated() const { return unterminated_; }

  // 1-based number of the line last returned by ReadLine (0 before the first).
  int64_t line_number() const { return line_; }
  // True when the file is bzip2-compressed.
  bool is_bz2() const { return source_.is_bz2(); }
  const std::string& path() const { return path_; }

 private:
  size_t Fill(char* dst, size_t cap);  // next text bytes; 0 at end
  [[noreturn]] void Fail(const std::string& what) const;

  std::string path_;
  TextPieceSource source_;
  std::shared_ptr<const TextPiece> piece_;  // the text being read
  size_t piece_at_ = 0;
  bool unterminated_ = false;

  // Decoded text; [begin_, end_) is not yet returned.
  std::vector<char> buf_;
  size_t begin_ = 0;
  size_t end_ = 0;
  bool eof_ = false;
  int64_t line_ = 0;
};

}  // namespace dba
