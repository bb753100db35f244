#pragma once
// Test helper: a strict little XML parser (elements, attributes, text, the five predefined
// entities, an optional <?xml ...?> prolog). Enough to check the well-formedness of what the
// VTU/PVD writers emit; throws std::runtime_error with the byte offset on anything else.
#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace invfem::test {

struct XmlNode {
  std::string name;
  std::map<std::string, std::string> attrs;
  std::string text;  // concatenated character data, entities decoded
  std::vector<XmlNode> children;

  // Children named `n`, in document order.
  std::vector<const XmlNode*> all(const std::string& n) const {
    std::vector<const XmlNode*> out;
    for (const auto& c : children)
      if (c.name == n) out.push_back(&c);
    return out;
  }
  // The only child named `n`; throws if there is not exactly one.
  const XmlNode& one(const std::string& n) const {
    const auto v = all(n);
    if (v.size() != 1)
      throw std::runtime_error("<" + name + "> has " + std::to_string(v.size()) + " <" + n + "> children");
    return *v[0];
  }
  const std::string& attr(const std::string& a) const {
    auto it = attrs.find(a);
    if (it == attrs.end()) throw std::runtime_error("<" + name + "> has no attribute " + a);
    return it->second;
  }
};

class XmlParser {
 public:
  explicit XmlParser(const std::string& s) : s_(s) {}

  XmlNode document() {
    skip_space();
    if (s_.compare(p_, 5, "<?xml") == 0) {
      const auto end = s_.find("?>", p_);
      if (end == std::string::npos) fail("unterminated prolog");
      p_ = end + 2;
    }
    skip_space();
    XmlNode root = element();
    skip_space();
    if (p_ != s_.size()) fail("content after the root element");
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("XML error at byte " + std::to_string(p_) + ": " + what);
  }
  void skip_space() {
    while (p_ < s_.size() && (s_[p_] == ' ' || s_[p_] == '\n' || s_[p_] == '\t' || s_[p_] == '\r')) ++p_;
  }
  void expect(char c) {
    if (p_ >= s_.size() || s_[p_] != c) fail(std::string("expected '") + c + "'");
    ++p_;
  }
  static bool name_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.' || c == ':';
  }
  std::string name() {
    const std::size_t start = p_;
    while (p_ < s_.size() && name_char(s_[p_])) ++p_;
    if (p_ == start) fail("expected a name");
    return s_.substr(start, p_ - start);
  }
  // Character data up to `stop`, with entities decoded; a bare '<' or '&' is an error.
  std::string chars(char stop) {
    std::string out;
    while (p_ < s_.size() && s_[p_] != stop) {
      if (s_[p_] == '<') fail("'<' in character data");
      if (s_[p_] == '&') {
        static const std::pair<const char*, char> ents[] = {
            {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
        bool found = false;
        for (const auto& [ent, c] : ents)
          if (s_.compare(p_, std::char_traits<char>::length(ent), ent) == 0) {
            out += c;
            p_ += std::char_traits<char>::length(ent);
            found = true;
            break;
          }
        if (!found) fail("unknown entity");
        continue;
      }
      out += s_[p_++];
    }
    return out;
  }
  XmlNode element() {
    XmlNode node;
    expect('<');
    node.name = name();
    for (;;) {
      skip_space();
      if (p_ >= s_.size()) fail("unterminated start tag");
      if (s_[p_] == '/') {
        ++p_;
        expect('>');
        return node;
      }
      if (s_[p_] == '>') {
        ++p_;
        break;
      }
      const std::string a = name();
      skip_space();
      expect('=');
      skip_space();
      expect('"');
      std::string v = chars('"');
      expect('"');
      if (!node.attrs.emplace(a, v).second) fail("repeated attribute " + a);
    }
    for (;;) {
      node.text += chars('<');
      if (p_ >= s_.size()) fail("unterminated element <" + node.name + ">");
      if (s_.compare(p_, 2, "</") == 0) {
        p_ += 2;
        if (name() != node.name) fail("end tag does not match <" + node.name + ">");
        skip_space();
        expect('>');
        return node;
      }
      node.children.push_back(element());
    }
  }

  const std::string& s_;
  std::size_t p_ = 0;
};

}  // namespace invfem::test
