#pragma once
// A kinematic body from a rigged, animated character (core geometry skinned_character.hpp's
// data, read by core io skinned_file.hpp, skinned by skinning.hpp): at each time its vertices are
// the linear blend skinning of one clip, every mesh merged into one surface, then placed by a
// transform (units, up axis). The velocity is the time derivative of that same evaluation. The
// body acts on the cloth as every animated mesh body does (animated_mesh_body.hpp).
//
// Time: clip time c = t - start_time, the clip's duration D.
//   c in [0, D]: the clip at c.
//   c > D: hold the last pose (velocity 0), or loop:
//     loop_blend B = 0: c modulo D. The clip's last pose must then lie within step_motion_limit()
//       (query_radius - offset) of its first, vertex by vertex, or the constructor refuses it
//       (loop_jump names the distance and the vertex): the wrap is a jump in position, the same
//       whatever the step's length, so a larger one is what no step can follow (a node the body
//       passes deeper than the limit reads as outside).
//     B in (0, D/2]: the wrap cross-faded. The clip plays plainly for c in [0, D - B), then repeats
//       with period P = D - B: with r = (c - P) mod P,
//         r < B:  x = (1 - s) clip(P + r) + s clip(r),  s = 3u^2 - 2u^3, u = r / B,
//         r >= B: x = clip(r),
//       so the clip's last B seconds blend into its first B. At r = 0, x = clip(P) as the pass
//       before ends; at r = B, x = clip(B); s and ds/dt are 0 at u = 0 and ds/dt is 0 at u = 1, so
//       positions and velocities are continuous at every seam. The velocity is the exact time
//       derivative: (1 - s) v(P + r) + s v(r) + ds/dt (clip(r) - clip(P + r)).
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
  double loop_blend = 0;    // [s] with after_end Loop: the wrap's cross-fade B, in [0, duration / 2]
  // Applied to every skinned vertex: x_world = linear * x + translation; velocities by `linear`.
  Mat3 linear = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
  double friction = 0.3;    // Coulomb coefficient for the collision processing
  MeshSurfaceOptions mesh;  // contact search radius
};

// The largest distance between a clip's last pose and its first, over the vertices, after
// `linear` (a translation cancels): the jump after_end Loop makes at the wrap without a blend.
struct LoopJump {
  double distance = 0;     // [m] after `linear`
  Eigen::Index vertex = 0;  // where it is largest
};
LoopJump loop_jump(const SkinnedCharacter& character, int clip, const Mat3& linear = Mat3::Identity());

class SkinnedBody final : public AnimatedMeshBody {
 public:
  // Checks the settings (std::invalid_argument naming the body) and moves the body to t = 0.
  SkinnedBody(std::string name, SkinnedCharacter character, SkinnedBodySettings settings);

  const SkinnedCharacter& character() const { return character_; }
  const AnimationClip& clip() const { return character_.clips[static_cast<std::size_t>(settings_.clip)]; }

 private:
  // Where the clip is read at clip time c >= 0 (see above): x = (1 - s) clip(from) + s clip(to),
  // ds = ds/dt [1/s]; s = ds = 0 but across a blended wrap.
  struct ClipSample {
    double from = 0, to = 0, s = 0, ds = 0;
  };
  ClipSample sample(double c) const;
  void evaluate(double t, Points& x, Points& v) override;
  // The clip at clip time c in [0, duration], world frame.
  void skinned(double c, Points& x, Points* v) const;
  // Before the clip's start (c < 0): its first pose, or the pre-roll from the bind pose.
  void before_clip(double c, Points& x, Points& v) const;
  // Throws std::invalid_argument for a loop_blend out of range, or a loop without one whose wrap
  // jumps further than step_motion_limit().
  void check_loop() const;

  SkinnedCharacter character_;
  SkinnedBodySettings settings_;
  Points bind_;   // world frame
  Points first_;  // the clip's first pose, world frame
};

}  // namespace invfem
