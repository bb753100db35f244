#pragma once
// Private to the io part: argument checks shared by the interchange writers (PLY, VTU, USDA).
// Each throws std::invalid_argument whose message starts with `who` (e.g. "write_ply(out.ply)").
#include <Eigen/Core>
#include <stdexcept>
#include <string>

#include "invfem/core/math/types.hpp"

namespace invfem::detail {

// Every coordinate of x (n x 3) finite.
inline void check_finite_points(const std::string& who, const Points& x) {
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (!x.row(i).allFinite())
      throw std::invalid_argument(who + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
}

// Every entry of an element table (tris or tets, rows x K) in [0, n).
template <class Elements>
void check_indices(const std::string& who, const char* element, const Elements& e, Eigen::Index n) {
  for (Eigen::Index r = 0; r < e.rows(); ++r)
    for (Eigen::Index k = 0; k < e.cols(); ++k)
      if (e(r, k) < 0 || e(r, k) >= n)
        throw std::invalid_argument(who + ": " + element + " " + std::to_string(r) + " index " +
                                    std::to_string(e(r, k)) + " outside [0, " + std::to_string(n) + ")");
}

}  // namespace invfem::detail
