// Internal: a fast whitespace tokenizer over an in-memory text buffer that knows
// its line number, so every reader reports "file:line: problem". Numbers are
// parsed with std::from_chars (locale-free, no allocation); NaN and infinity are
// rejected because no mesh coordinate may be one.
#pragma once

#include "structmesh/error.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>

namespace structmesh::detail {

class TextScanner {
 public:
  TextScanner(std::string_view data, std::string source_name) : data_(data), source_(std::move(source_name)) {}

  /// Line number (1-based) of the next unread character.
  std::uint32_t line() const { return line_; }
  const std::string& source() const { return source_; }
  bool at_end() {
    skip_space();
    return pos_ >= data_.size();
  }
  std::size_t position() const { return pos_; }
  std::string_view rest() const { return data_.substr(pos_); }

  /// Skips spaces, tabs, carriage returns and newlines (counting lines), and
  /// comments starting with `comment_char` when one is set.
  void skip_space() {
    while (pos_ < data_.size()) {
      const char c = data_[pos_];
      if (c == '\n') {
        ++line_;
        ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++pos_;
      } else if (comment_ != '\0' && c == comment_) {
        while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
  }
  void set_comment_char(char c) { comment_ = c; }

  /// Skips spaces and tabs on the current line only.
  void skip_blanks() {
    while (pos_ < data_.size() && (data_[pos_] == ' ' || data_[pos_] == '\t' || data_[pos_] == '\r')) ++pos_;
  }
  /// True when only blanks (or a comment) remain on the current line.
  bool at_line_end() {
    skip_blanks();
    return pos_ >= data_.size() || data_[pos_] == '\n' || (comment_ != '\0' && data_[pos_] == comment_);
  }
  /// Moves past the end of the current line.
  void skip_line() {
    while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
    if (pos_ < data_.size()) {
      ++pos_;
      ++line_;
    }
  }
  /// The rest of the current line (without the newline), consumed.
  std::string_view read_line() {
    const std::size_t start = pos_;
    while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
    std::string_view line = data_.substr(start, pos_ - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (pos_ < data_.size()) {
      ++pos_;
      ++line_;
    }
    return line;
  }

  /// Next whitespace-separated token; empty at end of input.
  std::string_view token() {
    skip_space();
    const std::size_t start = pos_;
    while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
    return data_.substr(start, pos_ - start);
  }
  /// Next token on the current line only; empty when the line has no more tokens.
  std::string_view token_on_line() {
    if (at_line_end()) return {};
    const std::size_t start = pos_;
    while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
    return data_.substr(start, pos_ - start);
  }

  /// A finite double; `what` names the value in the error message.
  double real(const char* what) { return parse_real(token(), what); }
  /// A non-negative or signed integer that fits in int64.
  std::int64_t integer(const char* what) { return parse_integer(token(), what); }

  double parse_real(std::string_view tok, const char* what) const {
    if (tok.empty()) fail(std::string("unexpected end of file, expected ") + what);
    double value = 0.0;
    const char* first = tok.data();
    const char* last = tok.data() + tok.size();
    if (*first == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, last, value);
    if (ec != std::errc() || ptr != last) fail(std::string("expected ") + what + ", found '" + clip(tok) + "'");
    if (!std::isfinite(value)) fail(std::string(what) + " is not finite ('" + clip(tok) + "')");
    return value;
  }
  std::int64_t parse_integer(std::string_view tok, const char* what) const {
    if (tok.empty()) fail(std::string("unexpected end of file, expected ") + what);
    std::int64_t value = 0;
    const char* first = tok.data();
    const char* last = tok.data() + tok.size();
    if (*first == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, last, value);
    if (ec != std::errc() || ptr != last) fail(std::string("expected ") + what + ", found '" + clip(tok) + "'");
    return value;
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(located_message(source_, line_, message));
  }

  static std::string clip(std::string_view s) {
    return s.size() <= 40 ? std::string(s) : std::string(s.substr(0, 40)) + "...";
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

  std::string_view data_;
  std::string source_;
  std::size_t pos_ = 0;
  std::uint32_t line_ = 1;
  char comment_ = '\0';
};

}  // namespace structmesh::detail
