#pragma once
// The self-collision layer (BFA02; ITF04 section 9: "For self-collisions we extract the boundary
// surface and apply the cloth collision algorithm of [BFA02]"), run after every step of either
// integrator (world.hpp, stage 4) on every taking-part object's surface (a cloth, a solid's
// boundary) and on the kinematic bodies' triangles where they are the body's shape (rigid mesh
// colliders, animated bodies: KinematicBody::surface_is_shape), which take part with infinite
// mass, as do pinned nodes. Analytic colliders (plane, sphere, gears...) act through the ITF04
// collision processing on the exact shape only.
//
// Per step, with x0 the surfaces at the step's start and v = (x(n+1) - x0) / dt the step's
// average velocity (collisions-BFA02.md section 1), after joining the nodes of recovering tets
// (inverted since a start the layer did not make, every node on the boundary:
// CollisionMesh::recovering), releasing the pairs that can undo each tangle at x0 (an edge through a face of a solid's boundary:
// candidates/tangles.hpp), releasing a cloth's crossings with a kinematic body
// at x0 from their pairs with the body (CollisionMesh::released, the recovery from an earlier
// step's fail-safe failure; stats `body_crossings`), passing back the smaller side of cloth that
// crosses cloth at x0 (candidates/tangles.hpp find_cloth_crossings, moved by
// response/pass_through.hpp; stats `cloth_crossings`) and holding those an analytic collider holds (infinite mass; a
// vertex the layer would push into a collider is held too and the step's layer work redone):
//   1. broad phase on the swept boxes (broad_phase/), giving candidates (candidates/)
//   2. repulsion at x0 (response/repulsion.hpp): pairs closer than the thickness
//   3. up to `impulse_passes` passes of CCD impulses (response/ccd_impulses.hpp)
//   4. impact zones until no pair may come within ccd_distance (response/impact_zones.hpp):
//      non-rigid (HVTG08's inelastic projection), rigid as the last resort
//   5. x(n+1) = x0 + dt v for every surface node; each node's end-of-step velocity gets the same
//      change as its average velocity (for the implicit step the two are one).
// Nodes off the surface (a solid's interior) are not touched. A solid's boundary is handled as a
// cloth (ITF04 section 9), its tet neighbours included: the layer stops the boundary, not the
// interior, from crossing, and the elements invert and recover through the interior
// (collision_mesh.hpp). The start state must be free of
// intersections; then the end state is too (up to the fail-safe's iteration cap, reported).
// Hence the tangle and crossing searches at x0 (edge-triangle tests over the whole surface,
// most of the layer's cost on a scene without contact) run only when the last step let pairs go
// (recovering tets, tangles, body or cloth crossings), left a step unresolved, or did not end where this step
// starts (the first step, a rebuilt mesh, another pass moved the surfaces).
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "invfem/collisions/colliders/implicit_surface.hpp"
#include "invfem/collisions/self_collision/broad_phase/broad_phase.hpp"
#include "invfem/collisions/self_collision/candidates/tangles.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/potential/cloth_contact_potential.hpp"
#include "invfem/collisions/self_collision/response/collider_keep_out.hpp"
#include "invfem/collisions/self_collision/response/impact_zones.hpp"
#include "invfem/core/world/world.hpp"

namespace invfem::collisions {

struct SelfCollisionSettings {
  double thickness = 1e-3;      // repulsion thickness h [m]: below the rest distance of non-neighbours
  double ccd_distance = 1e-5;   // separation the CCD and the zones keep [m], about 1e-2 h
  double friction = 0.3;        // Coulomb coefficient between surfaces
  int impulse_passes = 3;       // CCD impulse passes before the zones (PhysBAM's default)
  int max_zone_iterations = 100;
  // The impact zones' non-rigid rule (response/impact_zones.hpp): rounds 0 makes every zone rigid.
  ZoneProjectionSettings zone_projection;
  // How long [s] a tangle (candidates/tangles.hpp) may last, released only by the pairs that can
  // undo it, before it counts as stuck and its vertices leave the pairs among themselves. Long
  // enough for those pairs to undo an ordinary tangle over many steps, short enough that a stuck
  // one does not hold the surfaces crossed for long.
  double tangle_patience = 0.1;
  std::vector<std::string> excluded;  // names of objects that do not take part
  bool kinematic_bodies = true;       // kinematic bodies' shape triangles take part
  // A cloth's contact with itself also inside its implicit step: a barrier on its pairs closer
  // than the thickness and a CCD filter on Newton's line search (potential/cloth_contact_potential.hpp);
  // the layer after the step stays as the fail-safe.
  bool barrier = false;
};

// Throws std::invalid_argument naming the field for a bad setting (non-positive thickness, a ccd
// distance not below the thickness, negative friction, non-positive counts).
void validate(const SelfCollisionSettings& settings);

// In a step the impact zones could not resolve (left with collisions whatever is done), puts
// back the step's own velocity v_in on every vertex the layer moved further than any vertex
// moved in the step before it, plus the thickness. A failing fail-safe otherwise adds up its
// rounds' moves: a cape pressed between a flattened solid (infinite mass to it) and the ground
// was translated out of the ground and back round after round, 0.73 m in one step, and flung
// to 10^8 m within two frames (the quick mass-spring cape, README "Baselines"). Returns how
// many vertices were put back (stats `limited_vertices`).
// mesh: the step's CollisionMesh (movable, embedded vertices: these follow their nodes, synced);
// v_in, v: #V x 3 average velocities before and after the layer; projected_at: per vertex, its
// collider projection (-1 none), cleared where v is put back.
int limit_failed_step(const CollisionMesh& mesh, double dt, double thickness, const Points& v_in, Points& v,
                      std::vector<int>& projected_at);

// The layer's figures, per step and summed over a frame's steps in its FrameReport record
// (kSelfCollisionRecord; stats.jsonl "self_collision"): candidate pairs, repulsion impulses, CCD
// hits, impact zones (count and largest in vertices; of them, those that ended non-rigid and those
// that ended rigid), steps that ended with a collision the fail-safe could not resolve, and seconds.
struct SelfCollisionFigures {
  long long candidates = 0, proximity_impulses = 0, ccd_hits = 0;
  int impact_zones = 0, largest_zone = 0, projected_zones = 0, rigid_zones = 0, unresolved_steps = 0;
  long long tangled_pairs = 0;         // a solid boundary's edge-triangle crossings at a step's start (exempted)
  long long body_crossings = 0;        // a cloth's edge-triangle crossings with a kinematic body at a step's start (released)
  long long cloth_crossings = 0;       // cloth edge-triangle crossings of cloth at a step's start (passing back)
  long long collider_projections = 0;  // vertices the layer moved into an analytic collider, put back
  long long seam_impulses = 0;         // welds whose opening by the layer's impulses was undone (response/seams.hpp)
  long long limited_vertices = 0;      // vertices of unresolved steps put back to the step's own motion
  double seconds = 0;

  // Adds a step's figures to the frame's record (largest_zone: the largest), in this order.
  void add_to(PassRecord& record) const;
  // A frame's figures from its report (all zero when the layer did not run).
  static SelfCollisionFigures of(const FrameReport& report);
};
inline constexpr const char* kSelfCollisionRecord = "self_collision";

class SelfCollisionPass final : public StepPass {
 public:
  // analytic_colliders: the shapes of the kinematic bodies whose triangles do not take part (an
  // analytic plane, sphere or gear: KinematicBody::surface_is_shape false); a vertex the layer
  // would carry into one is put back out along its normal (stats `collider_projections`).
  explicit SelfCollisionPass(SelfCollisionSettings settings,
                             std::vector<std::shared_ptr<const ImplicitSurface>> analytic_colliders = {});
  void after_step(std::vector<SimObject>& objects, const StepPassInput& step, FrameReport& report) override;
  void open_record(FrameReport& report) const override { SelfCollisionFigures{}.add_to(report.pass(kSelfCollisionRecord)); }
  // kStepMotionEdges median edge lengths of the taking-part surfaces: the broad phase's candidates
  // per vertex grow with the square of its sweep in edges, and a step swept across a whole garment
  // (a body frame that jumps, steps of half a second) otherwise takes minutes and gigabytes.
  double step_motion_limit(const std::vector<SimObject>& objects) const override;
  static constexpr double kStepMotionEdges = 8;
  // Checkpoints: what carries over from one step to the next (the last step's end end_, whether
  // it let pairs go, the tangles' ages, the recovering tets), so a resumed run continues as the
  // one never stopped would. A checkpoint written before this state was kept (an empty blob)
  // resumes as a fresh start: the searches run and inverted boundary tets count as recovering.
  void save_state(StateWriter& out) const override;
  void restore_state(StateReader& in, std::vector<SimObject>& objects) override;
  const SelfCollisionSettings& settings() const { return settings_; }
  // With settings().barrier, a cloth's (an object with a surface and no tets) contact with itself,
  // made at its first step and again when its topology changes; null otherwise or for an excluded
  // object.
  ContactPotential* contact_potential(const SimObject& object, std::size_t index) override;

 private:
  // The object or body of this name does not take part (SelfCollisionSettings::excluded).
  bool excluded(const std::string& name) const;
  // Gathers the taking-part surfaces into mesh_ (topology built at the first step and again when
  // an object's topology_version changes, world.hpp; positions every step). A solid takes part
  // with its boundary SimObject::surface, or once cut (fracture) with its embedded material
  // surface SimObject::embedded (MBF04 2.3: what is written and drawn), whose vertices are points
  // of element copies: they enter the mesh with the nodes they lie in (collision_mesh.hpp
  // SurfaceEmbedding), impulses on them are spread to those nodes by their weights, impact zones
  // move the nodes, and the nodes are what is written back. Embedded vertices on a common node
  // are no pair (the two faces of a crack near its front are one material there).
  void gather(const std::vector<SimObject>& objects, const StepPassInput& step);
  // after_step's later stages (gather, above, is the first), each in a file of src/pass/ named for it.
  // The checkpoint's state (restore_state) once the mesh is gathered, if it fits.
  void adopt_resumed();
  // Releases for the step what the start holds crossed (recovering tets, tangles, a cloth's
  // crossings with a kinematic body: the counts), and finds the repulsion's candidates.
  struct StartCrossings {
    int recovering = 0, tangles = 0, crossings = 0;
    ClothCrossings cloth;  // cloth through cloth: the regions passing back (mesh_.passing), the pushes
  };
  StartCrossings release_start_crossings(double dt, SelfCollisionFigures& report);
  // Stages 1-4 on mesh_ (its inverse masses and exemptions as set), changing v. have_candidates:
  // candidates_ already holds the repulsion's candidates for these velocities and filters.
  void resolve(double dt, SelfCollisionFigures& report, const Points& v_in, Points& v, bool have_candidates,
               const ZoneConstraint& constrain);
  // Stages 1-2 (and the first broad phase unless have_candidates); returns the repulsions.
  long long repel(double dt, SelfCollisionFigures& report, const Points& v_in, Points& v, bool have_candidates);
  // Stage 3; repelled: the repulsion changed v since candidates_ were found. Returns true when the
  // last pass found nothing colliding.
  bool ccd_impulse_passes(double dt, SelfCollisionFigures& report, const Points& v_in, Points& v, bool repelled,
                          const CcdSettings& ccd);
  // Stage 5: the objects' surface nodes from v (v_in: the velocities before the layer).
  // kick: #V x 3 or empty, velocity in v - v_in that is a move only (push_through), not given to
  // the nodes' velocities.
  void write_back(std::vector<SimObject>& objects, double dt, const Points& v_in, const Points& v, const Points& kick,
                  const ColliderKeepOut& keep_out) const;
  // Keeps mesh_.passing per object (passing_), for the next step's contact potentials
  // (contact_potential hands it over) and the checkpoint.
  void keep_passing();
  // end_: where the surfaces ended the step, as the next step's gather will read them.
  void record_end(const std::vector<SimObject>& objects, const StepPassInput& step);

  // Sets mesh_.recovering (collision_mesh.hpp): the vertex pairs of the tets in boundary_tets_
  // that are inverted at the step's start (mesh_.x0) and were already so at a start the layer did
  // not make (fresh: !started_where_ended(): the first step, a rebuilt mesh, surfaces another
  // pass moved), kept in recovering_tets_ until they are sound again. Returns the number of pairs.
  int mark_recovering(bool fresh);

  SelfCollisionSettings settings_;
  std::vector<std::shared_ptr<const ImplicitSurface>> analytic_colliders_;
  BroadPhase broad_phase_;
  CollisionMesh mesh_;
  bool built_ = false;
  // True when the step's start (mesh_.x0) may hold a crossing, so the tangle and body-crossing
  // searches must run: the last step let pairs go or left one unresolved (left_crossable_), or
  // the start is not where the last step ended (end_: the first step, a rebuilt mesh, surfaces
  // another pass moved). Otherwise the last step ended free of intersections (self_collision_pass
  // stage 4's guarantee) and the searches would find nothing: they are skipped.
  bool may_start_crossed() const;
  // True when the step starts where the last one ended, bit for bit (end_).
  bool started_where_ended() const { return end_.rows() == mesh_.x0.rows() && end_ == mesh_.x0; }
  bool left_crossable_ = true;
  TangleAges tangle_ages_;  // the crossings at the last step's start and how long each has lasted
  Points end_;  // mesh_.x0 + dt v of the last step, #V x 3
  // Per object index: its surface vertices passing back through cloth (mesh_.passing at the last
  // step's start), which its contact potential lets pass in the next step; empty: none.
  std::vector<std::vector<char>> passing_;

  // Per mesh surface: the object it comes from (or -1 - k for kinematic body k).
  std::vector<int> source_;
  std::vector<std::uint64_t> versions_;  // per mesh surface: its object's topology_version when built
  // Per mesh surface: the body node of each of its vertices (-1 for an embedded vertex; empty for
  // a kinematic body) and its embedding (num_embedded 0 unless it is a cut solid's).
  std::vector<std::vector<int>> vertex_nodes_;
  std::vector<SurfaceEmbedding> embeddings_;
  // The tets of every solid (not cut) whose four nodes are all boundary vertices, as global
  // vertex indices in the tet's node order (positively oriented at rest, solids/tet_mesh.hpp).
  std::vector<std::array<int, 4>> boundary_tets_;
  std::vector<char> recovering_tets_;  // per boundary_tets_ entry: 1 while it recovers
  // What restore_state read, applied after the first gather() (which rebuilds the mesh) if the
  // mesh has the saved sizes.
  struct Resumed {
    Points end;
    bool left_crossable = true;
    TangleAges tangle_ages;
    std::vector<char> recovering_tets;
  };
  std::optional<Resumed> resumed_;
  Candidates candidates_;
  std::vector<std::pair<int, int>> edge_triangles_;
  // Per object index: its contact potential (or null) and the topology_version it was made for.
  std::vector<std::unique_ptr<ClothContactPotential>> potentials_;
  std::vector<std::uint64_t> potential_versions_;
  // Per object index: the positions its contact potential was made with (its edge mollifier's
  // reference, ClothContactPotential's `rest`): the surface at its first step, kept in the
  // checkpoint, so a resumed run's potential is the uninterrupted run's. Empty: none made yet.
  std::vector<Points> potential_rest_;
  // Per weld of mesh_: 1 once the seam was closed at a step's start (mark_open_welds); kept in the
  // checkpoint.
  std::vector<char> sewn_;
};

}  // namespace invfem::collisions
