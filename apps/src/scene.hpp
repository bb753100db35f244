#pragma once
// The scene file: plain data parsed and validated from JSON. The schema is documented in
// apps/scenes/README.md; every default is filled in here so the run can write the scene back
// out complete (OUT/scene.json).
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <filesystem>
#include <string>
#include <vector>

#include "invfem/core/math/scalar_track.hpp"
#include "scene_field.hpp"

namespace invfem::app {

struct MaterialSpec {
  std::string model = "rotated_linear";  // rotated_linear | neo_hookean | stvk | spline; baselines corotated | mass_spring
  double young = 1e5;                     // [Pa]
  double poisson = 0.3;
  double density = 1000;                  // [kg/m^3]
  double damping = 0.0;                   // k [s]: alpha = k lambda, beta = k mu
  std::string damping_model = "rotated";  // rotated (ITF04 6.2) | spin_free (tet_solid_force.hpp)
  double compression_limit = 0.3;         // neo_hookean, stvk: extension threshold on s_i
  double hardening_deformation = 0.5;     // spline: t
  double hardening_strength = 7;          // spline: r
  ScalarTrack strength = ScalarTrack::constant(1.0);  // multiplies the moduli over time

  static const FieldTable<MaterialSpec>& fields();  // scene_fields.cpp
};

struct Transform {
  double scale = 1;
  std::array<double, 3> rotate_degrees{0, 0, 0};  // applied x, then y, then z
  std::array<double, 3> translate{0, 0, 0};
};

// How a rigid collider moves: fixed at its transform, at constant linear and angular
// velocity from it, or by absolute keyframes. Pinned vertices use it too, about their rest
// positions (the keys then move the pinned set as a rigid body from where it rests).
struct MotionSpec {
  enum class Kind { Fixed, ConstantVelocity, Keyframed } kind = Kind::Fixed;
  std::array<double, 3> velocity{0, 0, 0};    // [m/s]
  std::array<double, 3> spin_axis{0, 0, 1};
  double spin_rate = 0;                       // [rad/s], about the collider's translate point
  std::vector<std::pair<double, std::array<double, 3>>> translate_keys;  // (t, world translation)
  struct RotateKey {
    double t;
    std::array<double, 3> axis;
    double degrees;
  };
  std::vector<RotateKey> rotate_keys;
};

struct PinBox {
  std::array<double, 3> min{0, 0, 0}, max{0, 0, 0};  // world rest positions inside are held still
};

// Ductile fracture by the virtual node algorithm (solids/fracture_criterion.hpp): an element
// copy whose largest principal stress (or accumulated plastic strain) passes its threshold is
// cut orthogonally to its largest principal stress direction. A threshold left out is not used.
struct FractureSpec {
  std::optional<double> max_principal_stress;  // [Pa]
  std::optional<double> max_plastic_strain;    // max |log| of Fp's singular values
  double front_fraction = 0.5;                 // a crack front's element is cut at this fraction of a threshold
  int max_cuts_per_step = 4;                   // element copies cut per step, crack front first
  int max_elements = 0;                        // no cut once the mesh has this many copies (0: none)
  // A crack seed (fracture_criterion.hpp): the tets the rest plane (point, normal) crosses, with
  // their rest centroid in the box, are cut at `factor` x the thresholds, through the plane.
  struct Seed {
    std::array<double, 3> point{0, 0, 0};  // [m], rest (transformed) positions
    std::array<double, 3> normal{0, 1, 0};
    std::optional<std::array<double, 3>> min, max;  // [m], the box (none: all of the plane)
    double factor = 0.5;                   // in (0, 1]
  };
  std::optional<Seed> seed;

  static const FieldTable<FractureSpec>& fields();  // scene_fields.cpp
};

struct PlasticitySpec {       // ITF04 6.3
  double yield = 0.1;         // gamma: ||ln F^e|| <= gamma
  bool deviatoric_only = false;
  bool preserve_volume = false;
  double max_stretch = 10;    // the limit on Fp's singular values (and their inverses)

  static const FieldTable<PlasticitySpec>& fields();  // scene_fields.cpp
};

struct PlasticGoalSpec {      // ITF04 7: control toward the rest shape scaled per axis
  std::array<double, 3> scale{1, 1, 1};
  std::array<double, 3> center{0, 0, 0};

  static const FieldTable<PlasticGoalSpec>& fields();  // scene_fields.cpp
};

struct FiberSpec {            // ITF04 6.1: transversely isotropic muscle fibers
  std::array<double, 3> direction{1, 0, 0};  // material (rest) direction, world axes
  double k_passive = 0;       // [Pa]
  double k_active = 0;        // [Pa]
  double max_contraction = 0.3;
  ScalarTrack activation = ScalarTrack::constant(0.0);

  static const FieldTable<FiberSpec>& fields();  // scene_fields.cpp
};

// Where a solid starts: node positions from a file (same nodes, same order as its mesh) or a
// scramble of its rest positions (solids/scramble.hpp). The rest shape stays the mesh's.
struct SolidInitialShapeSpec {
  std::filesystem::path file;          // a tet mesh or OBJ; empty: a scramble
  std::optional<Transform> transform;  // for file; default: the solid's transform
  std::string scramble;                // point | line | plane | mirror | box
  int seed = 0;
  double size = 0;                     // box: edge of the cube about the centroid [m]

  static const FieldTable<SolidInitialShapeSpec>& fields();  // scene_fields.cpp
};

// One-way coupling (ITF04 section 10): the solid's deformed boundary is a moving collider for
// cloths (never pushed back).
struct ClothCouplingSpec {
  bool enabled = true;
  std::vector<std::string> cloths;  // empty: every cloth of the scene
  double friction = 0.3;            // Coulomb coefficient between the cloth and the solid
  double query_radius = 0.05;       // [m] contact search distance
  double offset = 1e-3;             // [m] the collision surface lies this far outside the boundary

  static const FieldTable<ClothCouplingSpec>& fields();  // scene_fields.cpp
};

struct SolidSpec {
  std::string name;
  ClothCouplingSpec cloth_coupling;
  bool self_collision = true;  // its boundary surface takes part in the self-collision layer
  std::filesystem::path mesh;  // absolute, resolved against the scene file's folder
  int mesh_resolution = 24;    // BCC cells along the longest side, when `mesh` is a surface
  Transform transform;
  std::array<double, 3> velocity{0, 0, 0};
  MaterialSpec material;
  std::vector<PinBox> pin_boxes;
  std::optional<PlasticitySpec> plasticity;
  std::optional<PlasticGoalSpec> plastic_goal;
  std::optional<FiberSpec> fiber;
  std::optional<SolidInitialShapeSpec> initial_shape;
  // pin_boxes[k]'s motion (Fixed: held still), about the box's pinned nodes' centre at rest.
  std::vector<MotionSpec> pin_box_motions;
  std::optional<FractureSpec> fracture;

  static const FieldTable<SolidSpec>& fields();  // scene_fields.cpp
};

struct ClothMaterialSpec {
  std::string model = "rotated_linear";  // as MaterialSpec's (in-plane, plane stress; mass_spring: edge springs)
  double young = 1e6;             // [Pa], in-plane
  double poisson = 0.3;
  double compression_limit = 0.3;      // neo_hookean, stvk
  double hardening_deformation = 0.5;  // spline: t
  double hardening_strength = 7;       // spline: r
  double density = 300;           // [kg/m^3]; areal density = density * thickness
  double thickness = 0.001;       // [m]
  double damping = 0.01;          // k [s] for the in-plane rotated damping
  double bending_stiffness = 1e-4;  // BMF03 k_e [N m]
  double bending_damping = 1e-5;    // BMF03 k_d [N m s]

  static const FieldTable<ClothMaterialSpec>& fields();  // scene_fields.cpp
};

struct GridSpec {
  double width = 1, height = 1;   // [m], in the x-z plane before the transform
  int nx = 20, ny = 20;

  static const FieldTable<GridSpec>& fields();  // scene_fields.cpp
};

// A generated shell: the upper half of a torus about the y axis (its tube angle in [0, pi]),
// standing on its two rims in the plane y = 0 before the transform.
struct HalfTorusSpec {
  double major_radius = 0.5;  // R [m], axis to tube centre
  double minor_radius = 0.2;  // r [m], tube
  int around = 70;            // cells around the axis
  int across = 25;            // cells across the tube

  static const FieldTable<HalfTorusSpec>& fields();  // scene_fields.cpp
};

struct BendingPlasticitySpec {     // ITF04 8: plastic rest angles
  double yield_degrees = 5;        // gamma_b
  double max_change_degrees = 90;  // limit on |theta_p - theta_0|

  static const FieldTable<BendingPlasticitySpec>& fields();  // scene_fields.cpp
};

struct StitchSpec {
  bool from_mesh = true;                    // use the mesh file's `stitch` lines
  // More stitches [i, j, k, r], 0-based vertices, read in 64 bits and checked against the mesh
  // when the cloth is built (a scene file knows no vertex count).
  struct Extra {
    std::array<std::int64_t, 3> vertices{0, 0, 0};
    double r = 0;
  };
  std::vector<Extra> list;
  double stiffness = 1e3;                   // [N/m^2] per metre of seam
  double damping = 0;                       // [N s/m^2] per metre of seam
  double closing_speed = 0;                 // [m/s] sewing: rest lengths close from the start gaps; 0: closed

  static const FieldTable<StitchSpec>& fields();  // scene_fields.cpp
};

// Pinned vertices, chosen by index list, box (rest positions) or group, held still or moved.
struct PinSpec {
  std::vector<std::int64_t> vertices;  // checked against the mesh when the cloth is built
  std::optional<PinBox> box;
  std::string group;
  MotionSpec motion;  // Fixed: held still; else carried by the motion about their rest positions
};

// Cloth vertices tied to a solid (world.hpp Attachment), chosen as pins are: by vertex list, box
// (the cloth's initial positions) or group (`selection`; its motion stays Fixed). Each is embedded
// in the solid's tet that holds it, or on the closest boundary triangle, when the run starts.
struct AttachmentSpec {
  std::string solid;
  PinSpec selection;
};

struct ClothSpec {
  std::string name;
  std::vector<AttachmentSpec> attachments;
  bool self_collision = true;     // takes part in the self-collision layer
  std::filesystem::path mesh;     // empty: a grid or a shape
  GridSpec grid;
  std::optional<HalfTorusSpec> half_torus;
  std::string rest_shape = "mesh";     // mesh | pattern (the OBJ's vt)
  std::filesystem::path initial_shape; // optional: the same vertices, another shape (a drape)
  std::optional<Transform> initial_transform;  // for initial_shape; default: `transform`
  Transform transform;
  std::array<double, 3> velocity{0, 0, 0};
  ClothMaterialSpec material;
  std::optional<PlasticitySpec> plasticity;                 // in-plane
  std::optional<BendingPlasticitySpec> bending_plasticity;
  std::string inversion_test = "none";                     // none | rest | direction
  std::array<double, 3> inversion_direction{0, 1, 0};
  StitchSpec stitches;
  std::vector<std::int64_t> pin_vertices;  // vertex indices of the mesh, held in place (checked when built)
  std::vector<PinBox> pin_boxes;  // every vertex whose world rest position lies in a box
  std::vector<PinSpec> pins;      // general pins (with groups and motions)

  static const FieldTable<ClothSpec>& fields();  // scene_fields.cpp
};

struct CameraSpec {
  bool automatic = true;          // framed around the objects' first frame
  std::array<double, 3> position{0, 1, 4}, target{0, 0.5, 0};
  double fov_degrees = 35;

  static const FieldTable<CameraSpec>& fields();  // scene_fields.cpp
};

struct RenderSpec {
  int width = 640, height = 480;
  bool ground = true;
  CameraSpec camera;

  static const FieldTable<RenderSpec>& fields();  // scene_fields.cpp
};

// A body from a mesh sequence (collisions/body_sequence.hpp): its frame files, by pattern or list.
struct SequenceSpec {
  std::string pattern;  // absolute, with its {N} / {N:0W} placeholder; empty: `files` as listed
  int first = 0, last = 0;                  // pattern: frame numbers
  std::vector<std::filesystem::path> files; // absolute, frame k = files[k] (expanded from the pattern)
  double fps = 25;                          // [frames/s] of the sequence
  double start_time = 0;                    // [s] when frame 0 (files[0]) is shown
  std::optional<int> start_frame;           // given instead: files[start_frame] at t = 0
  std::string after_end = "hold";           // hold | loop
};

// A body from a rigged, animated character (collisions/skinned_body.hpp).
struct SkinnedSpec {
  std::filesystem::path file;       // absolute: any file assimp reads with bones and a clip
  std::string clip = "0";           // the clip's name, or its index
  double start_time = 0;            // [s] when the clip's time 0 is shown
  double pre_roll = 0;              // [s] from the bind pose into the clip's first pose
  std::string after_end = "hold";   // hold | loop
};

struct ColliderSpec {
  std::string name;
  std::string type = "plane";  // plane | sphere | box | cylinder | gears | mesh | sequence | skinned
  std::array<double, 3> point{0, 0, 0};      // plane
  std::array<double, 3> normal{0, 1, 0};     // plane
  double radius = 0.5;                        // sphere, cylinder
  std::array<double, 3> half_extents{0.5, 0.5, 0.5};  // box
  double half_height = 0.5;                   // cylinder (axis y in its frame)
  int teeth = 12;                             // gears: a pair turning in opposite directions
  double outer_radius = 0.5, root_radius = 0.4, thickness = 0.3, clearance = 0.0;
  std::filesystem::path mesh;                 // mesh: any triangle surface assimp reads
  double query_radius = 0.05;                 // mesh, sequence, skinned: contact search distance [m]
  double offset = 1e-3;                       // mesh, sequence, skinned: collision surface outside the mesh [m]
  SequenceSpec sequence;                      // sequence
  SkinnedSpec skinned;                        // skinned
  double loop_blend = 0;                      // skinned, after_end loop: [s] the wrap's cross-fade
  Transform transform;                        // body -> world at rest (not with keyframes)
  MotionSpec motion;
  double friction = 0.3;

  static const FieldTable<ColliderSpec>& fields();  // scene_fields.cpp
};

struct SolverSpec {
  // "itf04" (the ITF04 section 9 step) | "implicit" (backward Euler by Newton, core/implicit_step.hpp).
  // Default: implicit when the scene has a cloth, else itf04.
  std::string integrator;
  // implicit: how the Newton systems are solved, "cg" (block-Jacobi PCG) | "direct" (sparse LDL^T,
  // core/sparse_direct.hpp). CG is the default: the direct solve is slower on the cloth drapes
  // and the dress, faster on a stiff shell that CG barely solves.
  std::string linear = "cg";
  std::string preconditioner = "auto";  // auto | block_jacobi | amg (implicit integrator, CG)
  double cfl = 0.5;
  double max_dt = 0.005;          // [s]; implicit default: half a frame
  double cg_tolerance = 1e-8;     // relative residual (itf04 solves; floor of the implicit forcing term)
  int cg_max_iterations = 1000;
  double newton_tolerance = 1e-4;   // implicit: |S grad E| relative to the forces at play
  int newton_max_iterations = 12;   // implicit: a step that hits it is reported
  // A frame that would take more steps stops the run (exit 1) instead of running for days; the
  // run prints its step size and estimate at the start when a frame needs over 1000.
  int max_substeps_per_frame = 20000;
  // [m] motion-bounded steps (WorldSettings::max_step_motion); 0: the colliders' limits only.
  double max_step_motion = 0;
  int max_step_retries = 3;  // WorldSettings::max_step_retries

  static const FieldTable<SolverSpec>& fields();  // scene_fields.cpp
};

// The self-collision layer (collisions/self_collision_pass.hpp), run after every step on every
// object that takes part, and on the colliders' triangles.
struct SelfCollisionSpec {
  bool enabled = true;
  double thickness = 1e-3;      // repulsion thickness [m]
  double ccd_distance = 1e-5;   // separation the CCD keeps [m]
  double friction = 0.3;
  int impulse_passes = 3;
  int max_zone_iterations = 100;
  bool colliders = true;        // mesh colliders' triangles take part (infinite mass)

  static const FieldTable<SelfCollisionSpec>& fields();  // scene_fields.cpp
};

struct Scene {
  std::filesystem::path file;
  std::string name;
  double fps = 30;
  int frames = 60;  // frames after frame 0
  // The number frame 0 carries in the files a run writes (NNNN.obj, png/NNNN.png) and in their
  // time codes (USD, PC2): DCC timelines start at 1. Frame k is written as k + first_frame_number;
  // options and energies.csv count frames from 0.
  int first_frame_number = 0;
  std::array<double, 3> gravity{0, -9.81, 0};
  SolverSpec solver;
  SelfCollisionSpec self_collision;
  std::vector<SolidSpec> solids;
  std::vector<ClothSpec> cloths;
  std::vector<ColliderSpec> colliders;
  RenderSpec render;
  nlohmann::json quick;           // field overrides for a quick-resolution run (--quick)

  static const FieldTable<Scene>& fields();  // scene_fields.cpp
  int file_number(int frame) const { return frame + first_frame_number; }
};

// Parse and validate. Throws InputError naming the file, the JSON path, what was expected and
// what was found. `overrides` are "path.to.field=value" assignments applied to the JSON before
// validation (--set); `quick` applies the scene's own "quick" overrides first.
Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {},
                 bool quick = false);
// load_scene's work on a scene already parsed (the Python module's dicts): `file` names it in
// errors and resolves its relative paths.
Scene scene_from_json(nlohmann::json j, const std::filesystem::path& file, const std::vector<std::string>& overrides = {},
                      bool quick = false);
// check_files = false skips the existence checks of mesh paths (rendering a finished run needs
// only its frames).
Scene parse_scene(const nlohmann::json& j, const std::filesystem::path& file, bool check_files = true);

// The scene with every default filled in (what OUT/scene.json holds).
nlohmann::json to_json(const Scene& scene);

// The field tables of apps/scenes/README.md, generated from the specs' field tables
// (scene_fields.cpp): (section, Markdown table). The document holds each between the lines
// `<!-- fields: SECTION -->` and `<!-- /fields -->`.
std::vector<std::pair<std::string, std::string>> scene_field_tables();

}  // namespace invfem::app
