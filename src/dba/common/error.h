// Errors that reach the user: every message names where and what.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace dba {

// Bad input data: names the file, the line (0 when not line-based) and what
// was expected there.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, int64_t line, const std::string& what)
      : std::runtime_error(Format(file, line, what)), file_(file), line_(line) {}

  const std::string& file() const { return file_; }
  int64_t line() const { return line_; }

 private:
  static std::string Format(const std::string& file, int64_t line,
                            const std::string& what) {
    std::string s = file;
    if (line > 0) {
      s += ':';
      s += std::to_string(line);
    }
    s += ": ";
    s += what;
    return s;
  }
  std::string file_;
  int64_t line_;
};

// An argument that does not fit the input, found after the input was read
// (an image id the problem does not have, an option for another kind of
// input, an output that would overwrite an input or another output): like a
// parse error, exit status 2.
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// `text` for a message: whole when short, else its start and its length
// (a 60 MB field is not echoed whole).
inline std::string Clipped(std::string_view text, size_t max = 80) {
  if (text.size() <= max) return std::string(text);
  return std::string(text.substr(0, max)) + "... (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace dba
