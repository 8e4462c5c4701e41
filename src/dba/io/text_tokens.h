// The lexing both text formats share (BAL, COLMAP's .txt): blank-separated
// tokens of one line, and numbers parsed exactly (std::from_chars: no locale,
// no silent truncation), a leading '+' allowed. Each reader words its own
// messages from the status (they name file, line and what was expected).
// Thread safety: pure functions and values.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dba {

// Space, tab, CR, VT, FF (LF ends the line before tokens are read).
inline bool IsBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// A blank or a line end: what separates tokens in a text read whole.
inline bool IsSeparator(char c) { return IsBlank(c) || c == '\n'; }

// What a reader of text in pieces needs of each piece before parsing it in
// parallel (io/bal_parallel_reader): its tokens (separated by IsSeparator;
// a piece starting with a non-separator counts one there), its line ends,
// and where its first and last separator and line end are (npos: none).
struct TextCounts {
  int64_t tokens = 0;
  int64_t newlines = 0;
  size_t first_separator = std::string_view::npos;
  size_t last_separator = std::string_view::npos;
  size_t first_newline = std::string_view::npos;
  size_t last_newline = std::string_view::npos;
};
TextCounts CountText(std::string_view text);

inline std::string_view TrimBlanks(std::string_view s) {
  while (!s.empty() && IsBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsBlank(s.back())) s.remove_suffix(1);
  return s;
}

// The tokens of one line, consumed from the front.
class LineTokens {
 public:
  LineTokens() = default;
  explicit LineTokens(std::string_view line) : rest_(line) {}
  // The next token; false when the line has no more.
  bool Next(std::string_view* token) {
    SkipBlanks();
    if (rest_.empty()) return false;
    size_t n = 0;
    while (n < rest_.size() && !IsBlank(rest_[n])) ++n;
    *token = rest_.substr(0, n);
    rest_.remove_prefix(n);
    return true;
  }
  // Tokens not yet consumed.
  int Remaining() const {
    LineTokens copy = *this;
    int n = 0;
    std::string_view t;
    while (copy.Next(&t)) ++n;
    return n;
  }
  bool Done() const { return TrimBlanks(rest_).empty(); }
  // Everything not yet consumed, trimmed.
  std::string_view Rest() const { return TrimBlanks(rest_); }

 private:
  void SkipBlanks() {
    while (!rest_.empty() && IsBlank(rest_.front())) rest_.remove_prefix(1);
  }
  std::string_view rest_;
};

enum class NumberStatus { kOk, kNotANumber, kOutOfRange, kNotFinite };

// The whole token as a double (finite), or why not.
NumberStatus ParseDouble(std::string_view token, double* value);

// The fields of a line of dba's own text inputs (camera priors, ground
// control): the text before any '#', split at blanks and commas.
std::vector<std::string> CommentFreeFields(std::string_view line);
// The whole token as an integer of the type's range, or why not.
NumberStatus ParseInteger(std::string_view token, int64_t* value);
NumberStatus ParseInteger(std::string_view token, uint64_t* value);

}  // namespace dba
