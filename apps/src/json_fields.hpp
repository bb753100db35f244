#pragma once
// Typed access to scene JSON with errors that name the file, the JSON path of the field, what
// was expected and what was found. Unknown fields are errors (a typo must not pass silently).
#include <nlohmann/json.hpp>

#include <array>
#include <initializer_list>
#include <stdexcept>
#include <string>

namespace invfem::app {

// Bad user input (a scene, a mesh, an option): exit code 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Fields {
 public:
  Fields(const nlohmann::json& j, std::string file, std::string path);

  bool has(const std::string& key) const { return j_.contains(key); }
  double number(const std::string& key, double fallback) const;
  double number(const std::string& key) const;  // required
  // A number in [lo, hi] (inclusive unless open_* is set).
  double number_in(const std::string& key, double fallback, double lo, double hi) const;
  int integer(const std::string& key, int fallback, int lo, int hi) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  std::string string(const std::string& key) const;  // required
  std::array<double, 3> vec3(const std::string& key, std::array<double, 3> fallback) const;
  Fields object(const std::string& key) const;  // required object; {} if absent and optional
  Fields object_or_empty(const std::string& key) const;
  const nlohmann::json& raw(const std::string& key) const { return j_.at(key); }
  std::string path_of(const std::string& key) const { return path_ + "." + key; }
  // Throws for any key of the object not in `known`.
  void reject_unknown(std::initializer_list<const char*> known) const;

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

std::string describe(const nlohmann::json& value);

}  // namespace invfem::app
