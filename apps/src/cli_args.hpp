#pragma once
// Command-line options of the invfem subcommands: `--name value`, `--name=value` and flags.
// Unknown options are InputErrors that name the command.
#include <map>
#include <set>
#include <string>
#include <vector>

namespace invfem::app {

struct ParsedArgs {
  std::vector<std::string> positional;
  std::map<std::string, std::vector<std::string>> values;  // option -> every value given
  std::set<std::string> flags;

  bool flag(const std::string& name) const { return flags.count(name) > 0; }
  bool has(const std::string& name) const { return values.count(name) > 0; }
  const std::string& value(const std::string& name) const { return values.at(name).back(); }
  const std::vector<std::string>& all(const std::string& name) const;
  // Typed getters: throw InputError naming the option and the bad text.
  int integer(const std::string& name, int fallback, int lo, int hi) const;
  // A finite number in [lo, hi].
  double real(const std::string& name, double fallback, double lo, double hi) const;
};

ParsedArgs parse_args(const std::vector<std::string>& args, const std::string& command,
                      const std::set<std::string>& value_options, const std::set<std::string>& flag_options);

// "A-B" or "A" -> [A, B] (inclusive).
std::pair<int, int> parse_frame_range(const std::string& text, const std::string& option);

// Ascending frame numbers as runs, "2, 5-9, 12"; at most `shown` runs, then "and N more".
std::string frame_ranges(const std::vector<int>& frames, std::size_t shown = 8);

}  // namespace invfem::app
