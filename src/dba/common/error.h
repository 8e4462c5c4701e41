// Errors that reach the user: every message names where and what.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

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

}  // namespace dba
