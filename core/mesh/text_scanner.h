#pragma once
// Internal to core/mesh: a scanner over the bytes of a text mesh file that yields lines and
// whitespace-separated tokens and knows the current line number, for error messages.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/common/error.h"

namespace hexcover::detail {

inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/// Splits one line into tokens separated by blanks.
class LineTokens {
 public:
  explicit LineTokens(std::string_view line) : rest_(line) {}
  /// The next token, or an empty view at the end of the line.
  std::string_view next() {
    std::size_t i = 0;
    while (i < rest_.size() && isBlank(rest_[i])) ++i;
    std::size_t j = i;
    while (j < rest_.size() && !isBlank(rest_[j])) ++j;
    const std::string_view token = rest_.substr(i, j - i);
    rest_.remove_prefix(j);
    return token;
  }
  /// What is left of the line, leading blanks removed.
  std::string_view rest() {
    std::size_t i = 0;
    while (i < rest_.size() && isBlank(rest_[i])) ++i;
    return rest_.substr(i);
  }

 private:
  std::string_view rest_;
};

/// Iterates over the lines of a text (LF or CRLF), counting them from 1.
class LineScanner {
 public:
  explicit LineScanner(std::string_view text) : text_(text) {}
  /// Advances to the next line; false at the end of the text. The line excludes "\r\n".
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line = text_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = stop + 1;
    ++lineNumber_;
    return true;
  }
  /// 1-based number of the line last returned by next().
  std::size_t lineNumber() const { return lineNumber_; }
  /// Byte offset where the next line starts.
  std::size_t offset() const { return std::min(pos_, text_.size()); }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t lineNumber_ = 0;
};

[[noreturn]] inline void failAtLine(ErrorCode code, std::string_view format, std::size_t line,
                                    const std::string& what) {
  throw Error(code, std::string(format) + " line " + std::to_string(line) + ": " + what);
}

inline std::string quoted(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  std::string shown(token.substr(0, kMaxShown));
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return "'" + shown + (token.size() > kMaxShown ? "...'" : "'");
}

/// Parses a whole token as a double (a leading '+' allowed); false if it is not a number.
inline bool parseDouble(std::string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size() && !token.empty();
}

/// Parses a whole token as a signed 64-bit integer (a leading '+' allowed).
inline bool parseInteger(std::string_view token, std::int64_t& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size() && !token.empty();
}

}  // namespace hexcover::detail
