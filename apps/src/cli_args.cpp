#include "cli_args.hpp"

#include <cmath>
#include <sstream>

#include "json_reader.hpp"

namespace invfem::app {

namespace {
bool parse_int(const std::string& text, long long& out) {
  try {
    std::size_t used = 0;
    out = std::stoll(text, &used);
    return used == text.size();
  } catch (const std::exception&) {
    return false;
  }
}
}  // namespace

const std::vector<std::string>& ParsedArgs::all(const std::string& name) const {
  static const std::vector<std::string> none;
  const auto it = values.find(name);
  return it == values.end() ? none : it->second;
}

int ParsedArgs::integer(const std::string& name, int fallback, int lo, int hi) const {
  if (!has(name)) return fallback;
  long long v = 0;
  if (!parse_int(value(name), v) || v < lo || v > hi)
    throw InputError(name + ": expected a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "], found \"" + value(name) + "\"");
  return static_cast<int>(v);
}

double ParsedArgs::real(const std::string& name, double fallback, double lo, double hi) const {
  if (!has(name)) return fallback;
  const std::string& text = value(name);
  double v = 0;
  std::size_t used = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream range;
    range << "[" << lo << ", " << hi << "]";
    throw InputError(name + ": expected a number in " + range.str() + ", found \"" + text + "\"");
  }
  return v;
}

ParsedArgs parse_args(const std::vector<std::string>& args, const std::string& command,
                      const std::set<std::string>& value_options, const std::set<std::string>& flag_options) {
  ParsedArgs out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string a = args[i];
    if (a.size() < 2 || a[0] != '-' || a == "--") {
      out.positional.push_back(a);
      continue;
    }
    std::string inline_value;
    bool has_inline = false;
    if (const auto eq = a.find('='); eq != std::string::npos) {
      inline_value = a.substr(eq + 1);
      a = a.substr(0, eq);
      has_inline = true;
    }
    if (flag_options.count(a)) {
      if (has_inline) throw InputError(command + ": option " + a + " takes no value");
      out.flags.insert(a);
    } else if (value_options.count(a)) {
      if (has_inline) {
        out.values[a].push_back(inline_value);
      } else {
        if (i + 1 >= args.size()) throw InputError(command + ": option " + a + " needs a value");
        out.values[a].push_back(args[++i]);
      }
    } else {
      throw InputError(command + ": unknown option \"" + a + "\" (see invfem " + command + " --help)");
    }
  }
  return out;
}

std::pair<int, int> parse_frame_range(const std::string& text, const std::string& option) {
  const auto dash = text.find('-', 1);
  long long a = 0, b = 0;
  const bool ok = dash == std::string::npos ? parse_int(text, a) && (b = a, true)
                                             : parse_int(text.substr(0, dash), a) && parse_int(text.substr(dash + 1), b);
  if (!ok || a < 0 || b < a || b > 10000000)
    throw InputError(option + ": expected a frame range A-B with 0 <= A <= B, found \"" + text + "\"");
  return {static_cast<int>(a), static_cast<int>(b)};
}

std::string frame_ranges(const std::vector<int>& frames, std::size_t shown) {
  std::string out;
  std::size_t runs = 0, more = 0;
  for (std::size_t i = 0; i < frames.size();) {
    std::size_t j = i;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    if (runs++ < shown) {
      if (!out.empty()) out += ", ";
      out += std::to_string(frames[i]);
      if (j > i) out.append("-").append(std::to_string(frames[j]));
    } else {
      more += j - i + 1;
    }
    i = j + 1;
  }
  if (more) out += " and " + std::to_string(more) + " more";
  return out;
}

}  // namespace invfem::app
