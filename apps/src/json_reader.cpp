#include "json_reader.hpp"

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace invfem::app {

namespace {
const nlohmann::json& empty_object() {
  static const nlohmann::json e = nlohmann::json::object();
  return e;
}
}  // namespace

namespace {

constexpr std::size_t kDescribeLength = 80;  // characters of a value shown in a message
constexpr int kDescribeDepth = 3;           // levels of arrays and objects shown

// Appends a rendering of v to out, `depth` levels deep at most; stops adding once out holds more
// than kDescribeLength characters (the caller cuts it there). Recursion is bounded by depth.
void render(const nlohmann::json& v, int depth, std::string& out) {
  constexpr auto replace = nlohmann::json::error_handler_t::replace;
  if (out.size() > kDescribeLength) return;
  if (v.is_array() || v.is_object()) {
    const bool array = v.is_array();
    out += array ? '[' : '{';
    if (depth <= 0 && !v.empty()) {
      out += "...";
    } else {
      bool first = true;
      for (auto it = v.begin(); it != v.end() && out.size() <= kDescribeLength; ++it) {
        if (!first) out += ", ";
        first = false;
        if (!array) out += nlohmann::json(it.key()).dump(-1, ' ', false, replace) + ": ";
        render(*it, depth - 1, out);
      }
    }
    out += array ? ']' : '}';
    return;
  }
  if (v.is_string()) {  // only the head of a long string is escaped and shown
    const auto& s = v.get_ref<const std::string&>();
    out += nlohmann::json(s.substr(0, kDescribeLength + 1)).dump(-1, ' ', false, replace);
    return;
  }
  out += v.dump(-1, ' ', false, replace);
}

// Parses `input` (a stream or a string) with the nesting bound and no key twice in one object
// (JSON parsers keep one of them, silently); throws InputError for those, nlohmann's exceptions
// for anything else.
template <class Input>
nlohmann::json parse_bounded(Input&& input, const std::string& origin) {
  std::vector<std::set<std::string>> keys;  // of each object open, innermost last
  const auto bound = [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    // depth counts the containers already open around this one (0 for the outermost).
    if ((event == E::object_start || event == E::array_start) && depth >= kMaxJsonDepth)
      throw InputError(origin + ": JSON nested more than " + std::to_string(kMaxJsonDepth) +
                       " levels deep (arrays or objects within one another)");
    if (event == E::object_start) keys.emplace_back();
    if (event == E::object_end && !keys.empty()) keys.pop_back();
    if (event == E::key && !keys.empty() && parsed.is_string() && !keys.back().insert(parsed.get<std::string>()).second)
      throw InputError(origin + ": the key \"" + parsed.get<std::string>() +
                       "\" appears twice in one object (give each field once)");
    return true;
  };
  return nlohmann::json::parse(std::forward<Input>(input), bound);
}

}  // namespace

std::string describe(const nlohmann::json& value) {
  std::string s;
  render(value, kDescribeDepth, s);
  if (s.size() > kDescribeLength) s = s.substr(0, kDescribeLength - 3) + "...";
  return value.is_null() ? s : std::string(value.type_name()) + " " + s;  // "null", not "null null"
}

namespace {
// The offset of the first byte that is not part of well-formed UTF-8, or npos.
std::size_t first_non_utf8(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    if (n == 0 || i + n > text.size()) return i;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(text[i + k]) >> 6) != 0x2) return i;
    i += n;
  }
  return std::string::npos;
}
}  // namespace

nlohmann::json parse_json(std::istream& in, const std::string& origin) {
  std::ostringstream text;
  text << in.rdbuf();
  return parse_json(text.str(), origin);
}

nlohmann::json parse_json(const std::string& text, const std::string& origin) {
  try {
    return parse_bounded(text, origin);
  } catch (const nlohmann::json::exception& e) {  // parse errors, and numbers out of range (1e309)
    // Text in another encoding (Latin-1): say where, instead of echoing the raw byte.
    if (const std::size_t at = first_non_utf8(text); at != std::string::npos) {
      const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
      const std::size_t line_start = text.rfind('\n', at == 0 ? 0 : at - 1);
      const std::size_t column = at - (line_start == std::string::npos || at == 0 ? 0 : line_start + 1) + 1;
      char byte[8];
      std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(text[at]));
      throw InputError(origin + ": not UTF-8 text: byte " + byte + " at line " + std::to_string(line) + ", column " +
                       std::to_string(column) + " (a Latin-1 or other 8-bit encoding?): save the file as UTF-8");
    }
    throw InputError(origin + ": not valid JSON: " + e.what());
  }
}

std::optional<nlohmann::json> try_parse_json(const std::string& text, const std::string& origin) {
  try {
    return parse_bounded(text, origin);
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

Fields::Fields(const nlohmann::json& j, std::string file, std::string path)
    : j_(j), file_(std::move(file)), path_(std::move(path)) {
  if (!j_.is_object())
    throw InputError(file_ + ": " + path_ + ": expected an object, found " + describe(j_));
}

void Fields::fail(const std::string& key, const std::string& expected, const std::string& found) const {
  std::string msg = file_ + ": " + path_of(key) + ": expected " + expected;
  if (!found.empty())
    msg += ", found " + found;
  else if (j_.contains(key))
    msg += ", found " + describe(j_.at(key));
  else
    msg += ", but it is missing";
  throw InputError(msg);
}

double Fields::number(const std::string& key) const {
  if (!j_.contains(key)) fail(key, "a number");
  const auto& v = j_.at(key);
  if (!v.is_number()) fail(key, "a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(key, "a finite number");
  return x;
}

double Fields::number(const std::string& key, double fallback) const {
  return j_.contains(key) ? number(key) : fallback;
}

double Fields::number_in(const std::string& key, double fallback, double lo, double hi) const {
  const double x = number(key, fallback);
  if (x < lo || x > hi) {
    std::ostringstream range;
    range << "a number in [" << lo << ", " << hi << "]";
    fail(key, range.str());
  }
  return x;
}

std::optional<std::int64_t> json_int64(const nlohmann::json& v) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return std::nullopt;
    return static_cast<std::int64_t>(u);
  }
  if (v.is_number_integer()) return v.get<std::int64_t>();
  return std::nullopt;
}

int Fields::integer(const std::string& key, int fallback, int lo, int hi) const {
  if (!j_.contains(key)) return fallback;
  const auto x = json_int64(j_.at(key));
  const std::string range = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!x) fail(key, j_.at(key).is_number_integer() ? range : "an integer");
  if (*x < lo || *x > hi) fail(key, range);
  return static_cast<int>(*x);
}

std::vector<std::int64_t> Fields::index_list(const std::string& key) const {
  if (!j_.contains(key) || !j_.at(key).is_array()) fail(key, "an array of vertex indices");
  const auto& v = j_.at(key);
  std::vector<std::int64_t> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto x = json_int64(v[i]);
    if (!x || *x < 0) fail(key, "vertex indices (integers >= 0)", "element " + std::to_string(i) + ": " + describe(v[i]));
    out.push_back(*x);
  }
  return out;
}

bool Fields::boolean(const std::string& key, bool fallback) const {
  if (!j_.contains(key)) return fallback;
  if (!j_.at(key).is_boolean()) fail(key, "true or false");
  return j_.at(key).get<bool>();
}

std::string Fields::string(const std::string& key) const {
  if (!j_.contains(key) || !j_.at(key).is_string()) fail(key, "a string");
  return j_.at(key).get<std::string>();
}

std::string Fields::string(const std::string& key, const std::string& fallback) const {
  return j_.contains(key) ? string(key) : fallback;
}

std::optional<std::array<double, 3>> bounded_vec3(const nlohmann::json& v, double max_norm) {
  if (!v.is_array() || v.size() != 3) return std::nullopt;
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!v[i].is_number()) return std::nullopt;
    out[i] = v[i].get<double>();
    if (!std::isfinite(out[i])) return std::nullopt;
  }
  // hypot: no overflow in the norm of finite components near 1e308.
  if (!(std::hypot(out[0], out[1], out[2]) <= max_norm)) return std::nullopt;
  return out;
}

std::string vec3_expected(double max_norm) {
  std::ostringstream s;
  s << "an array of 3 finite numbers of magnitude <= " << max_norm;
  return s.str();
}

std::array<double, 3> Fields::vec3(const std::string& key, std::array<double, 3> fallback, double max_norm) const {
  if (!j_.contains(key)) return fallback;
  const auto v = bounded_vec3(j_.at(key), max_norm);
  if (!v) fail(key, vec3_expected(max_norm));
  return *v;
}

std::string object_name_problem(const std::string& name) {
  constexpr std::size_t kMaxNameBytes = 100;  // well below a file name's 255, with room for suffixes
  if (name.empty()) return "it is empty";
  if (name.size() > kMaxNameBytes) return "it is longer than " + std::to_string(kMaxNameBytes) + " bytes";
  if (name == "." || name == "..") return "\"" + name + "\" names a folder, not an object";
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) return "it holds a control character (byte " + std::to_string(u) + ")";
    if (c == '/' || c == '\\') return "it holds a path separator '" + std::string(1, c) + "'";
  }
  return "";
}

std::string Fields::object_name(const std::string& key) const {
  const std::string name = string(key);
  if (const std::string problem = object_name_problem(name); !problem.empty())
    fail(key, "a name that can be a folder name (printable, no '/' or '\\', not \".\" or \"..\")",
         describe(j_.at(key)) + ": " + problem);
  return name;
}

Fields Fields::object(const std::string& key) const {
  if (!j_.contains(key)) fail(key, "an object");
  return Fields(j_.at(key), file_, path_of(key));
}

Fields Fields::object_or_empty(const std::string& key) const {
  if (!j_.contains(key)) return Fields(empty_object(), file_, path_of(key));
  return object(key);
}

void Fields::reject_unknown(std::initializer_list<const char*> known) const {
  reject_unknown_keys(std::vector<std::string>(known.begin(), known.end()));
}

void Fields::reject_unknown_keys(const std::vector<std::string>& known) const {
  for (auto it = j_.begin(); it != j_.end(); ++it) {
    if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    throw InputError(file_ + ": " + path_of(it.key()) + ": unknown field (known fields: " + list + ")");
  }
}

}  // namespace invfem::app
