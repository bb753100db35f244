#include "field_table.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace invfem::app {

std::string format_number(double x) {
  char text[40];
  if (x == std::floor(x) && std::fabs(x) < 1e7) {
    std::snprintf(text, sizeof text, "%.0f", x);
    return text;
  }
  std::snprintf(text, sizeof text, "%g", x);
  if (std::strtod(text, nullptr) != x) std::snprintf(text, sizeof text, "%.17g", x);  // 2147483647, not 2.14748e+09
  std::string s = text;
  // 1e-08 -> 1e-8, 1e+06 -> 1e6
  if (const auto e = s.find('e'); e != std::string::npos) {
    std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
    const bool negative = exponent[0] == '-';
    exponent = exponent.substr(exponent[0] == '-' || exponent[0] == '+' ? 1 : 0);
    exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
    s = mantissa + "e" + (negative ? "-" : "") + exponent;
  }
  return s;
}

std::string range_expected(const Range& r, bool integer) {
  std::ostringstream out;  // Fields::number_in's words for a closed range
  out << (integer ? "an integer in " : "a number in ") << (r.open_lo ? "(" : "[") << r.lo << ", " << r.hi
      << (r.open_hi ? ")" : "]");
  return out.str();
}

std::string choices_expected(const std::vector<std::string>& choices) {
  std::string out;
  for (std::size_t k = 0; k < choices.size(); ++k)
    out += (k == 0 ? "" : k + 1 == choices.size() ? " or " : ", ") + ("\"" + choices[k] + "\"");
  return out;
}

std::string with_sentence(const std::string& meaning, const std::string& more) {
  if (meaning.empty()) return more;
  const char last = meaning.back();
  return meaning + (last == '.' ? " " : ". ") + more;
}

std::string markdown_table(const std::vector<FieldRow>& rows) {
  std::string out = "| field | unit | default | meaning |\n|---|---|---|---|\n";
  for (const FieldRow& r : rows)
    out += "| `" + r.key + "` | " + r.unit + " | " + r.default_text + " | " + r.meaning + " |\n";
  return out;
}

}  // namespace invfem::app
