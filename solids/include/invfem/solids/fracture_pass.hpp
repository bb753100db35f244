#pragma once
// Ductile fracture during a run (ITF04 Figure 9; meshing-and-fracture.md Part 2): an after-step
// pass of the World (world.hpp stage 4) that checks each fracturing solid's criterion
// (fracture_criterion.hpp) at the step's end, cuts the loaded element copies (not those whose new
// surface would be born crossing the body's: crack_crossings.hpp) and, when the topology changed,
// rebuilds the solid on the enlarged mesh (rebuild_fractured_solid):
//  - nodes: positions and velocities carried from their parents (a virtual node starts where its
//    original is, with its velocity); masses from the weighted lumped masses, so each old node's
//    mass is split among its copies and mass and momentum are conserved across the split;
//  - the force: a new TetSolidForce on the weighted rest data with the parent copies' plastic
//    state (restore_plastic_state: the World re-evaluates the object where it is without a second
//    plastic flow, as a checkpoint's restore does, so resumed runs stay bit-identical);
//  - the surfaces: SimObject::surface (what the collision code reads) is the boundary of the
//    enlarged mesh: closed, one surface per piece, but each cut element's copies show whole, so
//    the two sides of a crack overlap by one element; SimObject::embedded (what is written and
//    drawn, once a crack opens) is the material surface of embedded_crack_surface.hpp: each copy
//    clipped to its side of the cut, with the crack polygons.
//  - pins: every copy of a pinned node is pinned to its original's anchor.
// Indices are stable (virtual_node_cut.hpp): old nodes keep theirs, so a cloth attached to the
// solid stays attached. Per-frame outputs are written with each frame's own topology.
//
// The pass's state (the cut mesh) goes into checkpoints ahead of the objects' (World::save_state),
// and restoring it rebuilds the solids before their positions are read.
#include <string>
#include <vector>

#include "invfem/core/world/world.hpp"
#include "invfem/solids/fracture_criterion.hpp"
#include "invfem/solids/tet_mesh.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "invfem/solids/virtual_node_cut.hpp"

namespace invfem {

// A solid as it was built, before any fracture: what every rebuild starts from.
struct FractureBase {
  TetMaterial material;         // per-element fields (fiber directions, plastic goals) per root tet
  double density = 1000;        // [kg/m^3]
  std::vector<PinGroup> pins;   // over the root nodes
};

// Rebuilds solid `o` on `mesh`'s current topology. With `change` (o holding the topology before
// it): positions, velocities and the plastic state carried from the parents. Without (a
// checkpoint's restore, which reads them next): positions at rest, velocities zero, Fp^-1 = Id.
// `force` is o's tet force, replaced by the new one in o.forces; returns the new one. Leaves the
// force to be updated at o.body.x (the World does so for an object whose node count changed).
TetSolidForce* rebuild_fractured_solid(SimObject& o, const TetSolidForce& force, const VirtualNodeMesh& mesh,
                                       const FractureBase& base, const TopologyChange* change);

struct FracturingSolid {
  std::string object;           // the SimObject's name
  TetMesh mesh;                 // its rest mesh (validated, positively oriented), node order of the object
  FractureCriterion criterion;
  TetSolidForce* force = nullptr;  // the object's tet force (make_solid); null: not fracturable
};

class FracturePass final : public StepPass {
 public:
  // Throws std::invalid_argument for an invalid criterion or an empty mesh.
  explicit FracturePass(std::vector<FracturingSolid> solids);

  void after_step(std::vector<SimObject>& objects, const StepPassInput& step, FrameReport& report) override;
  void save_state(StateWriter& out) const override;
  void restore_state(StateReader& in, std::vector<SimObject>& objects) override;

  const VirtualNodeMesh& mesh(std::size_t k) const { return solids_[k].mesh; }
  int events() const { return events_; }  // topology changes so far (not saved: a run's figure)
  // Starts not cut because their surface would have been born crossing (crack_crossings.hpp);
  // not saved: a run's figure. A refused start may pass at a later step.
  int refused() const { return refused_; }

 private:
  struct Solid {
    FracturingSolid spec;
    VirtualNodeMesh mesh;
    FractureBase base;
    int object = -1;  // index in the World's objects, bound at first use
    TetSolidForce* force = nullptr;  // the object's tet force, followed through rebuilds
  };
  void bind(std::vector<SimObject>& objects);

  std::vector<Solid> solids_;
  int events_ = 0;
  int refused_ = 0;
};

}  // namespace invfem
