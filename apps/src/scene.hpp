#pragma once
// The scene file, parsed and validated from JSON: the modules' own settings (WorldSettings,
// SelfCollisionSettings, TetMaterial, ClothObjectParams, ...) filled by the field tables
// (scene_tables.cpp), and three descriptions that are no module's parameters: a solid, a cloth
// and a collider (their names, files, transforms and selections). The schema is documented in
// apps/scenes/README.md; every default is the initializer of the member a field fills, so the run
// can write the scene back out complete (OUT/scene.json).
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <filesystem>
#include <string>
#include <vector>

#include "invfem/collisions/colliders/body_sequence.hpp"
#include "invfem/collisions/colliders/gear.hpp"
#include "invfem/collisions/colliders/rigid_collisions.hpp"
#include "invfem/collisions/colliders/skinned_body.hpp"
#include "invfem/collisions/self_collision/self_collision_pass.hpp"
#include "invfem/core/integrate/material_choice.hpp"
#include "invfem/core/math/plasticity.hpp"
#include "invfem/core/math/plasticity_control.hpp"
#include "invfem/core/geometry/rigid_motion.hpp"
#include "invfem/core/math/scalar_track.hpp"
#include "invfem/core/world/world.hpp"
#include "invfem/renders/camera.hpp"
#include "invfem/renders/mesh_renderer.hpp"
#include "invfem/shells/bending_force.hpp"
#include "invfem/shells/cloth_object.hpp"
#include "invfem/shells/garment.hpp"
#include "invfem/shells/shapes.hpp"
#include "invfem/shells/stitch_force.hpp"
#include "invfem/solids/bcc_mesher.hpp"
#include "invfem/solids/fracture_criterion.hpp"
#include "invfem/solids/scramble.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "field_table.hpp"

namespace invfem::app {

struct Transform {
  double scale = 1;
  std::array<double, 3> rotate_degrees{0, 0, 0};  // applied x, then y, then z
  std::array<double, 3> translate{0, 0, 0};
};

struct PinBox {
  std::array<double, 3> min{0, 0, 0}, max{0, 0, 0};  // world rest positions inside are held still
};

struct SolidSpec {
  std::string name;
  // One-way coupling (ITF04 section 10): its deformed boundary is a moving collider for cloths
  // (never pushed back); `solid` is filled with the name when the world is built.
  bool cloth_coupling_enabled = true;
  SolidCoupling cloth_coupling;
  bool self_collision = true;  // its boundary surface takes part in the self-collision layer
  std::filesystem::path mesh;  // absolute, resolved against the scene file's folder
  BccMeshOptions meshing;      // when `mesh` is a surface: mesh_resolution
  Transform transform;
  std::array<double, 3> velocity{0, 0, 0};
  // `material`: the model chosen, and the rest of its FE material (density, damping, strength;
  // `plasticity`, `fiber`'s stiffnesses and activation), whose model and cfl are filled when built.
  MaterialChoice model;
  TetMaterial material;
  std::vector<PinBox> pin_boxes;
  std::optional<AxisScaledGoal> plastic_goal;  // ITF04 7: control toward the rest shape scaled per axis
  // ITF04 6.1: the muscle fibers (material.fiber) run along one material (rest) direction, world axes.
  std::array<double, 3> fiber_direction{1, 0, 0};
  // Where it starts (`initial_shape`; the rest shape stays the mesh's): node positions from a
  // file (same nodes, same order as its mesh) or a scramble of its rest positions.
  std::filesystem::path initial_shape;         // a tet mesh or OBJ; empty: none, or a scramble
  std::optional<Transform> initial_transform;  // for the file; default: `transform`
  std::optional<Scramble> scramble;
  // pin_boxes[k]'s motion (Fixed: held still), about the box's pinned nodes' centre at rest.
  std::vector<MotionScript> pin_box_motions;
  // Ductile fracture by the virtual node algorithm (solids/fracture_criterion.hpp): a threshold
  // not given is infinite; a seed given has a factor below 1.
  std::optional<FractureCriterion> fracture;

  static const FieldTable<SolidSpec>& fields();  // scene_tables.cpp
};

// More stitches than the mesh file's (`stitches.list`): [i, j, k, r], 0-based vertices, read in
// 64 bits and checked against the mesh when the cloth is built (a scene file knows no vertex count).
struct ExtraStitch {
  std::array<std::int64_t, 3> vertices{0, 0, 0};
  double r = 0;
};

struct ClothSpec {
  std::string name;
  // `attachments`: (a solid, vertices chosen as pins are, by their initial positions) tied to the
  // solid (world.hpp Attachment), each embedded in the solid's tet that holds it, or on the
  // closest boundary triangle, when the run starts.
  std::vector<std::pair<std::string, VertexSelection>> attachments;
  bool self_collision = true;     // takes part in the self-collision layer
  std::filesystem::path mesh;     // empty: a grid or a shape
  GridParams grid;
  std::optional<HalfTorusParams> half_torus;
  std::string rest_shape = "mesh";     // mesh | pattern (the OBJ's vt)
  std::filesystem::path initial_shape; // optional: the same vertices, another shape (a drape)
  std::optional<Transform> initial_transform;  // for initial_shape; default: `transform`
  Transform transform;
  // `material`: the in-plane model chosen; the cloth's own parameters (thickness, density,
  // damping, bending and its plasticity, in-plane plasticity, stitches, the inversion test, the
  // initial velocity), whose model, gravity and pins are filled when built.
  MaterialChoice model{.young = 1e6};
  ClothObjectParams params;
  bool stitches_from_mesh = true;        // stitches.from_mesh: use the mesh file's `stitch` lines
  std::vector<ExtraStitch> extra_stitches;  // stitches.list
  std::vector<std::int64_t> pin_vertices;  // vertex indices of the mesh, held in place (checked when built)
  std::vector<PinBox> pin_boxes;  // every vertex whose world rest position lies in a box
  // `pins`: vertices by index list, box (initial positions) or group, with their motion (Fixed:
  // held still; else carried by it about their rest positions).
  std::vector<std::pair<VertexSelection, MotionScript>> pins;

  static const FieldTable<ClothSpec>& fields();  // scene_tables.cpp
};

// A collider: its type's fields fill the module's own settings (GearPairParams, MeshSurfaceOptions,
// BodySequenceSettings, SkinnedBodySettings); what depends on the transform and motion, or on the
// file read, is filled when the colliders are built.
struct ColliderSpec {
  std::string name;
  std::string type = "plane";  // plane | sphere | box | cylinder | gears | mesh | sequence | skinned
  std::array<double, 3> point{0, 0, 0};      // plane
  std::array<double, 3> normal{0, 1, 0};     // plane
  double radius = 0.5;                        // sphere, cylinder
  std::array<double, 3> half_extents{0.5, 0.5, 0.5};  // box
  double half_height = 0.5;                   // cylinder (axis y in its frame)
  GearPairParams gears;                       // gears: a pair turning in opposite directions
  std::filesystem::path mesh;                 // mesh: any triangle surface assimp reads
  MeshSurfaceOptions contact = kBodyContact;  // mesh, sequence, skinned
  // sequence: files (absolute; frame k = files[k]), fps, start_time, after_end; given as a pattern,
  // its text (absolute, with its {N} placeholder) and frame numbers; start_frame: given instead of
  // start_time (files[start_frame] at t = 0).
  BodySequenceSettings sequence;
  std::string frames_pattern;
  int first_frame = 0, last_frame = 0;
  std::optional<int> start_frame;
  // skinned: start_time, pre_roll, after_end, loop_blend; the character's file (absolute) and its
  // clip by name or index.
  SkinnedBodySettings skinned;
  std::filesystem::path character;
  std::string clip = "0";
  Transform transform;                        // body -> world at rest (not with keyframes)
  MotionScript motion;
  double friction = BodySequenceSettings{}.friction;  // Coulomb coefficient, every type's

  static const FieldTable<ColliderSpec>& fields();  // scene_tables.cpp
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
  // The World's settings (`solver`; solver_fields()). solver.integrator, when not given, is
  // implicit with a cloth, else itf04, and the implicit max_dt half a frame.
  WorldSettings solver;
  double cfl = TetMaterial{}.cfl;  // solver.cfl, for every solid's explicit step
  // The self-collision layer (collisions/self_collision_pass.hpp), run after every step on every
  // object that takes part (`excluded` is filled from the objects' flags when the world is built),
  // and on the colliders' triangles; none when not enabled.
  bool self_collision_enabled = true;
  collisions::SelfCollisionSettings self_collision;
  std::vector<SolidSpec> solids;
  std::vector<ClothSpec> cloths;
  std::vector<ColliderSpec> colliders;
  renders::RenderSettings render;       // preview size and ground (render_fields())
  std::optional<renders::Camera> camera;  // render.camera; none: framed around the objects' first frame
  nlohmann::json quick;           // field overrides for a quick-resolution run (--quick)

  static const FieldTable<Scene>& fields();  // scene_tables.cpp
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

// The tables of the sections whose fields fill a module's settings (scene_tables.cpp).
const FieldTable<Scene>& solver_fields();           // Scene::solver, Scene::cfl
const FieldTable<Scene>& self_collision_fields();   // Scene::self_collision(_enabled)
const FieldTable<Scene>& settle_fields();           // Scene::solver.settle
const FieldTable<PlasticParams>& plasticity_fields();
const FieldTable<ClothSpec>& stitch_fields();        // ClothSpec::params.stitch, stitches_from_mesh
const FieldTable<SolidSpec>& material_fields();      // SolidSpec::model, material
const FieldTable<ClothSpec>& cloth_material_fields();  // ClothSpec::model, params
const FieldTable<SolidSpec>& cloth_coupling_fields();  // SolidSpec::cloth_coupling(_enabled)
const FieldTable<FractureCriterion>& fracture_fields();
const FieldTable<BendingPlasticity>& bending_plasticity_fields();
const FieldTable<GridParams>& grid_fields();
const FieldTable<AxisScaledGoal>& plastic_goal_fields();
const FieldTable<FiberMaterial>& fiber_fields();
const FieldTable<Scramble>& initial_shape_fields();  // a solid's initial_shape
const FieldTable<renders::RenderSettings>& render_fields();
const FieldTable<renders::Camera>& camera_fields();
const FieldTable<HalfTorusParams>& half_torus_fields();

// The field tables of apps/scenes/README.md, generated from the specs' field tables
// (scene_tables.cpp): (section, Markdown table). The document holds each between the lines
// `<!-- fields: SECTION -->` and `<!-- /fields -->`.
std::vector<std::pair<std::string, std::string>> scene_field_tables();

}  // namespace invfem::app
