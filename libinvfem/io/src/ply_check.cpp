#include "ply_check.hpp"

#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

namespace invfem::detail {

namespace {

struct Scalar {
  int size = 0;  // bytes; 0 = unknown type name
  bool is_float = false;
  bool is_signed = false;
};

struct Property {
  std::string name;
  bool is_list = false;
  Scalar count;  // a list's count type
  Scalar item;   // the scalar type, or each list item's type
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> props;
  int header_line = 0;
};

// Element counts are capped where assimp's unsigned int counters still hold them.
constexpr long long kMaxElementCount = std::numeric_limits<int32_t>::max();

Scalar scalar_type(std::string_view t) {
  if (t == "char" || t == "int8") return {1, false, true};
  if (t == "uchar" || t == "uint8") return {1, false, false};
  if (t == "short" || t == "int16") return {2, false, true};
  if (t == "ushort" || t == "uint16") return {2, false, false};
  if (t == "int" || t == "int32") return {4, false, true};
  if (t == "uint" || t == "uint32") return {4, false, false};
  if (t == "float" || t == "float32") return {4, true, true};
  if (t == "double" || t == "float64") return {8, true, true};
  return {};
}

[[noreturn]] void fail(const std::string& path, const std::string& msg) {
  throw std::runtime_error(path + ": malformed PLY: " + msg);
}

// Printable excerpt of untrusted bytes for an error message.
std::string shown(std::string_view s) {
  std::string out;
  for (char c : s.substr(0, 40)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[u >> 4];
      out += hex[u & 15];
    }
  }
  if (s.size() > 40) out += "...";
  return out;
}

// Words of a line separated by spaces and tabs (the only separators the format uses).
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    if (line[i] == ' ' || line[i] == '\t') {
      ++i;
      continue;
    }
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    out.push_back(line.substr(start, i - start));
  }
  return out;
}

bool all_digits(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

// Strict ASCII value of type `t`: integers are [-]digits within the type's range (no sign for
// unsigned types); reals are [-]digits[.digits][e[+-]digits] (or .digits) and finite in the
// type. Anything else (hex, inf/nan, a leading '+', control bytes) is refused: assimp's own
// number scanners stop early on such text and then misalign the rest of the element.
bool parse_value(std::string_view tok, const Scalar& t, double& out) {
  std::string_view body = tok;
  const bool negative = !body.empty() && body.front() == '-';
  if (negative) body.remove_prefix(1);
  if (!t.is_float) {
    if (!all_digits(body) || body.size() > 12) return false;
    if (negative && !t.is_signed) return false;
    long long v = 0;
    std::from_chars(body.data(), body.data() + body.size(), v);
    if (negative) v = -v;
    const int bits = 8 * t.size;
    const long long lo = t.is_signed ? -(1LL << (bits - 1)) : 0;
    const long long hi = t.is_signed ? (1LL << (bits - 1)) - 1 : (1LL << bits) - 1;
    if (v < lo || v > hi) return false;
    out = static_cast<double>(v);
    return true;
  }
  std::size_t i = 0;
  std::size_t digits = 0;
  while (i < body.size() && body[i] >= '0' && body[i] <= '9') ++i, ++digits;
  if (i < body.size() && body[i] == '.') {
    ++i;
    while (i < body.size() && body[i] >= '0' && body[i] <= '9') ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < body.size() && (body[i] == 'e' || body[i] == 'E')) {
    ++i;
    if (i < body.size() && (body[i] == '+' || body[i] == '-')) ++i;
    if (!all_digits(body.substr(std::min(i, body.size())))) return false;
    i = body.size();
  }
  if (i != body.size()) return false;
  double v = 0;
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
  if (r.ec != std::errc() || r.ptr != tok.data() + tok.size()) return false;
  const double limit = t.size == 4 ? double(FLT_MAX) : DBL_MAX;
  if (!(std::fabs(v) <= limit)) return false;
  out = v;
  return true;
}

// Supplies the body's values element by element, for ASCII (one line per element, checked
// against the declared number of values) or binary (fixed-size fields).
class BodyReader {
 public:
  BodyReader(const std::string& path, const std::string& data, std::size_t pos, bool ascii,
             bool big_endian)
      : path_(path), data_(data), pos_(pos), ascii_(ascii), swap_(big_endian) {}

  // Starts element instance `index` of `e`: in ASCII, takes its line.
  void begin(const Element& e, long long index) {
    where_ = e.name + " " + std::to_string(index);
    if (!ascii_) return;
    if (pos_ >= data_.size()) fail(path_, "body ends before " + where_);
    std::size_t end = data_.find('\n', pos_);
    if (end == std::string::npos) end = data_.size();
    std::string_view line(data_.data() + pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    tokens_ = words(line);
    next_ = 0;
    if (tokens_.empty()) fail(path_, where_ + ": empty line where its values should be");
  }

  double value(const Scalar& t) {
    double v = 0;
    if (ascii_) {
      if (next_ >= tokens_.size())
        fail(path_, where_ + ": the line has " + std::to_string(tokens_.size()) +
                        " values, fewer than its properties need");
      const std::string_view tok = tokens_[next_++];
      if (!parse_value(tok, t, v))
        fail(path_, where_ + ": '" + shown(tok) + "' is not a valid " +
                        (t.is_float ? "real" : t.is_signed ? "integer" : "unsigned integer") +
                        " of " + std::to_string(t.size) + " bytes");
      return v;
    }
    if (data_.size() - std::min(pos_, data_.size()) < static_cast<std::size_t>(t.size))
      fail(path_, "binary body ends inside " + where_);
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, t.size);
    pos_ += t.size;
    if (swap_)
      for (int i = 0; i < t.size / 2; ++i) std::swap(b[i], b[t.size - 1 - i]);
    if (t.is_float) {
      if (t.size == 4) {
        float f;
        std::memcpy(&f, b, 4);
        v = f;
      } else {
        std::memcpy(&v, b, 8);
      }
      if (!std::isfinite(v)) fail(path_, where_ + ": a real value is not finite");
    } else if (t.size == 1) {
      v = t.is_signed ? double(static_cast<int8_t>(b[0])) : double(b[0]);
    } else if (t.size == 2) {
      uint16_t u;
      std::memcpy(&u, b, 2);
      v = t.is_signed ? double(static_cast<int16_t>(u)) : double(u);
    } else {
      uint32_t u;
      std::memcpy(&u, b, 4);
      v = t.is_signed ? double(static_cast<int32_t>(u)) : double(u);
    }
    return v;
  }

  // Values still available to a list of the current instance (an upper bound in binary).
  long long room(const Scalar& item) const {
    if (ascii_) return static_cast<long long>(tokens_.size() - next_);
    return static_cast<long long>((data_.size() - std::min(pos_, data_.size())) / item.size);
  }

  // Ends the instance: in ASCII the line must hold nothing more.
  void end(std::size_t declared) {
    if (ascii_ && next_ != tokens_.size())
      fail(path_, where_ + ": the line has " + std::to_string(tokens_.size()) +
                      " values, but its properties declare " + std::to_string(declared));
  }

  // After the last element: ASCII may only have trailing whitespace; binary nothing at all.
  void finish() const {
    if (pos_ >= data_.size()) return;
    if (!ascii_)
      fail(path_, std::to_string(data_.size() - pos_) +
                      " bytes after the last element (the binary body is longer than declared)");
    for (std::size_t i = pos_; i < data_.size(); ++i) {
      const char c = data_[i];
      if (c != ' ' && c != '\t' && c != '\r' && c != '\n')
        fail(path_, "data after the last element: '" + shown(std::string_view(data_).substr(i)) +
                        "'");
    }
  }

 private:
  const std::string& path_;
  const std::string& data_;
  std::size_t pos_;
  bool ascii_;
  bool swap_;
  std::string where_;
  std::vector<std::string_view> tokens_;
  std::size_t next_ = 0;
};

bool is_index_list(const Property& p) {
  return p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
}

}  // namespace

void check_ply_structure(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open file");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());

  // Header: text lines up to and including "end_header". `pos` is where the next line starts;
  // it never passes data.size() (a file may end right after "end_header").
  std::size_t pos = 0;
  int line_no = 0;
  auto next_line = [&](std::string_view& line) {
    if (pos >= data.size()) return false;
    std::size_t end = data.find('\n', pos);
    const std::size_t next = end == std::string::npos ? data.size() : end + 1;
    if (end == std::string::npos) end = data.size();
    line = std::string_view(data).substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = next;
    ++line_no;
    return true;
  };
  auto at = [&] { return "header line " + std::to_string(line_no) + ": "; };

  std::string_view line;
  if (!next_line(line) || line != "ply") fail(path, "first line is not 'ply'");
  std::string format;
  std::vector<Element> elements;
  bool ended = false;
  while (next_line(line)) {
    for (char c : line)
      if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f)
        fail(path, at() + "control byte in '" + shown(line) + "'");
    const std::vector<std::string_view> w = words(line);
    if (w.empty()) fail(path, at() + "empty line");
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (line == "end_header") {
      ended = true;
      break;
    }
    if (w[0] == "format") {
      if (!format.empty()) fail(path, at() + "second format line");
      if (!elements.empty()) fail(path, at() + "format line after an element");
      if (w.size() != 3 || w[2] != "1.0" ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        fail(path, at() + "expected 'format ascii|binary_little_endian|binary_big_endian 1.0', got '" +
                       shown(line) + "'");
      format = w[1];
    } else if (w[0] == "element") {
      if (format.empty()) fail(path, at() + "element before the format line");
      if (w.size() != 3 || !all_digits(w[2]) || w[2].size() > 10)
        fail(path, at() + "expected 'element NAME COUNT', got '" + shown(line) + "'");
      Element e;
      e.name = std::string(w[1]);
      std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
      e.header_line = line_no;
      if (e.count > kMaxElementCount)
        fail(path, at() + "element " + e.name + " count " + std::to_string(e.count) + " is too large");
      if (e.name != "vertex" && e.name != "face")
        fail(path, at() + "element '" + shown(e.name) + "' is not supported (only vertex and face)");
      for (const Element& o : elements)
        if (o.name == e.name) fail(path, at() + "second '" + e.name + "' element");
      elements.push_back(std::move(e));
    } else if (w[0] == "property") {
      if (elements.empty()) fail(path, at() + "property before any element");
      Property p;
      if (w.size() == 5 && w[1] == "list") {
        p.is_list = true;
        p.count = scalar_type(w[2]);
        p.item = scalar_type(w[3]);
        p.name = std::string(w[4]);
        if (p.count.size == 0 || p.count.is_float || p.item.size == 0)
          fail(path, at() + "bad list property '" + shown(line) + "'");
      } else if (w.size() == 3 && w[1] != "list") {
        p.item = scalar_type(w[1]);
        p.name = std::string(w[2]);
        if (p.item.size == 0) fail(path, at() + "unknown property type in '" + shown(line) + "'");
      } else {
        fail(path, at() + "expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME', got '" +
                       shown(line) + "'");
      }
      Element& e = elements.back();
      for (const Property& o : e.props)
        if (o.name == p.name)
          fail(path, at() + "element " + e.name + " declares property '" + shown(p.name) + "' twice");
      e.props.push_back(std::move(p));
    } else {
      fail(path, at() + "unexpected header line '" + shown(line) + "'");
    }
  }
  if (!ended) fail(path, "no end_header line");
  if (format.empty()) fail(path, "no format line");

  // Structure: exactly what the loader needs and assimp handles. A vertex element of scalars
  // including x, y, z; a face element with one integer index list and otherwise scalars.
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  for (const Element& e : elements) {
    if (e.props.empty())
      fail(path, "element " + e.name + " (header line " + std::to_string(e.header_line) +
                     ") has no properties");
    if (e.name == "vertex") {
      vertex = &e;
      int xyz = 0;
      for (const Property& p : e.props) {
        if (p.is_list) fail(path, "vertex property '" + shown(p.name) + "' is a list");
        if (p.name == "x" || p.name == "y" || p.name == "z") ++xyz;
      }
      if (xyz != 3) fail(path, "vertex element lacks scalar x, y, z properties");
    } else {
      face = &e;
      int lists = 0;
      for (const Property& p : e.props) {
        if (!p.is_list) continue;
        if (!is_index_list(p))
          fail(path, "face list property '" + shown(p.name) +
                         "' is not supported (only vertex_indices)");
        if (p.item.is_float) fail(path, "face vertex indices have a real type");
        ++lists;
      }
      if (lists != 1) fail(path, "face element needs exactly one vertex_indices list");
    }
  }
  if (!vertex) fail(path, "no vertex element");
  if (!face) fail(path, "no face element");
  if (face->count == 0) fail(path, "the face element has no faces");
  const long long n_vertices = vertex->count;

  // Body: every value of every element, in header order.
  BodyReader body(path, data, pos, format == "ascii", format == "binary_big_endian");
  for (const Element& e : elements) {
    const bool is_face = &e == face;
    for (long long i = 0; i < e.count; ++i) {
      body.begin(e, i);
      std::size_t declared = 0;
      for (const Property& p : e.props) {
        if (!p.is_list) {
          (void)body.value(p.item);
          ++declared;
          continue;
        }
        const double c = body.value(p.count);
        const long long n = static_cast<long long>(c);
        if (n < 0) fail(path, e.name + " " + std::to_string(i) + ": negative list count");
        if (n > body.room(p.item))
          fail(path, e.name + " " + std::to_string(i) + ": list count " + std::to_string(n) +
                         " exceeds the values present");
        if (is_face && n < 3)
          fail(path, "face " + std::to_string(i) + " has " + std::to_string(n) + " vertices");
        declared += 1 + static_cast<std::size_t>(n);
        for (long long k = 0; k < n; ++k) {
          const double v = body.value(p.item);
          if (is_face && (v < 0 || v >= static_cast<double>(n_vertices)))
            fail(path, "face " + std::to_string(i) + " uses vertex " +
                           std::to_string(static_cast<long long>(v)) + " of " +
                           std::to_string(n_vertices));
        }
      }
      body.end(declared);
    }
  }
  body.finish();
}

}  // namespace invfem::detail
