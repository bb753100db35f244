// The scene's field tables (field_table.hpp), one per section of a scene file: each field's key,
// unit, range and one-line meaning, once, and the slot it fills in a module's settings or an
// object's description, whose member initializer is the default. The document's tables
// (apps/scenes/README.md) are generated from these (test_scene_fields).
#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

// A row documented here and read by hand names no slot; Field::member (a variant) cannot take a
// default initializer under GCC 12 (it crashes the compiler).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace invfem::app {

namespace {
// A material's `model`: the kinds by their names (model_kind_name), in ModelKind's order.
template <class S, class Ref> Slot<S, std::string> model_kind(Ref ref) {
  std::vector<std::pair<std::string, ModelKind>> names;
  for (ModelKind k : {ModelKind::RotatedLinear, ModelKind::NeoHookean, ModelKind::StVK, ModelKind::Spline,
                      ModelKind::Corotated, ModelKind::MassSpring})
    names.emplace_back(model_kind_name(k), k);
  return named<S, ModelKind>(ref, std::move(names));
}
}  // namespace

const FieldTable<Scene>& Scene::fields() {
  using S = Scene;
  static const FieldTable<S> table({
      {.key = "name", .description = "shown in captions", .default_text = "file stem"},
      {.key = "fps", .member = &S::fps, .unit = "1/s", .range = {1, 10000}, .description = "output frame rate"},
      {.key = "frames", .member = &S::frames, .unit = "count", .range = {0, 1000000},
       .description = "frames after frame 0 (the rest state)"},
      {.key = "first_frame_number", .member = &S::first_frame_number, .unit = "count", .range = {0, 1000000},
       .description = "the number of frame 0 in the files a run writes (`NNNN.obj`, previews) and in USD and PC2 "
                      "time codes, e.g. 1 for a DCC timeline that starts at 1; `--frames` and `energies.csv` "
                      "count from 0"},
      {.key = "gravity", .unit = "m/s²", .description = "acceleration of gravity", .default_text = "`[0, -9.81, 0]`"},
      {.key = "solver", .description = "time stepping", .default_text = "see below"},
      {.key = "self_collision", .description = "the self-collision layer", .default_text = "see below"},
      {.key = "settle", .description = "a settling phase before the colliders move", .default_text = "none; see below"},
      {.key = "solids", .description = "volumetric objects (tetrahedra)", .default_text = "`[]`"},
      {.key = "cloths", .description = "cloth and shells (triangles)", .default_text = "`[]`"},
      {.key = "colliders", .description = "kinematic rigid bodies, mesh sequences and skinned characters", .default_text = "`[]`"},
      {.key = "render", .description = "preview size and camera", .default_text = "see below"},
      {.key = "quick",
       .description = "overrides applied by `--quick`, e.g. `{\"frames\": 30, \"solids.0.mesh_resolution\": 10}`",
       .default_text = "`{}`"},
  });
  return table;
}

// The solver's fields fill the World's settings (WorldSettings, ImplicitSettings, CGSettings).
const FieldTable<Scene>& solver_fields() {
  using S = Scene;
  static const FieldTable<S> table({
      {.key = "integrator",
       .member = named<S, Integrator>([](auto& s) -> auto& { return s.solver.integrator; },
                                      {{"itf04", Integrator::ITF04}, {"implicit", Integrator::Implicit}}),
       .description = "`itf04`: the ITF04 section 9 step (explicit elasticity, implicit damping, CFL-limited), the "
                      "reference; `implicit`: backward Euler by Newton's method with a line search, steps of "
                      "`max_dt` with no stability limit",
       .default_text = "`implicit` with a cloth, else `itf04`"},
      {.key = "linear", .member = named<S, LinearSolver>([](auto& s) -> auto& { return s.solver.implicit.linear; },
                                       {{"cg", LinearSolver::CG}, {"direct", LinearSolver::Direct}}),
       .description = "`implicit`: each Newton system solved by preconditioned CG (`cg`) or factorized by "
                      "CHOLMOD's supernodal sparse Cholesky (`direct`)"},
      {.key = "preconditioner", .member = named<S, Preconditioner>([](auto& s) -> auto& { return s.solver.implicit.preconditioner; },
                                         {{"auto", Preconditioner::Auto},
                                          {"block_jacobi", Preconditioner::BlockJacobi},
                                          {"amg", Preconditioner::Amg}}),
       .description = "`implicit` with `cg`: CG's preconditioner (see below)"},
      {.key = "body_contact", .member = named<S, BodyContact>([](auto& s) -> auto& { return s.solver.implicit.contact; },
                                       {{"active_set", BodyContact::ActiveSet}, {"barrier", BodyContact::Barrier}}),
       .description = "`implicit`: contact with the colliders as nodes held on their surfaces, let go and caught "
                      "between Newton iterates (`active_set`), or as a barrier in the potential Newton minimizes "
                      "(`barrier`: no accepted Newton iterate puts a node inside a collider)"},
      {.key = "barrier_distance", .member = at<S>([](auto& s) -> auto& { return s.solver.implicit.barrier.distance; }), .unit = "m", .range = {1e-7, 1},
       .description = "`barrier`: the distance from a collider's surface within which the barrier pushes"},
      {.key = "cfl", .member = &S::cfl, .range = {1e-3, 1},
       .description = "`itf04`: fraction of the explicit stability bound taken as the time step"},
      {.key = "max_dt", .member = at<S>([](auto& s) -> auto& { return s.solver.max_dt; }), .unit = "s", .range = {1e-9, 1},
       .description = "upper bound on the time step (`implicit`: half a frame when not given)"},
      // One tolerance for both: the itf04 damping solves', and the implicit forcing term's floor,
      // at least the ImplicitSettings default.
      {.key = "cg_tolerance",
       .member = Slot<S, double>([](const S& s) { return s.solver.cg.relative_tolerance; },
                                 [](S& s, const double& v) {
                                   s.solver.cg.relative_tolerance = v;
                                   s.solver.implicit.cg.relative_tolerance =
                                       std::max(v, ImplicitSettings{}.cg.relative_tolerance);
                                 }), .range = {1e-14, 1e-1},
       .description = "`itf04`: relative residual of the damping solves; `implicit`: floor (at least 1e-6) of each "
                      "Newton step's CG tolerance"},
      {.key = "cg_max_iterations",
       .member = Slot<S, int>([](const S& s) { return s.solver.cg.max_iterations; },
                              [](S& s, const int& v) { s.solver.cg.max_iterations = s.solver.implicit.cg.max_iterations = v; }), .unit = "count", .range = {1, 100000},
       .description = "per CG solve; a solve that hits it is reported (`cg_converged` in `stats.jsonl`)"},
      {.key = "newton_tolerance", .member = at<S>([](auto& s) -> auto& { return s.solver.implicit.tolerance; }), .range = {1e-12, 1},
       .description = "`implicit`: a step stops when the residual force is below this fraction of the forces at "
                      "play (gravity, the elastic forces at the step's start, the momentum per step)"},
      {.key = "newton_max_iterations", .member = at<S>([](auto& s) -> auto& { return s.solver.implicit.max_newton_iterations; }), .unit = "count", .range = {1, 1000},
       .description = "`implicit`: Newton iterations of a step; a step that reaches it is reported "
                      "(`newton_capped`, `newton_worst_residual`)"},
      {.key = "max_substeps_per_frame",
       .member = Slot<S, int>([](const S& s) { return static_cast<int>(s.solver.max_substeps); },
                              [](S& s, const int& v) { s.solver.max_substeps = v; }), .unit = "count",
       .range = {1, 2147483647},
       .description = "a frame that would take more steps stops the run with exit 1, at its start when the "
                      "first frame would (see below); the default stops a run that would take hours a frame"},
      // 0 in the scene is the World's infinity (no bound of its own).
      {.key = "max_step_motion",
       .member = Slot<S, double>(
           [](const S& s) { return std::isinf(s.solver.max_step_motion) ? 0.0 : s.solver.max_step_motion; },
           [](S& s, const double& v) { s.solver.max_step_motion = v > 0 ? v : std::numeric_limits<double>::infinity(); }), .unit = "m", .range = {0, 1e3},
       .description = "motion-bounded steps: the longest a node or a collider's surface may move in one step "
                      "(see below); 0: the colliders' and the layer's own limits only"},
      {.key = "max_step_retries", .member = at<S>([](auto& s) -> auto& { return s.solver.max_step_retries; }), .unit = "count", .range = {0, 10},
       .description = "halvings of a frame's steps after a step the self-collision layer left unresolved (see "
                      "below); 0: never retried"},
  });
  return table;
}

// The self-collision layer's fields fill collisions::SelfCollisionSettings.
const FieldTable<Scene>& self_collision_fields() {
  using S = Scene;
  static const FieldTable<S> table({
      {.key = "enabled", .member = &S::self_collision_enabled, .description = "false: no self-collision pass at all"},
      {.key = "thickness", .member = at<S>([](auto& s) -> auto& { return s.self_collision.thickness; }), .unit = "m", .range = {1e-9, 1},
       .description = "repulsion thickness: pairs closer than it at a step's start are pushed apart (a cloth and "
                      "a body's triangles: closer than half of it); below the rest distance of non-neighbouring "
                      "parts, and below every surface's median edge length (checked at load)"},
      {.key = "ccd_distance", .member = at<S>([](auto& s) -> auto& { return s.self_collision.ccd_distance; }), .unit = "m", .range = {0, 1},
       .description = "the separation the CCD impulses and the impact zones keep, below `thickness`"},
      {.key = "friction", .member = at<S>([](auto& s) -> auto& { return s.self_collision.friction; }), .range = {0, 10},
       .description = "Coulomb coefficient between surfaces"},
      {.key = "impulse_passes", .member = at<S>([](auto& s) -> auto& { return s.self_collision.impulse_passes; }), .unit = "count", .range = {0, 1000},
       .description = "CCD impulse passes before the impact zones take over"},
      {.key = "max_zone_iterations", .member = at<S>([](auto& s) -> auto& { return s.self_collision.max_zone_iterations; }), .unit = "count", .range = {1, 100000},
       .description = "detect-merge-move rounds of the impact zones; a step that needs more is counted "
                      "(`unresolved_steps`) and flagged in the progress line"},
      {.key = "zone_projection_rounds", .member = at<S>([](auto& s) -> auto& { return s.self_collision.zone_projection.rounds; }), .unit = "count", .range = {0, 100000},
       .description = "rounds of new collisions an impact zone is resolved non-rigidly (its velocities projected "
                      "onto its pairs' non-penetration constraints, keeping the sliding) before it turns rigid; "
                      "0: every zone rigid. Counted in `stats.jsonl` (`projected_zones`, `rigid_zones`)"},
      {.key = "colliders", .member = at<S>([](auto& s) -> auto& { return s.self_collision.kinematic_bodies; }),
       .description = "mesh colliders' triangles take part (analytic colliders act on their exact shape through "
                      "the collision processing)"},
      {.key = "barrier", .member = at<S>([](auto& s) -> auto& { return s.self_collision.barrier; }),
       .description = "`implicit`: a cloth's contact with itself also inside the step, as a barrier on its pairs "
                      "closer than `thickness` with a CCD filter on Newton's line search; the layer stays after "
                      "the step as the fail-safe"},
  });
  return table;
}

// The settle phase's fields fill WorldSettings::settle.
const FieldTable<Scene>& settle_fields() {
  using S = Scene;
  static const FieldTable<S> table({
      {.key = "duration", .member = at<S>([](auto& s) -> auto& { return s.solver.settle.duration; }), .unit = "s", .range = {0, 1e5},
       .description = "the first seconds of the run: every step starts from rest (the velocities zeroed at its "
                      "start) and the colliders and moving pins hold their pose of time 0; after it they move, "
                      "their animation this much behind the run's clock; 0: no settle"},
      {.key = "gravity", .member = at<S>([](auto& s) -> auto& { return s.solver.settle.gravity; }),
       .description = "false: no gravity during the settle"},
      {.key = "gravity_ramp", .member = at<S>([](auto& s) -> auto& { return s.solver.settle.gravity_ramp; }), .unit = "s", .range = {0, 1e5},
       .description = "with `gravity` false: after the settle, gravity grows linearly from none to whole over "
                      "this time (each step takes its end's share); 0: whole at once"},
  });
  return table;
}

const FieldTable<SolidSpec>& SolidSpec::fields() {
  using S = SolidSpec;
  static const FieldTable<S> table({
      {.key = "name", .description = "unique among the scene's objects and colliders", .default_text = "required"},
      {.key = "mesh", .unit = "path",
       .description = "a tet mesh, or a closed triangle surface that is checked and tet-meshed (see below)",
       .default_text = "required"},
      {.key = "mesh_resolution", .member = at<S>([](auto& s) -> auto& { return s.meshing.resolution; }), .unit = "cells", .range = {2, 1000},
       .description = "BCC cells along the longest side, for a surface `mesh`"},
      {.key = "transform",
       .description = "`scale` (factor), `rotate_degrees` `[x, y, z]` (applied x, then y, then z), `translate` "
                      "`[x, y, z]` m",
       .default_text = "identity"},
      {.key = "velocity", .unit = "m/s", .description = "initial velocity", .default_text = "`[0, 0, 0]`"},
      {.key = "material", .description = "the constitutive model and its parameters, see below",
       .default_text = "see below"},
      {.key = "pin_boxes", .unit = "m",
       .description = "`[{\"min\": [x, y, z], \"max\": [x, y, z]}, ...]`: nodes whose rest position lies in a box "
                      "are held still, or moved (see below)",
       .default_text = "`[]`"},
      {.key = "plasticity", .description = "ITF04 6.3 multiplicative plasticity, see below", .default_text = "none"},
      {.key = "plastic_goal",
       .description = "ITF04 7 control toward the rest shape scaled per axis, see below; needs `plasticity`",
       .default_text = "none"},
      {.key = "fiber", .description = "ITF04 6.1 muscle fibers, see below", .default_text = "none"},
      {.key = "initial_shape", .description = "where the solid starts, see below; the rest shape stays the mesh's",
       .default_text = "rest shape"},
      {.key = "self_collision", .member = &S::self_collision,
       .description = "its boundary surface takes part in the self-collision layer"},
      {.key = "cloth_coupling",
       .description = "one-way coupling (ITF04 section 10): its boundary is a moving collider for cloths, see below",
       .default_text = "on, every cloth"},
      {.key = "fracture", .description = "ductile fracture by the virtual node algorithm, see below",
       .default_text = "none"},
  });
  return table;
}

// The solids' material: the model chosen (MaterialChoice) and the TetMaterial.
const FieldTable<SolidSpec>& material_fields() {
  using S = SolidSpec;
  static const FieldTable<S> table({
      {.key = "model", .member = model_kind<S>([](auto& s) -> auto& { return s.model.model; }),
       .expected = "one of rotated_linear, neo_hookean, stvk, spline (ITF04) or the baselines corotated, mass_spring",
       .description = "the constitutive model: ITF04's four, extended through flat and inverted states, or a "
                      "baseline with no inversion handling (see below)"},
      {.key = "young", .member = at<S>([](auto& s) -> auto& { return s.model.young; }), .unit = "Pa", .range = {0, 1e13}, .description = "Young's modulus"},
      {.key = "poisson", .member = at<S>([](auto& s) -> auto& { return s.model.poisson; }), .range = {-1, 0.5, true, true},
       .expected = "a Poisson's ratio in (-1, 0.5) (0.5 is incompressible: use 0.49 or less)",
       .description = "Poisson's ratio; 0.5 (incompressible) is rejected"},
      {.key = "density", .member = at<S>([](auto& s) -> auto& { return s.material.density; }), .unit = "kg/m³", .range = {0, 1e6, true, false},
       .expected = "a density > 0 and <= 1e6 [kg/m^3]", .description = "mass density at rest"},
      {.key = "damping", .member = at<S>([](auto& s) -> auto& { return s.material.damping; }), .unit = "s", .range = {0, 10},
       .description = "ITF04 6.2 damping in the rotated frame: alpha = k lambda, beta = k mu"},
      {.key = "damping_model",
       .member = named<S, DampingModel>([](auto& s) -> auto& { return s.material.damping_model; },
                                        {{"rotated", DampingModel::Rotated}, {"spin_free", DampingModel::SpinFree}}),
       .description = "`rotated`: ITF04 6.2; `spin_free`: the same, but conserving angular momentum in every "
                      "state (see below)"},
      {.key = "compression_limit", .member = at<S>([](auto& s) -> auto& { return s.model.compression_limit; }), .range = {0, 1, true, true},
       .description = "`neo_hookean`, `stvk`: singular value below which the model is extended"},
      {.key = "compression_stiffness", .member = at<S>([](auto& s) -> auto& { return s.model.compression_stiffness; }), .range = {0, 1, true, false},
       .description = "`rotated_linear`, `corotated`: the modulus where a principal strain is negative, as a fraction of "
                      "that where it is positive (1: ITF04's model)"},
      {.key = "hardening_deformation", .member = at<S>([](auto& s) -> auto& { return s.model.hardening_deformation; }), .range = {0, 1, true, true},
       .description = "`spline`: strain where stiffening ends"},
      {.key = "hardening_strength", .member = at<S>([](auto& s) -> auto& { return s.model.hardening_strength; }), .range = {1, 1e3},
       .description = "`spline`: stiffness ratio beyond it"},
      {.key = "strength",
       .description = "a factor on the moduli: a number, or keys `[[t, factor], ...]` (piecewise linear in time)",
       .default_text = "1"},
  });
  return table;
}

const FieldTable<PlasticParams>& plasticity_fields() {
  using S = PlasticParams;
  static const FieldTable<S> table({
      {.key = "yield", .member = &S::yield, .unit = "log strain", .range = {0, 10, true, true},
       .expected = "a yield log-strain in (0, 10)", .description = "yield when ‖ln F^e‖ exceeds it"},
      {.key = "deviatoric_only", .member = &S::deviatoric_only,
       .description = "test only the deviatoric part (volume change stays elastic)"},
      {.key = "preserve_volume", .member = &S::preserve_volume,
       .description = "keep det Fp = 1 (not with a `plastic_goal`)"},
      {.key = "max_stretch", .member = &S::max_stretch, .range = {1, 1e6, true, false},
       .expected = "a stretch limit in (1, 1e6]", .description = "limit on Fp's singular values and their inverses"},
  });
  return table;
}

const FieldTable<AxisScaledGoal>& plastic_goal_fields() {
  static const FieldTable<AxisScaledGoal> table({
      {.key = "scale",
       .description = "the goal shape is the rest shape scaled per world axis about `center`, each factor > 0",
       .default_text = "`[1, 1, 1]`"},
      {.key = "center", .unit = "m", .description = "the point the goal's scaling is about",
       .default_text = "`[0, 0, 0]`"},
  });
  return table;
}

const FieldTable<FiberMaterial>& fiber_fields() {
  using S = FiberMaterial;
  static const FieldTable<S> table({
      {.key = "direction", .description = "fiber direction at rest (world axes), the same in every element",
       .default_text = "`[1, 0, 0]`"},
      {.key = "k_passive", .member = &S::k_passive, .unit = "Pa", .range = {0, 1e12},
       .description = "passive stiffness when stretched"},
      {.key = "k_active", .member = &S::k_active, .unit = "Pa", .range = {0, 1e12},
       .description = "contractile stiffness at full activation"},
      {.key = "max_contraction", .member = &S::max_contraction, .range = {0, 1, false, true},
       .description = "the fiber's rest stretch at activation 1 is 1 - this"},
      {.key = "activation", .description = "a number or keys `[[t, a], ...]` (piecewise linear in time), a in [0, 1]",
       .default_text = "0"},
  });
  return table;
}

// A threshold not given is the criterion's infinity (not used).
template <class Ref> Slot<FractureCriterion, std::optional<double>> threshold(Ref ref) {
  return Slot<FractureCriterion, std::optional<double>>(
      [ref](const FractureCriterion& c) { return std::isinf(ref(c)) ? std::nullopt : std::optional<double>(ref(c)); },
      [ref](FractureCriterion& c, const std::optional<double>& v) {
        ref(c) = v ? *v : std::numeric_limits<double>::infinity();
      });
}

const FieldTable<FractureCriterion>& fracture_fields() {
  using S = FractureCriterion;
  static const FieldTable<S> table({
      {.key = "max_principal_stress", .member = threshold([](auto& c) -> auto& { return c.max_principal_stress; }), .unit = "Pa", .range = {1e-6, 1e12},
       .description = "cut where the largest principal stress (first Piola-Kirchhoff, in the element's diagonal "
                      "frame; tension only) exceeds this"},
      {.key = "max_plastic_strain", .member = threshold([](auto& c) -> auto& { return c.max_plastic_strain; }), .range = {1e-6, 10},
       .description = "or where the accumulated plastic strain max‖log λ(Fp)‖ exceeds this; needs `plasticity`"},
      {.key = "front_fraction", .member = &S::front_fraction, .range = {0, 1, true, false},
       .expected = "a fraction in (0, 1]",
       .description = "an element already touched by a cut (the crack front) is cut at this fraction of the "
                      "thresholds"},
      {.key = "max_cuts_per_step", .member = &S::max_cuts_per_step, .unit = "elements", .range = {1, 1000000},
       .description = "at most this many elements cut per step, crack front first, then most loaded first"},
      {.key = "max_elements", .member = &S::max_elements, .unit = "elements", .range = {0, 1000000000},
       .description = "no more cuts once the mesh has this many element copies (0: no limit)"},
      {.key = "seed", .description = "a crack seed, a scored plane where the solid tears (see below)",
       .default_text = "none"},
  });
  return table;
}

const FieldTable<Scramble>& initial_shape_fields() {
  using S = Scramble;
  static const FieldTable<S> table({
      {.key = "file", .unit = "path",
       .description = "a tet mesh or an OBJ with the solid's nodes in the same order, read as positions only (see "
                      "below)",
       .default_text = "–"},
      {.key = "transform", .description = "for `file`: applied to its positions", .default_text = "the solid's"},
      {.key = "scramble",
       .description = "instead of `file`: the (transformed) rest nodes scrambled about their centroid (see below)",
       .default_text = "–"},
      {.key = "seed",
       .member = Slot<S, int>([](const S& s) { return static_cast<int>(s.seed); },
                              [](S& s, const int& v) { s.seed = static_cast<std::uint64_t>(v); }),
       .range = {0, 2147483647},
       .description = "the random line, plane, mirror or positions; a seed gives the same positions on every "
                      "machine"},
      {.key = "size", .unit = "m", .description = "`box` only: the cube's edge, in (0, 1e6]",
       .default_text = "required for `box`"},
  });
  return table;
}

// The coupling's fields fill the solid's SolidCoupling.
const FieldTable<SolidSpec>& cloth_coupling_fields() {
  using S = SolidSpec;
  static const FieldTable<S> table({
      {.key = "enabled", .member = &S::cloth_coupling_enabled, .description = "false: no coupling"},
      {.key = "cloths", .description = "the names of the cloths it acts on; empty: every cloth of the scene",
       .default_text = "`[]`"},
      {.key = "friction", .member = at<S>([](auto& s) -> auto& { return s.cloth_coupling.friction; }), .range = {0, 10},
       .description = "Coulomb coefficient between the cloth and the solid"},
      {.key = "query_radius", .member = at<S>([](auto& s) -> auto& { return s.cloth_coupling.surface.query_radius; }), .unit = "m", .range = {1e-6, 1e3},
       .description = "contact search distance: a cloth vertex deeper inside than it is not found"},
      {.key = "offset", .member = at<S>([](auto& s) -> auto& { return s.cloth_coupling.surface.offset; }), .unit = "m", .range = {0, 1},
       .description = "the collision surface lies this far outside the boundary, below `query_radius`"},
  });
  return table;
}

const FieldTable<ClothSpec>& ClothSpec::fields() {
  using S = ClothSpec;
  static const FieldTable<S> table({
      {.key = "name", .description = "unique among the scene's objects and colliders", .default_text = "required"},
      {.key = "mesh", .unit = "path",
       .description = "the garment or shell: an OBJ with its groups, `vt` and `stitch` lines, or any surface "
                      "assimp reads (see below)",
       .default_text = "–"},
      {.key = "grid", .description = "instead of `mesh`: a rectangle in the x-z plane centred on the origin, see below",
       .default_text = "1 x 1 m, 20 x 20"},
      {.key = "half_torus",
       .description = "instead of `mesh`: the upper half of a torus about y standing on its rims at y = 0, see below",
       .default_text = "–"},
      {.key = "rest_shape", .member = &S::rest_shape, .choices = {"mesh", "pattern"},
       .description = "`mesh`: the mesh's own 3D shape; `pattern`: the 2D sewing pattern of the OBJ's `vt` lines "
                      "(see below)"},
      {.key = "initial_shape",
       .description = "`{\"mesh\": path, \"transform\": {..}}`: start from another file with the same vertices in "
                      "the same order (see below)",
       .default_text = "–"},
      {.key = "transform", .description = "as for solids; it moves the 3D positions, not a pattern",
       .default_text = "identity"},
      {.key = "velocity", .unit = "m/s", .description = "initial velocity", .default_text = "`[0, 0, 0]`"},
      {.key = "material", .description = "in-plane and bending material, see below", .default_text = "see below"},
      {.key = "plasticity",
       .description = "in-plane plasticity: the fields of solids' `plasticity` on the 2x2 Fp of each triangle "
                      "(ITF04 6.3 return mapping)",
       .default_text = "none"},
      {.key = "bending_plasticity", .description = "plastic rest angles (ITF04 8), see below", .default_text = "none"},
      {.key = "inversion_test",
       .description = "ITF04 section 8: `rest` or a direction `[x, y, z]` gives the known surface normal, and a "
                      "triangle facing against it is inverted (see below)",
       .default_text = "`none`"},
      {.key = "stitches", .description = "seams, see below", .default_text = "see below"},
      {.key = "pin_vertices", .description = "vertex indices (of the file) held still", .default_text = "`[]`"},
      {.key = "pin_boxes", .unit = "m", .description = "as for solids, on the initial positions",
       .default_text = "`[]`"},
      {.key = "pins", .description = "pinned vertices, held still or carried by a `motion` (see below)",
       .default_text = "`[]`"},
      {.key = "self_collision", .member = &S::self_collision,
       .description = "takes part in the self-collision layer"},
      {.key = "attachments", .description = "vertices tied to a solid (see below)", .default_text = "`[]`"},
  });
  return table;
}

const FieldTable<GridParams>& grid_fields() {
  using S = GridParams;
  static const FieldTable<S> table({
      {.key = "width", .member = &S::width, .unit = "m", .range = {1e-4, 1e4}, .description = "extent along x"},
      {.key = "height", .member = &S::height, .unit = "m", .range = {1e-4, 1e4}, .description = "extent along z"},
      {.key = "nx", .member = &S::nx, .unit = "cells", .range = {1, 2000}, .description = "cells along x"},
      {.key = "ny", .member = &S::ny, .unit = "cells", .range = {1, 2000}, .description = "cells along z"},
  });
  return table;
}

const FieldTable<HalfTorusParams>& half_torus_fields() {
  using S = HalfTorusParams;
  static const FieldTable<S> table({
      {.key = "major_radius", .member = &S::major_radius, .unit = "m", .range = {1e-4, 1e4},
       .description = "R, from the axis to the tube's centre"},
      {.key = "minor_radius", .member = &S::minor_radius, .unit = "m", .range = {1e-5, 1e4},
       .description = "r, the tube's radius, below `major_radius`"},
      {.key = "around", .member = &S::around, .unit = "cells", .range = {3, 4000},
       .description = "cells around the axis"},
      {.key = "across", .member = &S::across, .unit = "cells", .range = {1, 4000},
       .description = "cells across the half tube"},
  });
  return table;
}

// The cloths' material: in-plane (plane stress) and bending.
// The model chosen (MaterialChoice) and the ClothObjectParams.
const FieldTable<ClothSpec>& cloth_material_fields() {
  using S = ClothSpec;
  static const FieldTable<S> table({
      {.key = "model", .member = model_kind<S>([](auto& s) -> auto& { return s.model.model; }),
       .expected = "one of rotated_linear, neo_hookean, stvk, spline (ITF04) or the baselines corotated, mass_spring",
       .description = "any model of the solids' `material`, in plane stress (see below)"},
      {.key = "young", .member = at<S>([](auto& s) -> auto& { return s.model.young; }), .unit = "Pa", .range = {0, 1e13},
       .description = "in-plane Young's modulus"},
      {.key = "poisson", .member = at<S>([](auto& s) -> auto& { return s.model.poisson; }), .range = {-1, 0.5, true, true},
       .expected = "a Poisson's ratio in (-1, 0.5)", .description = "in-plane Poisson's ratio"},
      {.key = "compression_limit", .member = at<S>([](auto& s) -> auto& { return s.model.compression_limit; }), .range = {0, 1, true, true},
       .description = "`neo_hookean`, `stvk`: as for solids"},
      {.key = "compression_stiffness", .member = at<S>([](auto& s) -> auto& { return s.model.compression_stiffness; }), .range = {0, 1, true, false},
       .description = "`rotated_linear`, `corotated`: as for solids; cloth buckles rather than shortens, so garments take about 0.01-0.1"},
      {.key = "hardening_deformation", .member = at<S>([](auto& s) -> auto& { return s.model.hardening_deformation; }), .range = {0, 1, true, true},
       .description = "`spline`: as for solids"},
      {.key = "hardening_strength", .member = at<S>([](auto& s) -> auto& { return s.model.hardening_strength; }), .range = {1, 1e3},
       .description = "`spline`: as for solids"},
      {.key = "density", .member = at<S>([](auto& s) -> auto& { return s.params.density; }), .unit = "kg/m³", .range = {0, 1e5, true, true},
       .expected = "a density in (0, 1e5) [kg/m^3]",
       .description = "areal density = density x `thickness`; masses come from the rest (pattern) areas"},
      {.key = "thickness", .member = at<S>([](auto& s) -> auto& { return s.params.thickness; }), .unit = "m", .range = {0, 1, true, true},
       .expected = "a thickness in (0, 1) [m]",
       .description = "shell thickness: the membrane's energy and the areal density scale with it"},
      {.key = "damping", .member = at<S>([](auto& s) -> auto& { return s.params.damping; }), .unit = "s", .range = {0, 10},
       .description = "in-plane rotated damping"},
      {.key = "strain_limit", .member = at<S>([](auto& s) -> auto& { return s.params.strain_limit; }), .range = {1, 100},
       .description = "no triangle stretches past this against its rest shape (pattern) within an implicit step "
                      "(C-IPC's garments use 1.10); 1: no limit; the `itf04` integrator takes none"},
      {.key = "bending_stiffness", .member = at<S>([](auto& s) -> auto& { return s.params.bending.stiffness; }), .unit = "N m", .range = {0, 1e6},
       .description = "BMF03 hinge bending stiffness"},
      {.key = "bending_damping", .member = at<S>([](auto& s) -> auto& { return s.params.bending.damping; }), .unit = "N m s", .range = {0, 1e6},
       .description = "BMF03 hinge bending damping"},
  });
  return table;
}

const FieldTable<BendingPlasticity>& bending_plasticity_fields() {
  using S = BendingPlasticity;
  static const FieldTable<S> table({
      {.key = "yield_degrees", .member = &S::yield_degrees, .unit = "degrees", .range = {0, 180},
       .description = "a hinge bent more than this past its rest angle drags the rest angle along"},
      {.key = "max_change_degrees", .member = &S::max_change_degrees, .unit = "degrees", .range = {1e-6, 360},
       .description = "the rest angle never moves more than this from its original value"},
  });
  return table;
}

// The stitches' fields fill the cloth's StitchParams.
const FieldTable<ClothSpec>& stitch_fields() {
  using S = ClothSpec;
  static const FieldTable<S> table({
      {.key = "from_mesh", .member = &S::stitches_from_mesh,
       .description = "use the mesh file's `stitch` lines (0-based vertex indices, as C-IPC writes them)"},
      {.key = "list", .description = "more stitches `[[i, j, k, r], ...]`, r in [0, 1]", .default_text = "`[]`"},
      {.key = "stiffness", .member = at<S>([](auto& s) -> auto& { return s.params.stitch.stiffness; }), .unit = "N/m²", .range = {1e-6, 1e9},
       .description = "per metre of seam; a gap g pulls with stiffness x length x g"},
      {.key = "damping", .member = at<S>([](auto& s) -> auto& { return s.params.stitch.damping; }), .unit = "N s/m²", .range = {0, 1e6},
       .description = "per metre of seam, on the gap's rate"},
      {.key = "closing_speed", .member = at<S>([](auto& s) -> auto& { return s.params.stitch.closing_speed; }), .unit = "m/s", .range = {0, 100},
       .description = "sewing: each stitch's rest length starts at its initial gap and shrinks at this speed (see "
                      "below); 0: every stitch pulls closed from the start"},
  });
  return table;
}

// A collider's fields: each type reads its own (parse_collider); the sequence's and the skinned
// body's (frames to pre_roll) are read by hand.
const FieldTable<ColliderSpec>& ColliderSpec::fields() {
  using S = ColliderSpec;
  static const FieldTable<S> table({
      {.key = "name", .description = "a `gears` collider's two bodies are written as `<name>_1`, `<name>_2`",
       .default_text = "required"},
      {.key = "type", .member = &S::type,
       .choices = {"plane", "sphere", "box", "cylinder", "gears", "mesh", "sequence", "skinned"},
       .expected = "one of plane, sphere, box, cylinder, gears, mesh, sequence, skinned",
       .description = "an analytic shape, a triangle `mesh`, a body animated by a mesh `sequence` or a "
                      "`skinned` character"},
      {.key = "point", .unit = "m", .description = "`plane` only: a point of the plane; planes are static",
       .default_text = "origin"},
      {.key = "normal", .description = "`plane` only: the plane's normal", .default_text = "+y"},
      {.key = "radius", .member = &S::radius, .unit = "m", .range = {1e-6, 1e4},
       .description = "`sphere`, `cylinder`"},
      {.key = "half_extents", .unit = "m", .description = "`box`: three half extents > 0",
       .default_text = "`[0.5, 0.5, 0.5]`"},
      {.key = "half_height", .member = &S::half_height, .unit = "m", .range = {1e-6, 1e4},
       .description = "`cylinder` (capped, axis y in its frame)"},
      {.key = "teeth", .member = at<S>([](auto& s) -> auto& { return s.gears.gear.teeth; }), .unit = "count", .range = {3, 1000},
       .description = "`gears`: teeth of each gear of the pair (see below)"},
      {.key = "outer_radius", .member = at<S>([](auto& s) -> auto& { return s.gears.gear.outer_radius; }), .unit = "m", .range = {1e-6, 1e4},
       .description = "`gears`: radius of the tooth tips"},
      {.key = "root_radius", .member = at<S>([](auto& s) -> auto& { return s.gears.gear.root_radius; }), .unit = "m", .range = {1e-6, 1e4},
       .description = "`gears`: radius of the gaps' bottoms, below `outer_radius`"},
      {.key = "thickness", .member = at<S>([](auto& s) -> auto& { return s.gears.gear.thickness; }), .unit = "m", .range = {1e-6, 1e4},
       .description = "`gears`: extent along their axes"},
      {.key = "clearance", .member = at<S>([](auto& s) -> auto& { return s.gears.clearance; }), .unit = "m", .range = {0, 1e4},
       .description = "`gears`: the axes are `outer_radius` + `root_radius` + this apart"},
      {.key = "mesh", .unit = "path", .description = "`mesh`: any triangle surface assimp reads, static",
       .default_text = "–"},
      {.key = "query_radius", .member = at<S>([](auto& s) -> auto& { return s.contact.query_radius; }), .unit = "m", .range = {1e-9, 1e4},
       .description = "`mesh`, `sequence`, `skinned`: contact searched within it"},
      {.key = "offset", .member = at<S>([](auto& s) -> auto& { return s.contact.offset; }), .unit = "m", .range = {0, 1},
       .description = "`mesh`, `sequence`, `skinned`: the collision surface lies this far outside the mesh, below "
                      "`query_radius` (see below)"},
      {.key = "transform", .description = "pose of the body frame (no `scale` except for `mesh`, `sequence` and `skinned`)",
       .default_text = "identity"},
      {.key = "motion",
       .description = "a constant velocity and spin, or absolute keyframes (then no `transform`); see below",
       .default_text = "fixed"},
      {.key = "friction", .member = &S::friction, .range = {0, 100}, .description = "Coulomb coefficient"},
      {.key = "frames",
       .description = "`sequence`: the frame files by pattern, `{\"pattern\": \"body/shell{N}.obj\", \"first\": 0, "
                      "\"last\": 120}` (see below)",
       .default_text = "–"},
      {.key = "files", .description = "`sequence`: the frame files as a list instead of `frames` (one of the two)",
       .default_text = "–"},
      {.key = "fps", .unit = "frames/s",
       .description = "`sequence`: frame rate of the sequence (independent of the scene's `fps`), in [0.001, 1e6]",
       .default_text = "required"},
      {.key = "start_time", .unit = "s",
       .description = "`sequence`, `skinned`: simulation time at which its first frame (the clip's time 0) is "
                      "shown (before it, that pose holds still), in [-1e9, 1e9]",
       .default_text = "0"},
      {.key = "start_frame",
       .description = "`sequence`: instead of `start_time`, the frame (0-based index into the frames) shown at t = 0",
       .default_text = "–"},
      {.key = "after_end",
       .description = "`sequence`, `skinned`: past the last frame, `hold` it (velocity 0) or `loop` (see below)",
       .default_text = "`hold`"},
      {.key = "file", .unit = "path",
       .description = "`skinned`: a rigged, animated character (glTF, FBX, Collada, .x: any file assimp reads with "
                      "bones and an animation clip)",
       .default_text = "required"},
      {.key = "clip", .description = "`skinned`: the animation clip, by name or index (a wrong name lists the file's "
                                     "clips)",
       .default_text = "0"},
      {.key = "pre_roll", .unit = "s",
       .description = "`skinned`: before `start_time`, the body goes from its bind pose (its skeleton at rest) into "
                      "the clip's first pose over this long, in [0, 1e6]; 0: no bind pose, the first pose holds",
       .default_text = "0"},
      {.key = "loop_blend", .member = at<S>([](auto& s) -> auto& { return s.skinned.loop_blend; }), .unit = "s", .range = {0, 1e6},
       .description = "`skinned` with `after_end` `loop`: the wrap is cross-faded over this long, the clip's last "
                      "`loop_blend` seconds into its first (the loop's period is then the clip's duration minus it; "
                      "at most half the duration); 0: none, and a clip whose last pose lies further than "
                      "`query_radius` - `offset` from its first is refused (the wrap would be a jump)"},
  });
  return table;
}

const FieldTable<renders::RenderSettings>& render_fields() {
  using S = renders::RenderSettings;
  static const FieldTable<S> table({
      {.key = "width", .member = &S::width, .unit = "px", .range = {16, 8192},
       .description = "preview width (`invfem render --width` overrides it)"},
      {.key = "height", .member = &S::height, .unit = "px", .range = {16, 8192},
       .description = "preview height (`invfem render --height` overrides it)"},
      {.key = "ground", .member = &S::ground, .description = "draw the y = 0 ground grid"},
      {.key = "camera", .description = "a fixed camera, see below; automatic: framed around the objects' first frame",
       .default_text = "automatic"},
  });
  return table;
}

// A fixed camera (`render.camera` given); without it the camera frames the objects.
const FieldTable<renders::Camera>& camera_fields() {
  using S = renders::Camera;
  static const FieldTable<S> table({
      {.key = "position", .unit = "m", .description = "the eye", .default_text = "`[0, 1, 4]`"},
      {.key = "target", .unit = "m", .description = "the point looked at, away from `position`",
       .default_text = "`[0, 0.5, 0]`"},
      {.key = "fov_degrees", .member = &S::fov_y_degrees, .unit = "degrees", .range = {1, 170},
       .description = "vertical field of view"},
  });
  return table;
}

// (section, table) in the document's order.
std::vector<std::pair<std::string, std::string>> scene_field_tables() {
  return {
      {"scene", Scene::fields().markdown()},
      {"solver", solver_fields().markdown()},
      {"self_collision", self_collision_fields().markdown()},
      {"settle", settle_fields().markdown()},
      {"solids", SolidSpec::fields().markdown()},
      {"material", material_fields().markdown()},
      {"plasticity", plasticity_fields().markdown()},
      {"plastic_goal", plastic_goal_fields().markdown()},
      {"fiber", fiber_fields().markdown()},
      {"fracture", fracture_fields().markdown()},
      {"initial_shape", initial_shape_fields().markdown()},
      {"cloth_coupling", cloth_coupling_fields().markdown()},
      {"cloths", ClothSpec::fields().markdown()},
      {"grid", grid_fields().markdown()},
      {"half_torus", half_torus_fields().markdown()},
      {"cloth_material", cloth_material_fields().markdown()},
      {"bending_plasticity", bending_plasticity_fields().markdown()},
      {"stitches", stitch_fields().markdown()},
      {"colliders", ColliderSpec::fields().markdown()},
      {"render", render_fields().markdown()},
      {"camera", camera_fields().markdown()},
  };
}

}  // namespace invfem::app
