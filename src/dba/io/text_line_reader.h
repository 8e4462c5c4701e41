// Line-by-line reading of a text file that is either plain or bzip2-compressed.
//
// The format is detected from the content ("BZh" magic), not from the file
// name. bzip2 data is decompressed in a streaming fashion (fixed-size chunks
// through BZ2_bzDecompress), so memory stays bounded by the longest line, and
// concatenated bzip2 streams (as written by `pbzip2` or `cat a.bz2 b.bz2`) are
// read as one text. Errors (unreadable file, corrupt or truncated bzip2 data)
// are thrown as dba::InputError naming the file and line.
//
// Not thread-safe: one reader per thread.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace dba {

class TextLineReader {
 public:
  // Opens `path`; throws InputError when it cannot be opened or read.
  explicit TextLineReader(const std::string& path);
  ~TextLineReader();
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
  bool is_bz2() const { return bz2_; }
  const std::string& path() const { return path_; }

 private:
  void RefillInput();                  // next raw chunk of the file
  size_t Fill(char* dst, size_t cap);  // next decoded bytes; 0 at end
  [[noreturn]] void Fail(const std::string& what) const;

  std::string path_;
  FILE* file_ = nullptr;
  bool unterminated_ = false;
  bool bz2_ = false;

  // Raw bytes from the file; the stream's next_in / avail_in mark the unread part
  // (also in plain mode, for the bytes read while sniffing the magic).
  std::vector<char> in_;
  bool in_eof_ = false;
  struct Stream;                  // libbz2's bz_stream, kept out of this header
  std::unique_ptr<Stream> stream_;
  Stream& strm();
  bool in_stream_ = false;      // strm_ is initialised for decompression
  bool stream_ended_ = false;   // at least one bzip2 stream was completed

  // Decoded text; [begin_, end_) is not yet returned.
  std::vector<char> buf_;
  size_t begin_ = 0;
  size_t end_ = 0;
  bool eof_ = false;
  int64_t line_ = 0;
};

}  // namespace dba
