#include "invfem/shells/shapes.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

namespace invfem {

TriangleSurface make_grid(double width, double height, int nx, int ny, const Vec3& origin, const Vec3& u_axis,
                          const Vec3& v_axis) {
  if (nx < 1 || ny < 1)
    throw std::invalid_argument("make_grid: need nx, ny >= 1, got " + std::to_string(nx) + ", " +
                                std::to_string(ny));
  if (!(width > 0) || !(height > 0) || !std::isfinite(width) || !std::isfinite(height))
    throw std::invalid_argument("make_grid: width and height must be finite and > 0");
  if (!origin.allFinite() || !(u_axis.cross(v_axis).norm() > 1e-12 * u_axis.norm() * v_axis.norm()))
    throw std::invalid_argument("make_grid: axes must be finite, non-zero and not parallel");
  const Vec3 u = u_axis.normalized(), v = v_axis.normalized();
  TriangleSurface mesh;
  mesh.source = "grid " + std::to_string(nx) + "x" + std::to_string(ny);
  mesh.x.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      mesh.x.row(j * (nx + 1) + i) =
          (origin + (width * i / nx) * u + (height * j / ny) * v).transpose();
  mesh.tris.resize(2 * nx * ny, 3);
  int t = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;  // a b / c d
      if ((i + j) % 2 == 0) {  // diagonal a-d
        mesh.tris.row(t++) << a, b, d;
        mesh.tris.row(t++) << a, d, c;
      } else {  // diagonal b-c
        mesh.tris.row(t++) << a, b, c;
        mesh.tris.row(t++) << b, d, c;
      }
    }
  return mesh;
}

void validate(const HalfTorusParams& p) {
  if (!(p.minor_radius > 0 && p.minor_radius < p.major_radius && std::isfinite(p.major_radius)))
    throw std::invalid_argument("make_half_torus: need 0 < minor radius < major radius, got " +
                                std::to_string(p.minor_radius) + " and " + std::to_string(p.major_radius));
  if (p.around < 3 || p.across < 1)
    throw std::invalid_argument("make_half_torus: need around >= 3 and across >= 1, got " + std::to_string(p.around) +
                                " and " + std::to_string(p.across));
}

TriangleSurface make_half_torus(double R, double r, int around, int across) {
  validate(HalfTorusParams{R, r, around, across});
  constexpr double kPi = 3.14159265358979323846;
  TriangleSurface s;
  s.source = "half torus " + std::to_string(around) + "x" + std::to_string(across);
  s.x.resize(around * (across + 1), 3);
  auto id = [&](int i, int j) { return (i % around) * (across + 1) + j; };
  for (int i = 0; i < around; ++i)
    for (int j = 0; j <= across; ++j) {
      const double theta = 2 * kPi * i / around, phi = kPi * j / across;
      const double rho = R + r * std::cos(phi);
      s.x.row(id(i, j)) << rho * std::cos(theta), r * std::sin(phi), -rho * std::sin(theta);
    }
  s.tris.resize(2 * around * across, 3);
  int t = 0;
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j) {
      // (i, j) -> (i+1, j) runs around the axis, (i, j) -> (i, j+1) over the tube: (d theta) x
      // (d phi) points out of the tube for theta counter-clockwise seen from +y.
      const int a = id(i, j), b = id(i + 1, j), c = id(i, j + 1), d = id(i + 1, j + 1);
      if ((i + j) % 2 == 0) {
        s.tris.row(t++) << a, b, d;
        s.tris.row(t++) << a, d, c;
      } else {
        s.tris.row(t++) << a, b, c;
        s.tris.row(t++) << b, d, c;
      }
    }
  return s;
}

TriangleSurface make_grid(const GridParams& p) {
  return make_grid(p.width, p.height, p.nx, p.ny, Vec3(-p.width / 2, 0, -p.height / 2), Vec3::UnitX(), Vec3::UnitZ());
}

TriangleSurface make_half_torus(const HalfTorusParams& p) {
  return make_half_torus(p.major_radius, p.minor_radius, p.around, p.across);
}

}  // namespace invfem
