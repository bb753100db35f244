#pragma once
// One scene field, defined once: its JSON key, unit, accepted range or values, one-line
// description, and the member of its plain-data spec (scene.hpp) it fills, whose initializer is
// its default. A spec's table (scene_fields.cpp) is what the parser reads (FieldTable::read: the
// unknown keys, the types, the ranges and their error messages), what to_json writes back
// (FieldTable::write) and what the tables of apps/scenes/README.md are generated from
// (FieldTable::markdown; test_scene_fields fails when the document differs).
//
// A field the table cannot read alone (a vector, a list, an object, a field whose check needs
// another) is a documented row without a member: the table lists it (its key is known, its
// default and meaning documented), and the spec's parser reads it by hand.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "json_fields.hpp"

namespace invfem::app {

// An interval of accepted numbers; an open end excludes its bound.
struct Range {
  double lo = 0, hi = 0;
  bool open_lo = false, open_hi = false;
};

template <class S> struct Field {
  // An optional number is read only when given (no default: "none"), and written only when set.
  using Member =
      std::variant<std::monostate, double S::*, std::optional<double> S::*, int S::*, bool S::*, std::string S::*>;
  std::string key;
  Member member;                     // monostate: documented here, read by hand
  std::string unit = "–";
  Range range;                       // double and int members
  std::vector<std::string> choices;  // string members: the accepted values (empty: any)
  std::string expected;              // the error's "expected ..." when not accepted ("": from range or choices)
  std::string description;           // one line
  std::string default_text;          // rows without a member: the default as documented
};

// The document's words for a number (1e-08 -> 1e-8, 100000 -> 100000, 0.005 -> 0.005).
std::string format_number(double x);
// "a number in [lo, hi]" (closed: Fields::number_in's own words), "a number in (lo, hi]", ...
std::string range_expected(const Range& r, bool integer);
// "\"a\", \"b\" or \"c\"".
std::string choices_expected(const std::vector<std::string>& choices);
// One Markdown table: | field | unit | default | meaning |.
struct FieldRow {
  std::string key, unit, default_text, meaning;
};
std::string markdown_table(const std::vector<FieldRow>& rows);
// `meaning` followed by the sentence `more` ("a. More", or "More" alone).
std::string with_sentence(const std::string& meaning, const std::string& more);

template <class S> class FieldTable {
 public:
  explicit FieldTable(std::vector<Field<S>> fields) : fields_(std::move(fields)) {}

  const std::vector<Field<S>>& fields() const { return fields_; }
  // Every key of the table, and any `more` (keys another part of the parser owns), is accepted;
  // any other throws InputError naming it.
  void reject_unknown(const Fields& f, std::initializer_list<const char*> more = {}) const {
    std::vector<std::string> known;
    for (const auto& d : fields_) known.push_back(d.key);
    for (const char* k : more) known.push_back(k);
    f.reject_unknown_keys(known);
  }
  // Reads every field with a member that `f` holds into `spec` (absent ones keep spec's value),
  // in table order, checking type and range; throws InputError naming the field.
  void read(const Fields& f, S& spec) const {
    for (const auto& d : fields_) std::visit([&](auto m) { read_one(f, spec, d, m); }, d.member);
  }
  // Writes every field with a member into j.
  void write(nlohmann::json& j, const S& spec) const {
    for (const auto& d : fields_)
      std::visit([&](auto m) {
        using M = decltype(m);
        if constexpr (std::is_same_v<M, std::optional<double> S::*>) {
          if (spec.*m) j[d.key] = *(spec.*m);
        } else if constexpr (!std::is_same_v<M, std::monostate>) {
          j[d.key] = spec.*m;
        }
      }, d.member);
  }
  // The table's rows for the document, defaults from a default-constructed spec.
  std::vector<FieldRow> rows() const {
    const S defaults{};
    std::vector<FieldRow> out;
    for (const auto& d : fields_) {
      FieldRow r{d.key, d.unit, d.default_text, d.description};
      std::visit([&](auto m) { describe(defaults, d, m, r); }, d.member);
      out.push_back(std::move(r));
    }
    return out;
  }
  std::string markdown() const { return markdown_table(rows()); }

 private:
  static void read_one(const Fields&, S&, const Field<S>&, std::monostate) {}
  static void read_one(const Fields& f, S& s, const Field<S>& d, double S::*m) { s.*m = checked(f, d, s.*m); }
  static void read_one(const Fields& f, S& s, const Field<S>& d, std::optional<double> S::*m) {
    if (f.has(d.key)) s.*m = checked(f, d, 0.0);
  }
  // The number at d.key (fallback when absent) within d.range.
  static double checked(const Fields& f, const Field<S>& d, double fallback) {
    const double x = f.number(d.key, fallback);
    const Range& r = d.range;
    if (r.open_lo ? !(x > r.lo) : !(x >= r.lo)) f.fail(d.key, d.expected.empty() ? range_expected(r, false) : d.expected);
    if (r.open_hi ? !(x < r.hi) : !(x <= r.hi)) f.fail(d.key, d.expected.empty() ? range_expected(r, false) : d.expected);
    return x;
  }
  static void read_one(const Fields& f, S& s, const Field<S>& d, int S::*m) {
    s.*m = f.integer(d.key, s.*m, static_cast<int>(d.range.lo), static_cast<int>(d.range.hi));
  }
  static void read_one(const Fields& f, S& s, const Field<S>& d, bool S::*m) { s.*m = f.boolean(d.key, s.*m); }
  static void read_one(const Fields& f, S& s, const Field<S>& d, std::string S::*m) {
    const std::string v = f.string(d.key, s.*m);
    if (!d.choices.empty() && std::find(d.choices.begin(), d.choices.end(), v) == d.choices.end())
      f.fail(d.key, d.expected.empty() ? choices_expected(d.choices) : d.expected);
    s.*m = v;
  }

  static void describe(const S&, const Field<S>&, std::monostate, FieldRow&) {}
  static void describe(const S& defaults, const Field<S>& d, double S::*m, FieldRow& r) {
    r.default_text = format_number(defaults.*m);
    r.meaning = with_sentence(r.meaning, range_sentence(d.range));
  }
  static void describe(const S&, const Field<S>& d, std::optional<double> S::*, FieldRow& r) {
    r.default_text = "none";
    r.meaning = with_sentence(r.meaning, range_sentence(d.range));
  }
  static void describe(const S& defaults, const Field<S>& d, int S::*m, FieldRow& r) {
    r.default_text = std::to_string(defaults.*m);
    r.meaning = with_sentence(r.meaning, range_sentence(d.range));
  }
  static void describe(const S& defaults, const Field<S>&, bool S::*m, FieldRow& r) {
    r.default_text = defaults.*m ? "true" : "false";
  }
  static void describe(const S& defaults, const Field<S>& d, std::string S::*m, FieldRow& r) {
    r.default_text = (defaults.*m).empty() ? r.default_text : "`" + defaults.*m + "`";
    if (!d.choices.empty()) {
      std::string list;
      for (std::size_t k = 0; k < d.choices.size(); ++k)
        list += (k == 0 ? "" : k + 1 == d.choices.size() ? " or " : ", ") + ("`" + d.choices[k] + "`");
      r.meaning = with_sentence(r.meaning, "One of " + list);
    }
  }
  // "In [lo, hi]" for the document.
  static std::string range_sentence(const Range& r) {
    return "In " + std::string(r.open_lo ? "(" : "[") + format_number(r.lo) + ", " + format_number(r.hi) +
           (r.open_hi ? ")" : "]");
  }

  std::vector<Field<S>> fields_;
};

}  // namespace invfem::app
