#include "ply_check.hpp"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace invfem::detail {

namespace {

struct Property {
  std::string name;
  bool is_list = false;
  int count_size = 0;  // bytes of a list's count
  bool count_float = false;
  int size = 0;        // bytes of the scalar (or of each list item)
  bool is_float = false;
  bool is_signed = false;
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> props;
};

// Size in bytes, float?, signed? of a PLY scalar type name; size 0 if unknown.
void scalar_type(const std::string& t, int& size, bool& is_float, bool& is_signed) {
  is_float = false;
  is_signed = false;
  size = 0;
  if (t == "char" || t == "int8") size = 1, is_signed = true;
  else if (t == "uchar" || t == "uint8") size = 1;
  else if (t == "short" || t == "int16") size = 2, is_signed = true;
  else if (t == "ushort" || t == "uint16") size = 2;
  else if (t == "int" || t == "int32") size = 4, is_signed = true;
  else if (t == "uint" || t == "uint32") size = 4;
  else if (t == "float" || t == "float32") size = 4, is_float = true, is_signed = true;
  else if (t == "double" || t == "float64") size = 8, is_float = true, is_signed = true;
}

[[noreturn]] void fail(const std::string& path, const std::string& msg) {
  throw std::runtime_error(path + ": malformed PLY: " + msg);
}

class BinaryReader {
 public:
  BinaryReader(const std::string& data, std::size_t pos, bool big_endian)
      : data_(data), pos_(pos), swap_(big_endian) {}
  bool read(int size, bool is_float, bool is_signed, double& out) {
    if (pos_ + size > data_.size()) return false;
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, size);
    pos_ += size;
    if (swap_)
      for (int i = 0; i < size / 2; ++i) std::swap(b[i], b[size - 1 - i]);
    if (is_float) {
      if (size == 4) { float f; std::memcpy(&f, b, 4); out = f; }
      else { double d; std::memcpy(&d, b, 8); out = d; }
    } else if (size == 1) {
      out = is_signed ? double(static_cast<int8_t>(b[0])) : double(b[0]);
    } else if (size == 2) {
      uint16_t u; std::memcpy(&u, b, 2);
      out = is_signed ? double(static_cast<int16_t>(u)) : double(u);
    } else {
      uint32_t u; std::memcpy(&u, b, 4);
      out = is_signed ? double(static_cast<int32_t>(u)) : double(u);
    }
    return true;
  }
 private:
  const std::string& data_;
  std::size_t pos_;
  bool swap_;
};

}  // namespace

void check_ply_structure(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open file");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());

  // Header: text lines up to and including "end_header".
  std::size_t pos = 0;
  auto next_line = [&](std::string& line) {
    if (pos >= data.size()) return false;
    std::size_t end = data.find('\n', pos);
    if (end == std::string::npos) end = data.size();
    line = data.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = end + 1;
    return true;
  };
  std::string line;
  if (!next_line(line) || line != "ply") fail(path, "first line is not 'ply'");
  std::string format;
  std::vector<Element> elements;
  bool ended = false;
  while (next_line(line)) {
    std::istringstream ss(line);
    std::string word;
    ss >> word;
    if (word == "end_header") { ended = true; break; }
    if (word == "comment" || word == "obj_info" || word.empty()) continue;
    if (word == "format") {
      ss >> format;
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        fail(path, "unknown format '" + format + "'");
    } else if (word == "element") {
      Element e;
      if (!(ss >> e.name >> e.count) || e.count < 0) fail(path, "bad element line '" + line + "'");
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) fail(path, "property before any element");
      Property p;
      std::string type;
      ss >> type;
      if (type == "list") {
        std::string ctype, itype;
        ss >> ctype >> itype >> p.name;
        bool dummy;
        scalar_type(ctype, p.count_size, p.count_float, dummy);
        scalar_type(itype, p.size, p.is_float, p.is_signed);
        if (p.count_size == 0 || p.size == 0 || p.count_float)
          fail(path, "bad list property '" + line + "'");
        p.is_list = true;
      } else {
        ss >> p.name;
        scalar_type(type, p.size, p.is_float, p.is_signed);
        if (p.size == 0) fail(path, "unknown property type in '" + line + "'");
      }
      elements.back().props.push_back(p);
    } else {
      fail(path, "unexpected header line '" + line + "'");
    }
  }
  if (!ended) fail(path, "no end_header");
  if (format.empty()) fail(path, "no format line");
  long long n_vertices = -1;
  for (const Element& e : elements) {
    if (e.name != "vertex") continue;
    int xyz = 0;
    for (const Property& p : e.props)
      if (!p.is_list && (p.name == "x" || p.name == "y" || p.name == "z")) ++xyz;
    if (xyz != 3) fail(path, "vertex element lacks scalar x, y, z properties");
    n_vertices = e.count;
  }
  if (n_vertices < 0) fail(path, "no vertex element");

  // Body: every value of every element, in header order.
  const bool ascii = format == "ascii";
  std::istringstream text(ascii ? data.substr(pos) : std::string());
  BinaryReader bin(data, pos, format == "binary_big_endian");
  auto read = [&](int size, bool is_float, bool is_signed, double& v) {
    if (!ascii) return bin.read(size, is_float, is_signed, v);
    std::string tok;
    if (!(text >> tok)) return false;
    char* end = nullptr;
    v = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0') fail(path, "'" + tok + "' is not a number");
    return true;
  };
  for (const Element& e : elements) {
    const bool is_face = e.name == "face";
    for (long long i = 0; i < e.count; ++i) {
      for (const Property& p : e.props) {
        double v = 0;
        if (!p.is_list) {
          if (!read(p.size, p.is_float, p.is_signed, v))
            fail(path, "body ends inside " + e.name + " " + std::to_string(i));
          continue;
        }
        if (!read(p.count_size, false, false, v) || v < 0 || v != static_cast<long long>(v))
          fail(path, "bad list count in " + e.name + " " + std::to_string(i));
        const long long n = static_cast<long long>(v);
        const bool indices = is_face && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (indices && n < 3)
          fail(path, "face " + std::to_string(i) + " has " + std::to_string(n) + " vertices");
        for (long long k = 0; k < n; ++k) {
          if (!read(p.size, p.is_float, p.is_signed, v))
            fail(path, "body ends inside " + e.name + " " + std::to_string(i));
          if (indices && (v < 0 || v >= static_cast<double>(n_vertices)))
            fail(path, "face " + std::to_string(i) + " uses vertex " +
                           std::to_string(static_cast<long long>(v)) + " of " +
                           std::to_string(n_vertices));
        }
      }
    }
  }
}

}  // namespace invfem::detail
