#pragma once
// Private to solids/src: a whitespace tokenizer over a whole text file that remembers line
// numbers, parses numbers strictly (the whole token, finite reals) and throws MeshError with
// "<file>:<line>: <problem>" messages. Shared by the VTK, MEDIT and Gmsh readers.
#include <cstddef>
#include <string>
#include <string_view>

#include "invfem/core/io/mesh_error.hpp"

namespace invfem::detail {

// core/text_file.hpp's reader with the tet mesh readers' 4 GiB limit.
std::string read_text_file(const std::string& path);

class TextScanner {
 public:
  // `comment`: a character that starts a comment running to the end of the line (0 for none).
  TextScanner(std::string path, std::string text, char comment = 0);

  bool at_end();                          // only whitespace/comments left
  std::string_view peek();                // next token without consuming; empty at end
  std::string_view token(std::string_view what);  // MeshError "unexpected end of file" at end
  std::string_view line_rest();           // the rest of the current line, consumed with its '\n'
  void skip_line();                       // drop everything up to and including the next '\n'

  // Whole token as an integer / finite real. `what` and `index` (if >= 0) name the item.
  long long integer(std::string_view what, long long index = -1);
  double real(std::string_view what, long long index = -1);

  // A declared item count: an integer >= 0 that the rest of the file can hold, each item being
  // at least `tokens_per_item` tokens (>= 2 bytes each with a separator). Guards allocations.
  long long count(std::string_view what, int tokens_per_item);

  int line() const { return token_line_; }  // line (1-based) of the last token read
  const std::string& path() const { return path_; }
  std::size_t remaining_bytes() const { return text_.size() - pos_; }

  [[noreturn]] void fail(std::string_view problem) const;          // at the last token's line
  [[noreturn]] void fail_at(int line, std::string_view problem) const;

 private:
  void skip_space();
  std::string_view item_token(std::string_view what, long long index);
  std::string item_name(std::string_view what, long long index) const;

  std::string path_;
  std::string text_;
  char comment_;
  std::size_t pos_ = 0;
  int line_ = 1;        // line at pos_
  int token_line_ = 1;  // line of the last token returned
};

bool iequals(std::string_view a, std::string_view b);

}  // namespace invfem::detail
