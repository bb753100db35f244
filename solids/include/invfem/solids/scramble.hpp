#pragma once
// Scrambled starting shapes of a solid: ITF04's robustness demonstration (section 1, Figure 1:
// a solid crushed to a point, a line or a plane, or turned inside out, returns to its rest shape).
// Only the positions change: the rest shape (and so every element's Dm) stays the mesh's.
//
// Every kind acts about the centroid c of the given positions (the unweighted mean of the rows):
//   point   x_i = c                                  every element has F = 0
//   line    x_i = c + d d^T (X_i - c)               projection onto a random line, F of rank 1
//   plane   x_i = X_i - n n^T (X_i - c)             projection onto a random plane, F of rank 2
//   mirror  x_i = X_i - 2 n n^T (X_i - c)           reflection: every element has F = (Id - 2 n n^T) F0,
//                                                   det F = -det F0 (all inverted when F0 is the rest)
//   box     x_i = c + size (u_i - 1/2)              u_i uniform in [0, 1)^3: a cube of edge `size`
// d and n are unit vectors uniform on the sphere. The random numbers come from std::mt19937_64
// (whose sequence the C++ standard fixes) turned into doubles here rather than by a
// std::*_distribution (whose algorithms are left to the library), so a seed gives the same bits
// with every compiler and standard library.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "invfem/core/math/types.hpp"

namespace invfem {

enum class ScrambleKind { Point, Line, Plane, Mirror, Box };

struct Scramble {
  ScrambleKind kind = ScrambleKind::Point;
  std::uint64_t seed = 0;  // the random line, plane, mirror normal or box positions
  double size = 0;         // box only: edge of the cube [m], > 0
};

// "point", "line", "plane", "mirror", "box".
std::string_view scramble_kind_name(ScrambleKind kind);
// The kind of a name above; empty for any other string.
std::optional<ScrambleKind> scramble_kind_from_name(std::string_view name);
// The names above, comma separated, for error messages.
std::string scramble_kind_names();

// The scrambled positions of X (n x 3, n >= 1). Throws std::invalid_argument when X is empty or
// not finite, or a box scramble has a size that is not finite and > 0.
Points scramble_positions(const Points& X, const Scramble& s);

}  // namespace invfem
