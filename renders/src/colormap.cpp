#include "invfem/renders/colormap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace invfem::renders {
namespace {

// Piecewise-linear through evenly spaced control colours.
template <std::size_t N>
Vec3 piecewise(const std::array<Vec3, N>& stops, double t) {
  const double x = t * static_cast<double>(N - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(x), N - 2);
  const double w = x - static_cast<double>(i);
  return (1.0 - w) * stops[i] + w * stops[i + 1];
}

}  // namespace

Vec3 colormap(Colormap map, double t) {
  if (std::isnan(t)) throw std::invalid_argument("colormap: value is NaN");
  t = std::clamp(t, 0.0, 1.0);
  switch (map) {
    case Colormap::CoolWarm: {
      static const std::array<Vec3, 3> stops{Vec3(0.23, 0.30, 0.75), Vec3(0.87, 0.87, 0.87),
                                             Vec3(0.71, 0.02, 0.15)};
      return piecewise(stops, t);
    }
    case Colormap::Heat: {
      static const std::array<Vec3, 4> stops{Vec3(0.05, 0.0, 0.0), Vec3(0.85, 0.1, 0.0),
                                             Vec3(1.0, 0.85, 0.1), Vec3(1.0, 1.0, 1.0)};
      return piecewise(stops, t);
    }
    case Colormap::Rainbow: {
      static const std::array<Vec3, 5> stops{Vec3(0.1, 0.2, 0.9), Vec3(0.0, 0.8, 0.9),
                                             Vec3(0.2, 0.8, 0.2), Vec3(0.95, 0.85, 0.1),
                                             Vec3(0.9, 0.15, 0.1)};
      return piecewise(stops, t);
    }
  }
  throw std::invalid_argument("colormap: unknown Colormap value");
}

}  // namespace invfem::renders
