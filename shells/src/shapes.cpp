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

}  // namespace invfem
