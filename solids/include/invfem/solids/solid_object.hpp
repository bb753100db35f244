#pragma once
// A tetrahedral solid as a simulated object of the World (core/world.hpp): its nodes with lumped
// masses, the ITF04 volumetric force, its boundary surface (with the map to its nodes) and pins.
#include <optional>
#include <string>
#include <vector>

#include "invfem/core/integrate/edge_spring_force.hpp"
#include "invfem/core/world/world.hpp"
#include "invfem/solids/tet_mesh.hpp"
#include "invfem/solids/tet_solid_force.hpp"

namespace invfem {

// A solid's stage in the World's step (SimObject::stage): the first, so that the cloths (a later
// stage) see it at t + dt.
inline constexpr int kSolidStage = 0;

struct SolidObjectParams {
  TetMaterial material;
  Vec3 velocity = Vec3::Zero();          // initial velocity of every free node [m/s]
  Vec3 gravity = Vec3(0, -9.81, 0);      // [m/s^2]
  std::vector<PinGroup> pins;            // over the mesh's nodes
  // Starting positions (n x 3, the mesh's node order; scramble.hpp, initial_shape.hpp); empty:
  // the rest positions. The rest shape stays the mesh's either way.
  std::optional<Points> initial_positions;
  // The mass-spring baseline (core/edge_spring_force.hpp): springs on the tet edges replace the
  // FE force; material.density still gives the masses, the rest of `material` is unused. The
  // tets are kept to report inverted elements as the FE force does.
  std::optional<MassSpringMaterial> mass_spring;
};

// `mesh` must be validated and positively oriented (validate_and_orient). The object starts at
// params.initial_positions (else at its rest shape), its force and surface updated there at t = 0,
// pinned nodes moving with their pins. Throws std::invalid_argument (material, masses, initial
// positions of the wrong size or not finite) naming the problem.
SimObject make_solid_object(const std::string& name, const TetMesh& mesh, SolidObjectParams params);

// The same, with its tet force kept for what needs it back (fracture: FracturingSolid::force).
struct SolidObject {
  SimObject object;
  TetSolidForce* tet_force = nullptr;  // among object.forces; null for the mass-spring baseline
};
SolidObject make_solid(const std::string& name, const TetMesh& mesh, SolidObjectParams params);

}  // namespace invfem
