#pragma once
// Spur gear as an implicit surface (ITF04 Figures 6 and 7: bodies pulled through interlocking
// gears). Body frame: axis z through the origin, z in [-thickness/2, thickness/2].
//
// Tooth profile in polar coordinates (rho, theta) of the xy plane:
//   r(theta) = root + (outer - root) f(u),  u = teeth (theta - phase),
//   f(u) = (tanh(k (cos u - b)) - tanh(k (-1 - b))) / (tanh(k (1 - b)) - tanh(k (-1 - b)))
// so f(0) = 1 (a tooth tip at theta = phase), f(pi) = 0 (a gap bottom), smooth everywhere;
// k = sharpness flattens tips and gaps, b = tooth_bias > 0 makes teeth narrower than gaps
// (backlash, so a pair can turn without overlap).
//
// phi is the exact signed distance to the extruded profile, up to replacing the profile curve
// by a polyline of kSamplesPerTooth chords per tooth (chord error ~1e-5 of the radius with the
// defaults), so it is Lipschitz 1 and its zero set is the profile to within that error. The
// sign comes from the polyline's side at the nearest point (segment or vertex pseudo-normal),
// consistent with the distance. The normal is the outward unit direction between x and the
// nearest profile point, i.e. the gradient of phi.
#include <memory>
#include <vector>

#include "invfem/collisions/colliders/implicit_surface.hpp"
#include "invfem/collisions/colliders/moving_surface.hpp"
#include "invfem/core/geometry/surface.hpp"

namespace invfem {

struct GearParams {
  int teeth = 12;
  double outer_radius = 0.5;  // tooth tips [m]
  double root_radius = 0.4;   // gap bottoms [m]
  double thickness = 0.3;     // along z [m]
  double phase = 0;           // angle [rad] of one tooth's tip
  double sharpness = 2.5;     // k above
  double tooth_bias = 0.25;   // b above, in [0, 1)
};

// Throws std::invalid_argument naming the field: teeth outside [3, 1000], radii not 0 < root < outer,
// thickness <= 0, sharpness <= 0, tooth_bias outside [0, 1), anything non-finite.
void validate(const GearParams& params);

class GearSurface final : public ImplicitSurface {
 public:
  // Throws as validate(params) does.
  explicit GearSurface(const GearParams& params);

  double phi(const Vec3& x, double t) const override;
  Vec3 normal(const Vec3& x, double t) const override;
  // Half the thinner of the gear's thickness and its teeth's height.
  double step_motion_limit() const override;

  // The profile radius r(theta) and its derivative dr/dtheta.
  double tooth_radius(double theta) const;
  double tooth_radius_derivative(double theta) const;
  const GearParams& params() const { return p_; }

 private:
  static constexpr int kSamplesPerTooth = 256;
  GearParams p_;
  double f_lo_, f_scale_;  // tanh(k(-1-b)) and 1 / (tanh(k(1-b)) - tanh(k(-1-b)))
  std::vector<Vec2> profile_;  // r(theta_j) e(theta_j), theta_j = phase + 2 pi j / N, CCW
  // Signed distance in the xy plane and its outward unit gradient.
  double planar(double x, double y, Vec2& n) const;
};

// Two equal gears that mesh: axes along the pair frame's z, centers on its x axis at
// center -+ (D/2) x, D = outer + root + clearance. The first spins at +spin_rate, the second at
// -spin_rate (rad/s, right-hand about z), and the second's teeth are offset so that a tip of one
// faces a gap of the other on the line of centers at every time.
struct GearPairParams {
  GearParams gear;                       // gear.phase is the first gear's phase
  Vec3 center = Vec3::Zero();            // midpoint between the axes, world
  Mat3 orientation = Mat3::Identity();   // pair frame -> world rotation
  double spin_rate = 1.0;                // [rad/s]
  double clearance = 0.0;                // extra center distance [m], >= 0
};

struct GearPair {
  std::shared_ptr<MovingSurface> first;
  std::shared_ptr<MovingSurface> second;
  std::shared_ptr<const GearSurface> first_shape, second_shape;  // their body-frame shapes (gear_triangles)
};

// The gear's closed triangle surface in its body frame: a prism over its profile r(theta)
// sampled 16 times per tooth, from -thickness/2 to +thickness/2 along z.
TriangleSurface gear_triangles(const GearSurface& gear);

// Throws std::invalid_argument for bad gear parameters, a negative or non-finite clearance, a
// non-finite rate/center, or an orientation that is not a rotation.
GearPair make_gear_pair(const GearPairParams& params);

}  // namespace invfem
