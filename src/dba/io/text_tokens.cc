// Tokens and numbers of text formats; see text_tokens.h.
#include "dba/io/text_tokens.h"

#include <charconv>
#include <cmath>
#include <system_error>

namespace dba {
namespace {

// A leading '+' (not "+-") is skipped: from_chars refuses it.
std::string_view WithoutPlus(std::string_view t) {
  if (t.size() > 1 && t[0] == '+' && t[1] != '-') t.remove_prefix(1);
  return t;
}

template <typename T>
NumberStatus Parse(std::string_view token, T* value) {
  const std::string_view t = WithoutPlus(token);
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), *value);
  if (ec == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (ec != std::errc() || end != t.data() + t.size() || t.empty()) return NumberStatus::kNotANumber;
  return NumberStatus::kOk;
}

}  // namespace

NumberStatus ParseDouble(std::string_view token, double* value) {
  const NumberStatus s = Parse(token, value);
  if (s == NumberStatus::kOk && !std::isfinite(*value)) return NumberStatus::kNotFinite;
  return s;
}

NumberStatus ParseInteger(std::string_view token, int64_t* value) { return Parse(token, value); }
NumberStatus ParseInteger(std::string_view token, uint64_t* value) { return Parse(token, value); }

TextCounts CountText(std::string_view text) {
  TextCounts c;
  const size_t n = text.size();
  if (n == 0) return c;
  const char* t = text.data();
  // Branch-free, so that it vectorizes: a token starts at i when t[i] is not
  // a separator and t[i - 1] is. Separators: ' ' and '\t' .. '\r'.
  auto sep = [](char ch) -> unsigned {
    const auto u = static_cast<unsigned char>(ch);
    return (u == ' ') | (static_cast<unsigned char>(u - '\t') < 5);
  };
  int64_t tokens = sep(t[0]) ^ 1u;
  int64_t newlines = t[0] == '\n';
  for (size_t i = 1; i < n; ++i) {
    tokens += (sep(t[i]) ^ 1u) & sep(t[i - 1]);
    newlines += t[i] == '\n';
  }
  c.tokens = tokens;
  c.newlines = newlines;
  for (size_t i = 0; i < n; ++i) {
    if (sep(t[i])) {
      c.first_separator = i;
      break;
    }
  }
  for (size_t i = n; i-- > 0;) {
    if (sep(t[i])) {
      c.last_separator = i;
      break;
    }
  }
  c.first_newline = text.find('\n');
  c.last_newline = text.rfind('\n');
  return c;
}

std::vector<std::string> CommentFreeFields(std::string_view line) {
  std::string text(line.substr(0, line.find('#')));
  for (char& c : text) {
    if (c == ',') c = ' ';
  }
  LineTokens t(text);
  std::vector<std::string> fields;
  std::string_view token;
  while (t.Next(&token)) fields.emplace_back(token);
  return fields;
}

}  // namespace dba
