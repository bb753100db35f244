#pragma once
// Building blocks of the characters the skinning tests build by hand (core geometry
// skinned_character.hpp), and the skinning of a clip at one time.
#include <cmath>

#include "invfem/collisions/colliders/skinning.hpp"

namespace invfem::test {

// A node's local transform that only translates by p.
inline Mat4 translation(const Vec3& p) {
  Mat4 m = Mat4::Identity();
  m.block<3, 1>(0, 3) = p;
  return m;
}

// A rotation key: `degrees` about z.
inline Eigen::Quaterniond about_z(double degrees) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(degrees * M_PI / 180, Vec3::UnitZ()));
}

// The character's first clip at clip time t, no body and no transform: positions (#V x 3) and,
// when v is given, their velocities.
inline Points skin_first_clip(const SkinnedCharacter& c, double t, Points* v = nullptr) {
  Points x;
  skin_vertices(c, pose_skeleton(c, &c.clips[0], t), x, v);
  return x;
}

}  // namespace invfem::test
