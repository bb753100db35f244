#pragma once
// Typed access to scene JSON with errors that name the file, the JSON path of the field, what
// was expected and what was found. Unknown fields are errors (a typo must not pass silently).
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <initializer_list>
#include <istream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace invfem::app {

// Bad user input (a scene, a mesh, an option): exit code 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The physical ranges of a scene's quantities (apps/scenes/README.md, "Ranges"). Far beyond any
// real scene, they keep every product the simulator forms (m v^2, m g y, positions plus
// velocity times dt) finite: a velocity of 1e300 m/s once gave an infinite kinetic energy and a
// gravity of 1e300 m/s^2 froze every object.
namespace limits {
constexpr double kLength = 1e6;        // [m] positions, translations, extents, pin boxes
constexpr double kSpeed = 1e4;         // [m/s] initial and collider velocities
constexpr double kAcceleration = 1e4;  // [m/s^2] gravity
constexpr double kAngularSpeed = 1e4;  // [rad/s] collider spin rates
constexpr double kDegrees = 1e6;       // [degrees] rotations
constexpr double kDirection = 1e6;     // axes and directions (normalized when used)
constexpr double kTime = 1e9;          // [s] key times
constexpr double kScale = 1e6;         // transform scales and per-axis factors
}  // namespace limits

class Fields {
 public:
  Fields(const nlohmann::json& j, std::string file, std::string path);

  bool has(const std::string& key) const { return j_.contains(key); }
  double number(const std::string& key, double fallback) const;
  double number(const std::string& key) const;  // required
  // A number in [lo, hi] (inclusive unless open_* is set).
  double number_in(const std::string& key, double fallback, double lo, double hi) const;
  // An integer in [lo, hi], checked in 64 bits before it is narrowed (4294967297 is not 1).
  int integer(const std::string& key, int fallback, int lo, int hi) const;
  // A required array of indices >= 0 (mesh vertices), kept in 64 bits: the caller checks them
  // against the mesh before narrowing (shells selected_vertices).
  std::vector<std::int64_t> index_list(const std::string& key) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  std::string string(const std::string& key) const;  // required
  // A required object name (solids, cloths, colliders): see object_name_problem.
  std::string object_name(const std::string& key) const;
  // Three finite numbers whose Euclidean norm is at most max_norm (a physical range, `limits`).
  std::array<double, 3> vec3(const std::string& key, std::array<double, 3> fallback, double max_norm) const;
  Fields object(const std::string& key) const;  // required object; {} if absent and optional
  Fields object_or_empty(const std::string& key) const;
  const nlohmann::json& raw(const std::string& key) const { return j_.at(key); }
  std::string path_of(const std::string& key) const { return path_ + "." + key; }
  // Throws for any key of the object not in `known`.
  void reject_unknown(std::initializer_list<const char*> known) const;
  void reject_unknown_keys(const std::vector<std::string>& known) const;

  [[noreturn]] void fail(const std::string& key, const std::string& expected,
                         const std::string& found_detail = "") const;
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  const nlohmann::json& json() const { return j_; }

 private:
  const nlohmann::json& j_;
  std::string file_;
  std::string path_;
};

// A JSON value as error messages echo it: its type and a rendering at most 80 characters long
// and 3 levels deep ("[[[...]]]" below that), never recursing further, so that a hostile value
// (70,000 nested arrays, a megabyte string) neither overflows the stack nor floods the terminal.
// Invalid UTF-8 in strings is shown replaced, never thrown.
std::string describe(const nlohmann::json& value);

// [x, y, z] with finite components and a norm <= max_norm; nullopt otherwise (keyframe lists
// read their elements with it, Fields::vec3 its fields). vec3_expected: the message's "expected".
std::optional<std::array<double, 3>> bounded_vec3(const nlohmann::json& v, double max_norm);
std::string vec3_expected(double max_norm);

// The exact value of an integer JSON number, nullopt for anything else: a float (3.0 included,
// as JSON writes no integer that way) or an unsigned number above 2^63 - 1. Every integer of a
// scene is read through it, so none is truncated or wrapped.
std::optional<std::int64_t> json_int64(const nlohmann::json& v);

// Why `name` cannot name a scene object, "" when it can. An object's name is the folder of its
// frames (OUT/frames/<name>/) and the stem of its other files, so it must be one plain path
// component: not empty, at most 100 bytes, printable (no control characters, NUL included), no
// '/' or '\\', and not "." or "..".
std::string object_name_problem(const std::string& name);

// Arrays and objects nested deeper than this are refused when parsing (scene files, --set
// values, a run's scene.json): no scene needs more than a handful of levels, and every later
// walk over a parsed value (dump, copy, compare) recurses once per level.
constexpr int kMaxJsonDepth = 64;

// Parses JSON text, refusing nesting deeper than kMaxJsonDepth. Throws InputError naming
// `origin` (a file name, "--set frames") for a syntax error, a number out of range or the depth.
nlohmann::json parse_json(std::istream& in, const std::string& origin);
nlohmann::json parse_json(const std::string& text, const std::string& origin);
// The same, but text that is not JSON gives nullopt (a --set value is then taken as plain text);
// nesting too deep still throws.
std::optional<nlohmann::json> try_parse_json(const std::string& text, const std::string& origin);

}  // namespace invfem::app
