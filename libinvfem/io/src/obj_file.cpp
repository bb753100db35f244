#include "invfem/core/io/obj_file.hpp"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "invfem/core/io/text_file.hpp"

namespace invfem {

namespace {

// Limits against malformed or hostile input (documented in obj_file.hpp). With at most 1 GiB of
// text every count and line number fits an int, and memory stays proportional to the file size.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 30;
constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;
constexpr std::size_t kMaxExtraLines = std::size_t{1} << 22;
constexpr std::size_t kMaxExtraWords = std::size_t{1} << 24;
constexpr std::size_t kMaxGroups = std::size_t{1} << 20;
constexpr double kMaxObjCoordinate = 1e9;  // see Parser::in_range

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// A token quoted in a message, cut so that a huge token cannot make a huge message.
std::string quote(std::string_view t) {
  constexpr std::size_t kMax = 40;
  std::string s = "'";
  s.append(t.substr(0, kMax));
  if (t.size() > kMax) s.append("...");
  s.append("'");
  return s;
}

// Whitespace-separated words of one line whose comment and line end were already removed.
class Words {
 public:
  explicit Words(std::string_view s) : s_(s) {}
  // The next word, or empty at the end of the line.
  std::string_view next() {
    while (pos_ < s_.size() && is_space(s_[pos_])) ++pos_;
    const std::size_t start = pos_;
    while (pos_ < s_.size() && !is_space(s_[pos_])) ++pos_;
    return s_.substr(start, pos_ - start);
  }
  // Everything after the words read so far, without surrounding whitespace.
  std::string_view rest() {
    while (pos_ < s_.size() && is_space(s_[pos_])) ++pos_;
    return s_.substr(pos_);
  }

 private:
  std::string_view s_;
  std::size_t pos_ = 0;
};

// Removes a comment (a '#' at the start of the line or of a word) and trailing whitespace
// (including the '\r' of CRLF).
std::string_view strip_line(std::string_view line) {
  const std::size_t n = line.size();
  const char* data = line.data();
  std::size_t from = 0;
  while (from < n) {
    const void* hit = std::memchr(data + from, '#', n - from);
    if (hit == nullptr) break;
    const std::size_t at = static_cast<std::size_t>(static_cast<const char*>(hit) - data);
    if (at == 0 || is_space(data[at - 1])) {
      line = line.substr(0, at);
      break;
    }
    from = at + 1;
  }
  while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
  return line;
}

enum class NumberStatus { ok, not_a_number, not_finite, out_of_range };

// Strict: the whole token, decimal (fixed or scientific), an optional single leading sign.
NumberStatus parse_real(std::string_view t, double& out) {
  if (!t.empty() && t.front() == '+') {
    t.remove_prefix(1);
    if (!t.empty() && (t.front() == '+' || t.front() == '-')) return NumberStatus::not_a_number;
  }
  if (t.empty()) return NumberStatus::not_a_number;
  double v = 0;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v, std::chars_format::general);
  if (p != t.data() + t.size()) return NumberStatus::not_a_number;
  // libstdc++ leaves the value untouched on out_of_range and does not say which side; both
  // overflow and underflow past the subnormals are rejected.
  if (ec == std::errc::result_out_of_range) return NumberStatus::out_of_range;
  if (ec != std::errc()) return NumberStatus::not_a_number;
  if (!std::isfinite(v)) return NumberStatus::not_finite;  // "nan", "inf", "infinity"
  out = v;
  return NumberStatus::ok;
}

// Strict integer: whole token, optional single leading sign. False if not an integer at all;
// `overflow` set if it is one but does not fit a long long.
bool parse_integer(std::string_view t, long long& out, bool& overflow) {
  overflow = false;
  if (!t.empty() && t.front() == '+') {
    t.remove_prefix(1);
    if (!t.empty() && (t.front() == '+' || t.front() == '-')) return false;
  }
  if (t.empty()) return false;
  long long v = 0;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (p != t.data() + t.size()) return false;
  if (ec == std::errc::result_out_of_range) {
    overflow = true;
    return true;
  }
  if (ec != std::errc()) return false;
  out = v;
  return true;
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  ObjFile run() {
    if (text_.size() > kMaxFileBytes)
      throw ObjError(path_ + ": text is " + std::to_string(text_.size()) +
                     " bytes, over the 1 GiB limit of the OBJ reader");
    if (const void* nul = std::memchr(text_.data(), '\0', text_.size())) {
      const auto at = static_cast<std::size_t>(static_cast<const char*>(nul) - text_.data());
      line_ = 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
      fail("NUL byte: this is not a text OBJ file");
    }
    if (std::all_of(text_.begin(), text_.end(), [](char c) { return is_space(c) || c == '\n'; }))
      throw ObjError(path_ + ": file is empty");
    // A carriage return with no line feed after it: lines ended the classic Mac OS way, which
    // would read as one long line of every number.
    for (std::size_t cr = text_.find('\r'); cr != std::string_view::npos; cr = text_.find('\r', cr + 1))
      if (cr + 1 < text_.size() && text_[cr + 1] != '\n') {
        line_ = 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(cr), '\n'));
        fail("a carriage return without a line feed: lines end with CR only (classic Mac OS); save the file "
             "with LF or CRLF line endings");
      }

    std::size_t pos = 0;
    while (pos < text_.size()) {
      const void* nl = std::memchr(text_.data() + pos, '\n', text_.size() - pos);
      const std::size_t end =
          nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - text_.data()) : text_.size();
      ++line_;
      if (end - pos > kMaxLineBytes)
        fail("line is " + std::to_string(end - pos) + " bytes long, over the 1 MiB limit");
      parse_line(strip_line(text_.substr(pos, end - pos)));
      pos = end + 1;
    }
    return finish();
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw ObjError(path_ + ":" + std::to_string(line_) + ": " + problem);
  }

  void parse_line(std::string_view line) {
    if (line.empty()) return;
    Words w(line);
    const std::string_view kw = w.next();
    const bool continued = line.back() == '\\';
    if (kw == "v") {
      if (continued) fail_continuation();
      parse_v(w);
    } else if (kw == "vt") {
      if (continued) fail_continuation();
      parse_vt(w);
    } else if (kw == "vn") {
      if (continued) fail_continuation();
      parse_vn(w);
    } else if (kw == "f") {
      if (continued) fail_continuation();
      parse_f(w);
    } else if (kw == "g" || kw == "o") {
      if (continued) fail_continuation();
      const std::string_view name = w.rest();
      set_group(name.empty() ? std::string_view("default") : name);
    } else if (kw == "s" || kw == "usemtl" || kw == "mtllib") {
      // Smoothing groups and materials mean nothing to the simulator.
    } else {
      parse_extra(kw, w);
    }
  }

  [[noreturn]] void fail_continuation() const {
    fail("line continuation with a trailing '\\' is not supported");
  }

  // Up to `max` words into `out`; returns the number of words, or max + 1 if there are more.
  static int split(Words& w, std::string_view* out, int max) {
    int n = 0;
    for (std::string_view t = w.next(); !t.empty(); t = w.next()) {
      if (n == max) return max + 1;
      out[n++] = t;
    }
    return n;
  }

  double real(std::string_view t, const char* item, long long index, const char* field) const {
    double x = 0;
    const NumberStatus s = parse_real(t, x);
    if (s == NumberStatus::ok) return x;
    std::string what = std::string(item) + " " + std::to_string(index) + ": " + field + ": ";
    switch (s) {
      case NumberStatus::not_finite:
        fail(what + quote(t) + " is not a finite number");
      case NumberStatus::out_of_range:
        fail(what + quote(t) + " is outside the range of a double");
      default:
        fail(what + "expected a number, got " + quote(t));
    }
  }

  // Positions and pattern coordinates within +-1e9 (whatever the unit): beyond, areas and
  // energies overflow a double (a 1e160 pattern read as "zero area") before any check sees them.
  void in_range(double x, std::string_view t, const char* item, long long index, const char* field) const {
    if (std::abs(x) > kMaxObjCoordinate)
      fail(std::string(item) + " " + std::to_string(index) + ": " + field + ": " + quote(t) +
           " is outside [-1e9, 1e9] (no mesh unit needs it; areas and forces would overflow)");
  }

  void parse_v(Words& w) {
    std::string_view t[7];
    const int n = split(w, t, 6);
    const long long index = static_cast<long long>(v_.size() / 3) + 1;
    if (n != 3 && n != 4 && n != 6)
      fail("vertex " + std::to_string(index) +
           ": expected x y z, x y z w or x y z r g b, got " +
           (n > 6 ? std::string("more than 6") : std::to_string(n)) + " numbers");
    static const char* const kFields[] = {"x", "y", "z", "4th number", "5th number", "6th number"};
    double x[6];
    for (int k = 0; k < n; ++k) x[k] = real(t[k], "vertex", index, kFields[k]);
    for (int k = 0; k < 3; ++k) in_range(x[k], t[k], "vertex", index, kFields[k]);
    v_.insert(v_.end(), x, x + 3);
  }

  void parse_vt(Words& w) {
    std::string_view t[4];
    const int n = split(w, t, 3);
    const long long index = static_cast<long long>(vt_.size() / 2) + 1;
    if (n < 1 || n > 3)
      fail("texture coordinate " + std::to_string(index) + ": expected u [v [w]], got " +
           (n > 3 ? std::string("more than 3") : std::to_string(n)) + " numbers");
    static const char* const kFields[] = {"u", "v", "w"};
    double x[3] = {0, 0, 0};
    for (int k = 0; k < n; ++k) x[k] = real(t[k], "texture coordinate", index, kFields[k]);
    for (int k = 0; k < n; ++k) in_range(x[k], t[k], "texture coordinate", index, kFields[k]);
    vt_.insert(vt_.end(), x, x + 2);
  }

  void parse_vn(Words& w) {
    std::string_view t[4];
    const int n = split(w, t, 3);
    const long long index = vn_count_ + 1;
    if (n != 3)
      fail("normal " + std::to_string(index) + ": expected x y z, got " +
           (n > 3 ? std::string("more than 3") : std::to_string(n)) + " numbers");
    static const char* const kFields[] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) (void)real(t[k], "normal", index, kFields[k]);
    ++vn_count_;
  }

  // One index of a face corner, 1-based or negative (relative) in the file, 0-based on return.
  int resolve(std::string_view t, int corner, const char* kind, const char* kinds,
              long long count) const {
    long long idx = 0;
    bool overflow = false;
    if (!parse_integer(t, idx, overflow))
      fail("face corner " + std::to_string(corner) + ": expected an integer " + kind +
           " index, got " + quote(t));
    const std::string have =
        ", the file has " + std::to_string(count) + " " + kinds + " so far";
    if (overflow)
      fail("face corner " + std::to_string(corner) + " refers to " + kind + " " + quote(t) + have);
    if (idx == 0)
      fail("face corner " + std::to_string(corner) + ": " + kind +
           " index 0 is invalid (OBJ indices start at 1)");
    const long long resolved = idx > 0 ? idx : count + idx + 1;
    if (resolved < 1 || resolved > count)
      fail("face corner " + std::to_string(corner) + " refers to " + kind + " " +
           std::to_string(idx) + (idx < 0 ? " (relative)" : "") + have);
    return static_cast<int>(resolved - 1);
  }

  void parse_f(Words& w) {
    corner_v_.clear();
    corner_vt_.clear();
    const long long nv = static_cast<long long>(v_.size() / 3);
    const long long nvt = static_cast<long long>(vt_.size() / 2);
    for (std::string_view t = w.next(); !t.empty(); t = w.next()) {
      const int corner = static_cast<int>(corner_v_.size()) + 1;
      // Split "i", "i/t", "i//n", "i/t/n".
      const std::size_t s1 = t.find('/');
      std::string_view vi = t.substr(0, s1), ti, ni;
      bool has_n = false;
      if (s1 != std::string_view::npos) {
        const std::string_view after = t.substr(s1 + 1);
        const std::size_t s2 = after.find('/');
        ti = after.substr(0, s2);
        if (s2 != std::string_view::npos) {
          ni = after.substr(s2 + 1);
          has_n = true;
        }
        // "i/" and "i/t/" and "i//" and anything with a third slash are malformed.
        if ((!has_n && ti.empty()) || (has_n && ni.empty()) ||
            ni.find('/') != std::string_view::npos)
          fail("face corner " + std::to_string(corner) +
               ": expected i, i/t, i//n or i/t/n, got " + quote(t));
      }
      if (vi.empty())
        fail("face corner " + std::to_string(corner) + ": expected i, i/t, i//n or i/t/n, got " +
             quote(t));
      corner_v_.push_back(resolve(vi, corner, "vertex", "vertices", nv));
      corner_vt_.push_back(ti.empty() ? -1
                                      : resolve(ti, corner, "texture coordinate",
                                                "texture coordinates", nvt));
      if (has_n) (void)resolve(ni, corner, "normal", "normals", vn_count_);
      if ((corner_vt_.back() < 0) != (corner_vt_.front() < 0))
        fail("face corner " + std::to_string(corner) +
             (corner_vt_.back() < 0 ? " has no texture coordinate but corner 1 has one"
                                    : " has a texture coordinate but corner 1 has none") +
             " (a face gives vt for all corners or none)");
    }
    const std::size_t n = corner_v_.size();
    if (n < 3)
      fail("face with " + std::to_string(n) + " corner" + (n == 1 ? "" : "s") +
           ", a face needs at least 3");
    check_distinct();
    if (current_group_ < 0) {  // faces before any g/o
      groups_.emplace_back();
      group_index_.emplace(std::string(), 0);
      current_group_ = 0;
    }
    for (std::size_t k = 1; k + 1 < n; ++k) {
      f_.insert(f_.end(), {corner_v_[0], corner_v_[k], corner_v_[k + 1]});
      fvt_.insert(fvt_.end(), {corner_vt_[0], corner_vt_[k], corner_vt_[k + 1]});
      face_group_.push_back(current_group_);
    }
    if (n > 3) ++polygons_split_;
  }

  void check_distinct() {
    const std::size_t n = corner_v_.size();
    int dup = -1;
    if (n <= 8) {
      for (std::size_t a = 0; a < n && dup < 0; ++a)
        for (std::size_t b = a + 1; b < n; ++b)
          if (corner_v_[a] == corner_v_[b]) {
            dup = corner_v_[a];
            break;
          }
    } else {
      sorted_ = corner_v_;
      std::sort(sorted_.begin(), sorted_.end());
      const auto it = std::adjacent_find(sorted_.begin(), sorted_.end());
      if (it != sorted_.end()) dup = *it;
    }
    if (dup < 0) return;
    std::string corners;
    for (std::size_t k = 0; k < n; ++k)
      if (corner_v_[k] == dup) corners += (corners.empty() ? "" : " and ") + std::to_string(k + 1);
    fail("degenerate face: corners " + corners + " are the same vertex " +
         std::to_string(dup + 1));
  }

  void set_group(std::string_view name) {
    const auto [it, inserted] =
        group_index_.emplace(std::string(name), static_cast<int>(groups_.size()));
    if (inserted) {
      if (groups_.size() >= kMaxGroups) fail("more than 1,048,576 distinct groups");
      groups_.emplace_back(name);
    }
    current_group_ = it->second;
  }

  void parse_extra(std::string_view kw, Words& w) {
    if (extra_.size() >= kMaxExtraLines)
      fail("more than 4,194,304 lines with uninterpreted keywords (this one is " + quote(kw) +
           ")");
    ObjFile::Extra e;
    e.keyword = std::string(kw);
    e.line = line_;
    for (std::string_view t = w.next(); !t.empty(); t = w.next()) {
      if (++extra_words_ > kMaxExtraWords)
        fail("more than 16,777,216 words on lines with uninterpreted keywords");
      e.words.emplace_back(t);
    }
    extra_.push_back(std::move(e));
  }

  ObjFile finish() {
    if (f_.empty())
      throw ObjError(path_ + ": no faces (" + std::to_string(v_.size() / 3) + " vertices, " +
                     std::to_string(line_) + " lines)");
    ObjFile out;
    out.path = path_;
    out.v = Eigen::Map<const Points>(v_.data(), static_cast<Eigen::Index>(v_.size() / 3), 3);
    std::vector<double>().swap(v_);
    out.vt = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>(
        vt_.data(), static_cast<Eigen::Index>(vt_.size() / 2), 2);
    std::vector<double>().swap(vt_);
    out.faces = Eigen::Map<const Tris>(f_.data(), static_cast<Eigen::Index>(f_.size() / 3), 3);
    std::vector<int>().swap(f_);
    out.face_vt = Eigen::Map<const Tris>(fvt_.data(), static_cast<Eigen::Index>(fvt_.size() / 3), 3);
    std::vector<int>().swap(fvt_);
    out.face_group = std::move(face_group_);
    out.groups = std::move(groups_);
    out.extra = std::move(extra_);
    out.polygons_split = polygons_split_;
    return out;
  }

  std::string_view text_;
  const std::string& path_;
  int line_ = 0;
  std::vector<double> v_, vt_;
  long long vn_count_ = 0;
  std::vector<int> f_, fvt_, face_group_;
  std::vector<std::string> groups_;
  std::unordered_map<std::string, int> group_index_;
  int current_group_ = -1;
  std::vector<ObjFile::Extra> extra_;
  std::size_t extra_words_ = 0;
  int polygons_split_ = 0;
  std::vector<int> corner_v_, corner_vt_, sorted_;  // scratch for one face
};

}  // namespace

ObjFile parse_obj_text(std::string_view text, const std::string& path) {
  return Parser(text, path).run();
}

ObjFile read_obj_file(const std::string& path) {
  std::string text;
  try {
    text = read_text_file(path, kMaxFileBytes, "the OBJ reader");
  } catch (const ObjError&) {
    throw;
  } catch (const MeshError& e) {
    throw ObjError(e.what());  // callers of the OBJ reader catch ObjError
  }
  return parse_obj_text(text, path);
}

TriangleSurface read_obj_surface(const std::string& path) {
  ObjFile f = read_obj_file(path);
  return TriangleSurface{std::move(f.v), std::move(f.faces), path};
}

}  // namespace invfem
