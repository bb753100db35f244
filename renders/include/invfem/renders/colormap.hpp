#pragma once
// Scalar -> colour maps for per-vertex fields (stress, det F, ...). Colours are RGB in [0, 1].
#include "invfem/core/math/types.hpp"

namespace invfem::renders {

enum class Colormap {
  CoolWarm,  // diverging blue - light grey - red; for signed fields centred on a range midpoint
  Heat,      // black - red - yellow - white; for magnitudes
  Rainbow,   // blue - cyan - green - yellow - red
};

// t is clamped to [0, 1]; t must not be NaN (std::invalid_argument).
Vec3 colormap(Colormap map, double t);

}  // namespace invfem::renders
