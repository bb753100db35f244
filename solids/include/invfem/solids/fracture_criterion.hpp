#pragma once
// Where cracks start and run (meshing-and-fracture.md 2.4; ITF04 Figure 9): per element copy, the
// largest principal stress of its diagonal frame (P^ = dPsi/dsigma, the first Piola-Kirchhoff
// stress, so a threshold in Pa) or its accumulated plastic strain over a threshold. A copy that
// passes is cut by the plane orthogonal to its largest principal stress direction: the material
// direction V e_k (P = U diag(P^) V^T, so the traction P N on a material plane of normal N is
// largest for N = V e_k). With plasticity V is that of Fe = F Fp^-1, taken as a rest-space
// direction (the plastic rest shape's rotation is ignored: an approximation, documented).
// The plane goes through the cut points the root tet already carries from its neighbours (their
// mean; 2.4's snapping), else through its rest centroid, so a crack runs on continuously; on a
// seed (below) it is the seed plane.
#include <limits>
#include <string>
#include <vector>

#include "invfem/solids/tet_solid_force.hpp"
#include "invfem/solids/virtual_node_cut.hpp"

namespace invfem {

struct FractureCriterion {
  double max_principal_stress = std::numeric_limits<double>::infinity();  // [Pa], > 0
  // Accumulated plastic strain max_i |log lambda_i(Fp)| (lambda_i the singular values of Fp),
  // dimensionless, > 0; infinity: not used.
  double max_plastic_strain = std::numeric_limits<double>::infinity();
  // A crack runs on at a lower load than it starts: an element whose root tet already carries a
  // cut point (the crack front, cut by a neighbour) is cut at load >= front_fraction, any other
  // at load >= 1. In (0, 1]. Without it a crack's tip does not open until the whole front is cut
  // (partly cut tets stay materially connected), and the far field reaches the threshold first.
  double front_fraction = 0.5;
  int max_cuts_per_step = 4;   // element copies cut per check, crack front first, most loaded first (>= 1)
  int max_elements = 0;        // no cut once the mesh has this many element copies (0: no limit)
  // A crack seed (a scored plane, a notch): element copies whose root tet the rest-space plane
  // through seed_point with normal seed_normal crosses (its nodes on both sides), and whose rest
  // centroid lies in the box [seed_min, seed_max], are cut at seed_factor times the thresholds
  // (their load is divided by it) and cut along the seed plane itself (a scored plane: the scene
  // says where, the stress when). Such a tet is cut again, even if a neighbour's crack split it
  // first, while one of its edges across the plane is uncut, so once every seed tet is cut no
  // uncut edge crosses the plane in the box and the body is apart there. (Snapping seed cuts to the
  // neighbours' cut points instead let the plane wander, by the cut fraction's clamp, off edges
  // that cross it: the full-resolution Buddha stayed joined by a strand.) So a crack starts and
  // runs there rather than where a pin or a collider concentrates the load, and one crack, not a
  // band of chips, grows. Beyond the box, a crack runs on by the stress criterion. seed_factor in (0, 1]; 1: no seed. Rest space is the mesh's (the transform applied).
  double seed_factor = 1;
  Vec3 seed_point = Vec3::Zero(), seed_normal = Vec3::UnitY();  // normal: unit
  Vec3 seed_min = Vec3::Constant(-std::numeric_limits<double>::infinity());
  Vec3 seed_max = Vec3::Constant(std::numeric_limits<double>::infinity());
  // Throws std::invalid_argument "<where>: <field> ..." when a field is out of range or no
  // threshold is finite.
  void validate(const std::string& where) const;
};

struct CrackStart {
  int element = -1;      // the element copy
  double load = 0;       // max(stress / its threshold, plastic strain / its threshold), over the seed factor
  bool front = false;    // its root tet already carries a cut point
  bool seed = false;     // on the seed: cut along the seed plane itself (point lies on it)
  Vec3 normal;           // unit, rest space
  Vec3 point;            // rest space: the cut plane goes through it when the tet has no cut point
                         // yet (its centroid, or that projected onto the seed plane)
};

// max_i |log s_i| over the singular values of Fp^-1 (the plastic strain of the criterion).
double plastic_strain(const Mat3& Fp_inv);

// The element copies over the criterion at the force's last update, crack front first, then
// most loaded first (ties by index), at most max_cuts_per_step, none once the mesh has max_elements copies. Root tets already
// split into pieces are not cut again (at most one crack plane through a tet), except on the seed
// while an edge across the seed plane is uncut (then two: a neighbour's and the seed's). `force`
// must be the force over `mesh`'s element copies (same count).
std::vector<CrackStart> find_crack_starts(const VirtualNodeMesh& mesh, const TetSolidForce& force,
                                          const FractureCriterion& criterion);

// Cuts each start's root tet (cut_tet_by_plane, through the snapped point). Returns the cut
// points added; call update_topology afterwards.
int apply_crack_starts(VirtualNodeMesh& mesh, const std::vector<CrackStart>& starts);

}  // namespace invfem
