#pragma once
// Repulsion (BFA02 section 4, collisions-BFA02.md section 4): for every candidate pair closer
// than the thickness h at the step's start x0, an inelastic impulse that cancels the approach,
// a repulsion that models the cloth's thickness, and Coulomb friction, applied to the average
// velocity v of the step.
//
// The spring part is taken at BFA02's limiter: the pair's normal relative velocity is raised to
// 0.1 d / dt (d = h - distance, the overlap), so a repulsion removes at most a tenth of the
// overlap per step and never throws cloth apart, whatever the step (the limiter, not k, binds
// for steps above a few milliseconds with any stiffness that keeps thin cloth from bouncing).
//
// Against a kinematic body (a collider's triangles) the thickness is kinematic_share h: the
// implicit step holds cloth pressed on a body at the body's offset, which scenes set to h, and a
// repulsion within the whole h acted on every resting node at every step, against the step's own
// contact (thousands of impulses a step on a dress, each moving one node: stretch, and friction
// counted twice).
#include "invfem/collisions/self_collision/candidates/candidates.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"

namespace invfem::collisions {

struct RepulsionSettings {
  double thickness = 1e-3;  // h [m]
  double friction = 0.3;    // mu
  double kinematic_share = 1.0;  // a pair with a kinematic body's side repels within kinematic_share h
};

// Applies the impulses in candidate order (vertex-face pairs, then edge-edge pairs), each on the
// velocities the earlier ones left; proximities are measured in parallel first. Returns the
// number of pairs that received an impulse.
long long apply_repulsion(const CollisionMesh& mesh, const Candidates& candidates, double dt,
                          const RepulsionSettings& settings, Points& v);

}  // namespace invfem::collisions
