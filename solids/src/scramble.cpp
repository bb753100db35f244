#include "invfem/solids/scramble.hpp"

#include <array>
#include <cmath>
#include <random>
#include <stdexcept>

namespace invfem {

namespace {

constexpr std::array<std::pair<ScrambleKind, std::string_view>, 5> kNames{{{ScrambleKind::Point, "point"},
                                                                           {ScrambleKind::Line, "line"},
                                                                           {ScrambleKind::Plane, "plane"},
                                                                           {ScrambleKind::Mirror, "mirror"},
                                                                           {ScrambleKind::Box, "box"}}};

// Uniform in [0, 1): the top 53 bits of one draw (the standard fixes mt19937_64's outputs, not
// those of uniform_real_distribution).
double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Uniform on the unit sphere: a point uniform in the cube [-1, 1)^3, kept when it lies in the
// unit ball (probability pi/6) and not too near the centre to normalize well.
Vec3 unit_vector(std::mt19937_64& rng) {
  while (true) {
    const Vec3 p(2 * uniform(rng) - 1, 2 * uniform(rng) - 1, 2 * uniform(rng) - 1);
    const double n2 = p.squaredNorm();
    if (n2 <= 1 && n2 > 1e-4) return p / std::sqrt(n2);
  }
}

}  // namespace

std::string_view scramble_kind_name(ScrambleKind kind) {
  for (const auto& [k, name] : kNames)
    if (k == kind) return name;
  return "unknown";
}

std::optional<ScrambleKind> scramble_kind_from_name(std::string_view name) {
  for (const auto& [k, n] : kNames)
    if (n == name) return k;
  return std::nullopt;
}

std::string scramble_kind_names() {
  std::string out;
  for (const auto& [k, name] : kNames) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

Points scramble_positions(const Points& X, const Scramble& s) {
  if (X.rows() == 0) throw std::invalid_argument("scramble: no positions to scramble");
  if (!X.allFinite()) throw std::invalid_argument("scramble: the positions are not all finite");
  if (s.kind == ScrambleKind::Box && !(std::isfinite(s.size) && s.size > 0))
    throw std::invalid_argument("scramble: a box needs a finite size > 0 [m], got " + std::to_string(s.size));
  const Eigen::RowVector3d c = X.colwise().mean();
  std::mt19937_64 rng(s.seed);
  Points x(X.rows(), 3);
  switch (s.kind) {
    case ScrambleKind::Point:
      x.rowwise() = c;
      break;
    case ScrambleKind::Line: {
      const Eigen::RowVector3d d = unit_vector(rng).transpose();
      for (Eigen::Index i = 0; i < X.rows(); ++i) x.row(i) = c + (X.row(i) - c).dot(d) * d;
      break;
    }
    case ScrambleKind::Plane:
    case ScrambleKind::Mirror: {
      const Eigen::RowVector3d n = unit_vector(rng).transpose();
      const double k = s.kind == ScrambleKind::Plane ? 1 : 2;  // projection or reflection
      for (Eigen::Index i = 0; i < X.rows(); ++i) x.row(i) = X.row(i) - k * (X.row(i) - c).dot(n) * n;
      break;
    }
    case ScrambleKind::Box:
      for (Eigen::Index i = 0; i < X.rows(); ++i)
        for (int k = 0; k < 3; ++k) x(i, k) = c(k) + s.size * (uniform(rng) - 0.5);
      break;
  }
  return x;
}

}  // namespace invfem
