// The reading every COLMAP text file shares (cameras, images, points3D,
// rigs, frames), not for use outside io/ (not installed): lines bounded in
// length and ending in a line end, blank-separated tokens, numbers and
// quaternions checked, each error naming the file and line. Defined in
// colmap_lines.cc.
// Not thread-safe: one LineFile per thread.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "dba/io/text_line_reader.h"
#include "dba/io/text_tokens.h"

namespace dba {
namespace colmap_internal {

// 'tok' clipped to 40 characters, quoted, for messages.
std::string Quote(std::string_view tok);

// A text file read line by line, counting lines from 1 (line length
// bounded by TextLineReader). A file must end with a line end: one cut short
// could otherwise end inside its last number and be read without error.
class LineFile {
 public:
  explicit LineFile(std::string path) : reader_(path) {}
  const std::string& path() const { return reader_.path(); }
  int64_t line_number() const { return reader_.line_number(); }

  // The next line without its line end; false at the end of the file.
  bool Next(std::string_view* line);
  // The next line that is neither empty nor a comment, trimmed.
  bool NextData(std::string_view* line);
  [[noreturn]] void Fail(const std::string& what) const;

 private:
  TextLineReader reader_;
};

// Blank-separated tokens of one line; errors name the file and line.
class Tokens {
 public:
  Tokens(const LineFile& file, std::string_view line) : file_(file), tokens_(line) {}

  bool Done() const { return tokens_.Done(); }
  std::string_view Next(const char* what);
  // Everything left on the line, trimmed.
  std::string_view Rest() const { return tokens_.Rest(); }
  // Refuses tokens left after the entry's last field.
  void End() const;
  [[noreturn]] void Fail(const std::string& what) const { file_.Fail(what); }

  double Double(const char* what);
  // A pose's QW QX QY QZ TX TY TZ, the quaternion a rotation as read
  // (IsRotationQuaternion; `what` names it in the message).
  void Pose(const char* what, std::array<double, 4>* q, std::array<double, 3>* t);
  uint64_t Unsigned(const char* what, uint64_t max);
  // A point3D_id in images.txt: -1 (or COLMAP's invalid id 2^64-1) for none.
  int64_t Point3DRef(const char* what);

 private:
  const LineFile& file_;
  LineTokens tokens_;
};

}  // namespace colmap_internal
}  // namespace dba
