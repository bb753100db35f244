#pragma once
// A cloth or shell as a simulated object of the World (core/world.hpp): its vertices with lumped
// masses, the membrane force on the 3x2 F (ITF04 section 8) and BMF03 bending, its pins. A cloth
// is its surface: surface vertex i is node i.
#include <string>
#include <vector>

#include "invfem/core/materials/model.hpp"
#include "invfem/core/world.hpp"
#include "invfem/shells/bending_force.hpp"
#include "invfem/shells/membrane_force.hpp"

namespace invfem {

struct ClothObjectParams {
  IsotropicModel model = RotatedLinear{};  // 3D Lame parameters (plane stress is taken inside)
  double thickness = 0.001;                // h [m]
  double density = 300;                    // [kg/m^3]; areal density = density * thickness
  double damping = 0;                      // in-plane Rayleigh coefficient k [s]
  BendingParams bending;                   // k_e [N m], k_d [N m s]
  Vec3 velocity = Vec3::Zero();            // initial velocity of every free vertex [m/s]
  Vec3 gravity = Vec3(0, -9.81, 0);        // [m/s^2]
  std::vector<PinGroup> pins;              // over the surface's vertices
};

// The rest shape is `surface` itself (rest angles from its geometry). Throws
// std::invalid_argument naming `name` for bad parameters or a bad rest mesh.
SimObject make_cloth_object(const std::string& name, const TriangleSurface& surface, ClothObjectParams params);

}  // namespace invfem
