#pragma once
// A kinematic body from a rigged, animated character (core geometry skinned_character.hpp's
// data, read by core io skinned_file.hpp, skinned by skinning.hpp): at each time its vertices are
// the linear blend skinning of one clip, every mesh merged into one surface, then placed by a
// transform (units, up axis). The velocity is the time derivative of that same evaluation. The
// body acts on the cloth as every animated mesh body does (animated_mesh_body.hpp).
//
// Time: clip time c = t - start_time.
//   c in [0, duration]: the clip at c.
//   c > duration: hold the last pose (velocity 0), or loop (c modulo the duration).
//   c < 0 without a pre-roll: the clip's first pose, still.
//   c < 0 with a pre-roll P > 0: the bind pose (skinning.hpp bind_pose, which a garment is
//     dressed in) until c = -P, then over the pre-roll the vertices go from the bind pose to the
//     clip's first pose, x = (1 - s) x_bind + s x_first with the smoothstep s = 3u^2 - 2u^3,
//     u = 1 + c/P (no jump in velocity as the pre-roll starts).
#include <string>

#include "invfem/collisions/colliders/animated_mesh_body.hpp"
#include "invfem/core/geometry/skinned_character.hpp"

namespace invfem {

struct SkinnedBodySettings {
  int clip = 0;             // index into the character's clips
  double start_time = 0;    // [s] simulation time at which the clip's time 0 is shown
  double pre_roll = 0;      // [s] >= 0, see above
  AnimationEnd after_end = AnimationEnd::Hold;
  // Applied to every skinned vertex: x_world = linear * x + translation; velocities by `linear`.
  Mat3 linear = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
  double friction = 0.3;    // Coulomb coefficient for the collision processing
  MeshSurfaceOptions mesh;  // contact search radius
};

class SkinnedBody final : public AnimatedMeshBody {
 public:
  // Checks the settings (std::invalid_argument naming the body) and moves the body to t = 0.
  SkinnedBody(std::string name, SkinnedCharacter character, SkinnedBodySettings settings);

  const SkinnedCharacter& character() const { return character_; }
  const AnimationClip& clip() const { return character_.clips[static_cast<std::size_t>(settings_.clip)]; }
  // The clip time shown at simulation time t (see above; negative during and before a pre-roll).
  double clip_time(double t) const;

 private:
  void evaluate(double t, Points& x, Points& v) override;
  // The clip at clip time c in [0, duration], world frame.
  void skinned(double c, Points& x, Points* v) const;

  SkinnedCharacter character_;
  SkinnedBodySettings settings_;
  Points bind_;   // world frame
  Points first_;  // the clip's first pose, world frame
};

}  // namespace invfem
