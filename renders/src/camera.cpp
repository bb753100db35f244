#include "invfem/renders/camera.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace invfem::renders {

void validate_camera(const Camera& c) {
  if (!c.position.allFinite()) throw std::invalid_argument("Camera.position is not finite");
  if (!c.target.allFinite()) throw std::invalid_argument("Camera.target is not finite");
  if (!c.up.allFinite()) throw std::invalid_argument("Camera.up is not finite");
  if (!(c.fov_y_degrees > 0.0 && c.fov_y_degrees < 180.0))
    throw std::invalid_argument("Camera.fov_y_degrees must be in (0, 180), got " +
                                std::to_string(c.fov_y_degrees));
  const Vec3 forward = c.target - c.position;
  const double scale = std::max({1.0, c.position.norm(), c.target.norm()});
  if (forward.norm() <= 1e-12 * scale)
    throw std::invalid_argument("Camera.position equals Camera.target: no view direction");
  if (c.up.norm() == 0.0 || forward.normalized().cross(c.up.normalized()).norm() < 1e-9)
    throw std::invalid_argument("Camera.up is zero or parallel to the view direction");
}

Eigen::Matrix4d view_matrix(const Camera& c, const Vec3& origin) {
  validate_camera(c);
  const Vec3 eye = c.position - origin;
  const Vec3 f = (c.target - c.position).normalized();
  const Vec3 s = f.cross(c.up).normalized();  // camera right
  const Vec3 u = s.cross(f);                   // camera up, orthogonal to f and s
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Eigen::Matrix4d perspective_matrix(double fov_y_degrees, double aspect, double near, double far) {
  if (!(aspect > 0.0) || !(near > 0.0) || !(far > near))
    throw std::invalid_argument("perspective_matrix: need aspect > 0 and 0 < near < far");
  const double t = 1.0 / std::tan(0.5 * fov_y_degrees * std::numbers::pi / 180.0);
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = t / aspect;
  p(1, 1) = t;
  p(2, 2) = -(far + near) / (far - near);
  p(2, 3) = -2.0 * far * near / (far - near);
  p(3, 2) = -1.0;
  return p;
}

Camera frame_camera(const Eigen::AlignedBox3d& box, double aspect, const Vec3& view_direction,
                    double fov_y_degrees) {
  if (!(aspect > 0.0) || !std::isfinite(aspect))
    throw std::invalid_argument("frame_camera: aspect must be positive, got " + std::to_string(aspect));
  if (!view_direction.allFinite() || view_direction.norm() == 0.0)
    throw std::invalid_argument("frame_camera: view_direction must be a finite non-zero vector");
  if (!(fov_y_degrees > 0.0 && fov_y_degrees < 180.0))
    throw std::invalid_argument("frame_camera: fov_y_degrees must be in (0, 180)");
  Vec3 center = Vec3::Zero();
  Eigen::AlignedBox3d frame(Vec3::Constant(-1.0), Vec3::Constant(1.0));  // fallback: unit cube
  if (!box.isEmpty() && box.min().allFinite() && box.max().allFinite()) {
    center = box.center();
    const double radius = 0.5 * box.diagonal().norm();
    // A point-like box would put the camera on top of it: frame a unit cube around it instead.
    if (radius > 1e-9 * std::max(1.0, center.norm())) frame = Eigen::AlignedBox3d(box.min() - center, box.max() - center);
  }

  Camera cam;
  const Vec3 f = view_direction.normalized();
  cam.up = std::abs(f.y()) > 0.999 ? Vec3(0.0, 0.0, -1.0) : Vec3(0.0, 1.0, 0.0);
  const Vec3 s = f.cross(cam.up).normalized();
  const Vec3 u = s.cross(f);
  // Camera at centre - d f. A corner o (relative to the centre) is at depth d + o.f, and fits
  // when |o.s| <= tan(half_x) (d + o.f) and |o.u| <= tan(half_y) (d + o.f); take the smallest d
  // that fits all eight corners, with 6% of the half-field kept as margin.
  const double half_y = 0.5 * fov_y_degrees * std::numbers::pi / 180.0;
  const double tan_y = 0.94 * std::tan(half_y);
  const double tan_x = 0.94 * aspect * std::tan(half_y);
  double distance = 0.0, nearest = 0.0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 o = frame.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
    distance = std::max({distance, std::abs(o.dot(s)) / tan_x - o.dot(f), std::abs(o.dot(u)) / tan_y - o.dot(f)});
    nearest = std::max(nearest, -o.dot(f));
  }
  // Keep the camera outside the box, a little in front of its nearest corner.
  distance = std::max(distance, nearest + 0.05 * frame.diagonal().norm());

  cam.target = center;
  cam.position = center - distance * f;
  cam.fov_y_degrees = fov_y_degrees;
  return cam;
}

}  // namespace invfem::renders
