#pragma once
// A cloth, garment or shell as a simulated object of the World (core/world.hpp): its vertices
// with lumped masses (from the rest areas), the membrane force on the 3x2 F (ITF04 section 8),
// BMF03 bending, the seams' stitches, and pins. A cloth is its surface: surface vertex i is node i.
#include <optional>
#include <string>
#include <vector>

#include "invfem/core/integrate/edge_spring_force.hpp"
#include "invfem/core/math/materials/model.hpp"
#include "invfem/core/math/plasticity.hpp"
#include "invfem/core/world/world.hpp"
#include "invfem/shells/bending_force.hpp"
#include "invfem/shells/garment.hpp"
#include "invfem/shells/membrane_force.hpp"
#include "invfem/shells/stitch_force.hpp"
#include "invfem/shells/strain_limit_force.hpp"

namespace invfem {

// A cloth's stage in the World's step (SimObject::stage): after the solids (solid_object.hpp,
// stage 0), so that it sees them at t + dt and they are colliders for it, never the reverse.
inline constexpr int kClothStage = 1;

// Where the inversion test of ITF04 section 8 takes its known surface normal per triangle.
enum class InversionReference {
  None,       // no test (cloth: a flipped triangle is a rotated one)
  Rest,       // the triangle's normal in the rest shape (or the initial shape, for a pattern rest)
  Direction,  // one fixed direction for every triangle
};

struct ClothObjectParams {
  IsotropicModel model = RotatedLinear{};  // 3D Lame parameters (plane stress is taken inside)
  double thickness = 0.001;                // h [m]
  double density = 300;                    // [kg/m^3]; areal density = density * thickness
  double damping = 0.01;                   // in-plane Rayleigh coefficient k [s]
  BendingParams bending{1e-4, 1e-5};       // k_e [N m], k_d [N m s], optional plastic rest angles
  std::optional<PlasticParams> plasticity; // in-plane plasticity (ITF04 section 8), off when empty
  // No principal stretch against the rest shape (pattern) reaches it, within an implicit step
  // (strain_limit_force.hpp; C-IPC's garments use 1.10); 1 = none. The ITF04 step takes none.
  double strain_limit = 1;
  InversionReference inversion = InversionReference::None;
  Vec3 inversion_direction = Vec3::UnitY();  // for InversionReference::Direction
  StitchParams stitch;                     // for the garment's stitches and `extra_stitches`
  std::vector<Stitch> extra_stitches;      // stitches given besides the file's
  Vec3 velocity = Vec3::Zero();            // initial velocity of every free vertex [m/s]
  Vec3 gravity = Vec3(0, -9.81, 0);        // [m/s^2]
  std::vector<PinGroup> pins;              // over the garment's vertices
  // The mass-spring baseline (core/edge_spring_force.hpp): springs on the triangle edges, k from
  // young and thickness, replace the membrane; `model`, `damping` and `plasticity` are then unused
  // and inversion must be None.
  std::optional<MassSpringMaterial> mass_spring;
};

// Rest shape: the garment's pattern when it has one (rest bend angles flat), else its 3D surface
// (rest angles from its geometry). Initial positions: garment.initial, else the surface. Forces:
// membrane, bending, then stitches (when there are any), then the strain limit (when above 1). Throws std::invalid_argument naming
// `name` for bad parameters, a bad rest mesh or a bad stitch.
SimObject make_cloth_object(const std::string& name, const Garment& garment, ClothObjectParams params);

// The same for a plain surface (its own rest shape): a generated grid or shell.
SimObject make_cloth_object(const std::string& name, const TriangleSurface& surface, ClothObjectParams params);

}  // namespace invfem
