#include "text_scanner.hpp"

#include "invfem/core/io/text_file.hpp"

#include <cctype>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cmath>
#include <cstdlib>
#include <system_error>

namespace invfem::detail {

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'A' && x <= 'Z') x = char(x - 'A' + 'a');
    if (y >= 'A' && y <= 'Z') y = char(y - 'A' + 'a');
    if (x != y) return false;
  }
  return true;
}

std::string read_text_file(const std::string& path) {
  // Text meshes this large would not fit a simulation on one machine anyway.
  return invfem::read_text_file(path, std::uintmax_t{4} << 30, "the text mesh readers");
}

TextScanner::TextScanner(std::string path, std::string text, char comment)
    : path_(std::move(path)), text_(std::move(text)), comment_(comment) {}

void TextScanner::skip_space() {
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (c == '\n') {
      ++line_;
      ++pos_;
    } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++pos_;
    } else if (comment_ != 0 && c == comment_) {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    } else {
      break;
    }
  }
}

bool TextScanner::at_end() {
  skip_space();
  return pos_ >= text_.size();
}

std::string_view TextScanner::peek() {
  skip_space();
  std::size_t end = pos_;
  while (end < text_.size() && !std::isspace(static_cast<unsigned char>(text_[end]))) ++end;
  return std::string_view(text_).substr(pos_, end - pos_);
}

std::string_view TextScanner::token(std::string_view what) {
  const std::string_view t = peek();
  // Reported at the last token's line: the file ends after it.
  if (t.empty()) fail_at(token_line_, "unexpected end of file while reading " + std::string(what));
  token_line_ = line_;
  pos_ += t.size();
  return t;
}

std::string_view TextScanner::line_rest() {
  const std::size_t start = pos_;
  std::size_t end = text_.find('\n', pos_);
  if (end == std::string::npos) end = text_.size();
  token_line_ = line_;
  pos_ = end < text_.size() ? end + 1 : end;
  if (end < text_.size()) ++line_;
  std::string_view s = std::string_view(text_).substr(start, end - start);
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

void TextScanner::skip_line() { (void)line_rest(); }

std::string TextScanner::item_name(std::string_view what, long long index) const {
  std::string s(what);
  if (index >= 0) s.append(1, ' ').append(std::to_string(index));
  return s;
}

std::string_view TextScanner::item_token(std::string_view what, long long index) {
  // The item name is built only on failure: this runs once per number in the file.
  const std::string_view t = peek();
  if (t.empty())
    fail_at(token_line_, "unexpected end of file while reading " + item_name(what, index));
  token_line_ = line_;
  pos_ += t.size();
  return t;
}

long long TextScanner::integer(std::string_view what, long long index) {
  std::string_view t = item_token(what, index);
  std::string_view digits = t;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  long long v = 0;
  const auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
  if (ec == std::errc::result_out_of_range)
    fail(item_name(what, index) + ": integer '" + std::string(t) + "' is out of range");
  if (ec != std::errc() || p != digits.data() + digits.size() || digits.empty())
    fail(item_name(what, index) + ": expected an integer, got '" + std::string(t.substr(0, 40)) +
         "'");
  return v;
}

double TextScanner::real(std::string_view what, long long index) {
  std::string_view t = item_token(what, index);
  std::string_view digits = t;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  double v = 0;
  const auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
  // from_chars reports out-of-range for overflow and for underflow alike, and then leaves v
  // untouched; strtod on the same (already matched) text tells them apart: +-HUGE_VAL for an
  // overflow, a tiny or zero value for an underflow (which is fine).
  if (ec == std::errc::result_out_of_range && p == digits.data() + digits.size()) {
    v = std::strtod(std::string(digits).c_str(), nullptr);
    if (!std::isfinite(v)) fail(item_name(what, index) + ": number '" + std::string(t) + "' overflows a double");
  }
  if ((ec != std::errc() && ec != std::errc::result_out_of_range) ||
      p != digits.data() + digits.size() || digits.empty())
    fail(item_name(what, index) + ": expected a number, got '" + std::string(t.substr(0, 40)) +
         "'");
  if (!std::isfinite(v))
    fail(item_name(what, index) + ": coordinate is not finite ('" + std::string(t) + "')");
  return v;
}

long long TextScanner::count(std::string_view what, int tokens_per_item) {
  const long long n = integer(what);
  if (n < 0) fail(std::string(what) + ": negative count " + std::to_string(n));
  // Each token takes at least one character plus one separator.
  const long long max_items =
      (static_cast<long long>(remaining_bytes()) + 1) / (2LL * tokens_per_item);
  if (n > max_items)
    fail(std::string(what) + ": declared count " + std::to_string(n) +
         " exceeds what the rest of the file can hold (" + std::to_string(remaining_bytes()) +
         " bytes); the file is truncated or the count is wrong");
  if (n > INT_MAX) fail(std::string(what) + ": count " + std::to_string(n) + " is too large");
  return n;
}

void TextScanner::fail(std::string_view problem) const { fail_at(token_line_, problem); }

void TextScanner::fail_at(int line, std::string_view problem) const {
  if (line <= 0) throw MeshError(path_ + ": " + std::string(problem));
  throw MeshError(path_ + ":" + std::to_string(line) + ": " + std::string(problem));
}

}  // namespace invfem::detail
