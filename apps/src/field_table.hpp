#pragma once
// One scene field, defined once: its JSON key, unit, accepted range or values, one-line
// description, and the slot it fills: a member of a module's own settings (SelfCollisionSettings,
// WorldSettings, StitchParams, ...) or of the scene's object descriptions, whose initializer is
// its default. A section's table (scene_tables.cpp) is what the parser reads (FieldTable::read:
// the unknown keys, the types, the ranges and their error messages), what to_json writes back
// (FieldTable::write) and what the tables of apps/scenes/README.md are generated from
// (FieldTable::markdown; test_scene_fields fails when the document differs).
//
// A field the table cannot read alone (a vector, a list, an object, a field whose check needs
// another) is a documented row without a slot: the table lists it (its key is known, its
// default and meaning documented), and the section's parser reads it by hand.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "json_reader.hpp"

namespace invfem::app {

// An interval of accepted numbers; an open end excludes its bound.
struct Range {
  double lo = 0, hi = 0;
  bool open_lo = false, open_hi = false;
};

// Where a field's value lives in S: get reads it, set writes it. A plain member of S converts
// (`.member = &S::fps`); `at<S>(ref)` reaches a member of a settings struct that S holds; a
// conversion (a unit, a sentinel, one value feeding two settings) is a Slot built from its own
// get and set, written once beside its row.
template <class S, class T> struct Slot {
  std::function<T(const S&)> get;
  std::function<void(S&, const T&)> set;
  std::vector<std::string> names;  // a string slot that names an enum: its accepted values

  Slot(T S::*m) : get([m](const S& s) { return s.*m; }), set([m](S& s, const T& v) { s.*m = v; }) {}
  Slot(std::function<T(const S&)> g, std::function<void(S&, const T&)> s, std::vector<std::string> n = {})
      : get(std::move(g)), set(std::move(s)), names(std::move(n)) {}
};

// The slot of the member `ref` returns, e.g. at<Scene>([](auto& s) -> auto& { return s.solver.max_dt; }).
template <class S, class Ref> auto at(Ref ref) {
  using T = std::remove_cvref_t<decltype(ref(std::declval<S&>()))>;
  return Slot<S, T>([ref](const S& s) -> T { return ref(s); }, [ref](S& s, const T& v) { ref(s) = v; });
}

// A string field that names the enum member `ref` returns: (name, value) pairs, in the order the
// document lists them.
template <class S, class E, class Ref> Slot<S, std::string> named(Ref ref, std::vector<std::pair<std::string, E>> names) {
  std::vector<std::string> keys;
  for (const auto& n : names) keys.push_back(n.first);
  return Slot<S, std::string>(
      [ref, names](const S& s) {
        for (const auto& [key, value] : names)
          if (ref(s) == value) return key;
        return std::string();
      },
      [ref, names](S& s, const std::string& key) {
        for (const auto& [k, value] : names)
          if (k == key) ref(s) = value;
      },
      std::move(keys));
}

template <class S> struct Field {
  // An optional number is read only when given (no default: "none"), and written only when set.
  using Member = std::variant<std::monostate, Slot<S, double>, Slot<S, std::optional<double>>, Slot<S, int>,
                              Slot<S, bool>, Slot<S, std::string>>;
  std::string key;
  Member member;                     // monostate: documented here, read by hand
  std::string unit = "–";
  Range range;                       // double and int members
  std::vector<std::string> choices;  // string members: the accepted values (empty: any, or the slot's names)
  std::string expected;              // the error's "expected ..." when not accepted ("": from range or choices)
  std::string description;           // one line
  std::string default_text;          // rows without a slot, or whose default depends on the scene

  const std::vector<std::string>& accepted() const {
    if (const auto* s = std::get_if<Slot<S, std::string>>(&member); s && choices.empty()) return s->names;
    return choices;
  }
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
    for (const auto& d : fields_) std::visit([&](const auto& m) { read_one(f, spec, d, m); }, d.member);
  }
  // Writes every field with a member into j.
  void write(nlohmann::json& j, const S& spec) const {
    for (const auto& d : fields_)
      std::visit([&](const auto& m) {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, Slot<S, std::optional<double>>>) {
          if (const auto v = m.get(spec)) j[d.key] = *v;
        } else if constexpr (!std::is_same_v<M, std::monostate>) {
          j[d.key] = m.get(spec);
        }
      }, d.member);
  }
  // The table's rows for the document, defaults from a default-constructed spec.
  std::vector<FieldRow> rows() const {
    const S defaults{};
    std::vector<FieldRow> out;
    for (const auto& d : fields_) {
      FieldRow r{d.key, d.unit, d.default_text, d.description};
      std::visit([&](const auto& m) { describe(defaults, d, m, r); }, d.member);
      out.push_back(std::move(r));
    }
    return out;
  }
  std::string markdown() const { return markdown_table(rows()); }

 private:
  static void read_one(const Fields&, S&, const Field<S>&, std::monostate) {}
  static void read_one(const Fields& f, S& s, const Field<S>& d, const Slot<S, double>& m) {
    m.set(s, checked(f, d, m.get(s)));
  }
  static void read_one(const Fields& f, S& s, const Field<S>& d, const Slot<S, std::optional<double>>& m) {
    if (f.has(d.key)) m.set(s, checked(f, d, 0.0));
  }
  // The number at d.key (fallback when absent) within d.range.
  static double checked(const Fields& f, const Field<S>& d, double fallback) {
    const double x = f.number(d.key, fallback);
    const Range& r = d.range;
    if (r.open_lo ? !(x > r.lo) : !(x >= r.lo)) f.fail(d.key, d.expected.empty() ? range_expected(r, false) : d.expected);
    if (r.open_hi ? !(x < r.hi) : !(x <= r.hi)) f.fail(d.key, d.expected.empty() ? range_expected(r, false) : d.expected);
    return x;
  }
  static void read_one(const Fields& f, S& s, const Field<S>& d, const Slot<S, int>& m) {
    m.set(s, f.integer(d.key, m.get(s), static_cast<int>(d.range.lo), static_cast<int>(d.range.hi)));
  }
  static void read_one(const Fields& f, S& s, const Field<S>& d, const Slot<S, bool>& m) {
    m.set(s, f.boolean(d.key, m.get(s)));
  }
  static void read_one(const Fields& f, S& s, const Field<S>& d, const Slot<S, std::string>& m) {
    const std::string v = f.string(d.key, m.get(s));
    const auto& accepted = d.accepted();
    if (!accepted.empty() && std::find(accepted.begin(), accepted.end(), v) == accepted.end())
      f.fail(d.key, d.expected.empty() ? choices_expected(accepted) : d.expected);
    m.set(s, v);
  }

  static void describe(const S&, const Field<S>&, std::monostate, FieldRow&) {}
  static void describe(const S& defaults, const Field<S>& d, const Slot<S, double>& m, FieldRow& r) {
    r.default_text = format_number(m.get(defaults));
    r.meaning = with_sentence(r.meaning, range_sentence(d.range));
  }
  static void describe(const S&, const Field<S>& d, const Slot<S, std::optional<double>>&, FieldRow& r) {
    r.default_text = "none";
    r.meaning = with_sentence(r.meaning, range_sentence(d.range));
  }
  static void describe(const S& defaults, const Field<S>& d, const Slot<S, int>& m, FieldRow& r) {
    r.default_text = std::to_string(m.get(defaults));
    r.meaning = with_sentence(r.meaning, range_sentence(d.range));
  }
  static void describe(const S& defaults, const Field<S>&, const Slot<S, bool>& m, FieldRow& r) {
    r.default_text = m.get(defaults) ? "true" : "false";
  }
  static void describe(const S& defaults, const Field<S>& d, const Slot<S, std::string>& m, FieldRow& r) {
    // A default that depends on the rest of the scene is the row's own text.
    const std::string value = m.get(defaults);
    if (r.default_text.empty() && !value.empty()) r.default_text = "`" + value + "`";
    const auto& accepted = d.accepted();
    if (!accepted.empty()) {
      std::string list;
      for (std::size_t k = 0; k < accepted.size(); ++k)
        list += (k == 0 ? "" : k + 1 == accepted.size() ? " or " : ", ") + ("`" + accepted[k] + "`");
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
