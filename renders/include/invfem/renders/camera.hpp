#pragma once
// Pinhole camera for previews. World is Y-up (gravity along -y). Conventions follow OpenGL: the
// view matrix maps world to eye space where the camera looks down -z with +y up; the
// projection maps eye space to clip space with depth in [-1, 1].
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "invfem/core/math/types.hpp"

namespace invfem::renders {

struct Camera {
  Vec3 position{0.0, 1.0, 4.0};  // a scene's camera: looking at a body standing at the origin
  Vec3 target{0.0, 0.5, 0.0};
  Vec3 up{0.0, 1.0, 0.0};
  double fov_y_degrees = 35.0;  // full vertical field of view
};

// Throws std::invalid_argument naming the field if the camera is unusable: non-finite values,
// position == target, up parallel to the view direction, or fov outside (0, 180).
void validate_camera(const Camera& camera);

// World -> eye (rigid). `origin` is subtracted from world points first (the renderer shifts
// the scene to its centre so float vertex data keeps its precision far from the origin).
Eigen::Matrix4d view_matrix(const Camera& camera, const Vec3& origin = Vec3::Zero());

// Eye -> clip, OpenGL convention; aspect = width / height, 0 < near < far.
Eigen::Matrix4d perspective_matrix(double fov_y_degrees, double aspect, double near, double far);

// A camera looking along `view_direction` (from the camera towards the objects) at the box
// centre, just far enough back that all eight box corners fit the image with a 6% margin. Up
// is +y, or -z when looking straight up or down. An empty or zero-size box (e.g. all vertices
// equal) is framed as a 2 x 2 x 2 cube around its centre.
inline const Vec3 kDefaultViewDirection{-0.45, -0.35, -1.0};
Camera frame_camera(const Eigen::AlignedBox3d& box, double aspect,
                    const Vec3& view_direction = kDefaultViewDirection, double fov_y_degrees = 35.0);

}  // namespace invfem::renders
