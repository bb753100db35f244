#include "scene.hpp"

#include <cmath>
#include <fstream>
#include <set>

#include "invfem/collisions/colliders/body_sequence.hpp"
#include "invfem/solids/scramble.hpp"
#include "input_check.hpp"
#include "json_reader.hpp"
#include "scene_parsing.hpp"

namespace invfem::app {

namespace scene_detail {

ScalarTrack parse_track(const Fields& f, const std::string& key, double fallback) {
  if (!f.has(key)) return ScalarTrack::constant(fallback);
  const auto& v = f.raw(key);
  if (v.is_number()) return ScalarTrack::constant(f.number_in(key, fallback, 0, 1e6));
  if (!v.is_array() || v.empty())
    f.fail(key, "a number or a non-empty array of [time, value] keys");
  ScalarTrack track;
  double last_t = -INFINITY;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& k = v[i];
    if (!k.is_array() || k.size() != 2 || !k[0].is_number() || !k[1].is_number())
      f.fail(key, "[time, value] pairs of numbers", "element " + std::to_string(i) + ": " + describe(k));
    const double t = k[0].get<double>(), x = k[1].get<double>();
    if (!(std::abs(t) <= limits::kTime) || !std::isfinite(x) || x < 0)
      f.fail(key, "times in [-1e9, 1e9] s and finite values >= 0", "element " + std::to_string(i) + ": " + describe(k));
    if (t < last_t) f.fail(key, "keys sorted by time", "element " + std::to_string(i) + ": " + describe(k));
    last_t = t;
    track.keys.emplace_back(t, x);
  }
  return track;
}

// $.solids[i].material into the solid.
void parse_material(const Fields& f, SolidSpec& solid) {
  material_fields().reject_unknown(f);
  material_fields().read(f, solid);
  solid.material.strength = parse_track(f, "strength", 1.0);
}

Transform parse_transform(const Fields& f) {
  f.reject_unknown({"scale", "rotate_degrees", "translate"});
  Transform t;
  t.scale = f.number("scale", t.scale);
  if (!(t.scale > 0 && t.scale <= limits::kScale)) f.fail("scale", "a scale in (0, 1e6]");
  t.rotate_degrees = f.vec3("rotate_degrees", t.rotate_degrees, limits::kDegrees);
  t.translate = f.vec3("translate", t.translate, limits::kLength);
  return t;
}

std::vector<PinBox> parse_pin_boxes(const Fields& f, std::vector<MotionScript>* motions) {
  std::vector<PinBox> boxes;
  if (!f.has("pin_boxes")) return boxes;
  const auto& v = f.raw("pin_boxes");
  if (!v.is_array()) f.fail("pin_boxes", "an array of {\"min\": [x, y, z], \"max\": [x, y, z]} boxes");
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Fields b(v[i], f.file(), f.path_of("pin_boxes") + "[" + std::to_string(i) + "]");
    boxes.push_back(parse_pin_box(b, motions != nullptr));
    if (motions) motions->push_back(parse_motion(b.object_or_empty("motion")));
  }
  return boxes;
}

PinBox parse_pin_box(const Fields& b, bool with_motion) {
  if (with_motion) b.reject_unknown({"min", "max", "motion"});
  else b.reject_unknown({"min", "max"});
  PinBox box;
  box.min = b.vec3("min", box.min, limits::kLength);
  box.max = b.vec3("max", box.max, limits::kLength);
  for (int k = 0; k < 3; ++k)
    if (box.min[k] > box.max[k]) b.fail("max", "a box with min <= max in every coordinate");
  return box;
}

std::filesystem::path parse_mesh_path(const Fields& f, const std::string& key, const std::filesystem::path& dir,
                                      bool check_files) {
  const std::filesystem::path p = std::filesystem::absolute(dir / f.string(key)).lexically_normal();
  if (check_files)
    if (const std::string problem = input_file_problem(p); !problem.empty())
      f.fail(key, "an existing mesh file", "\"" + p.string() + "\", which " + as_clause(problem));
  return p;
}

PlasticParams parse_plasticity(const Fields& f) {
  plasticity_fields().reject_unknown(f);
  PlasticParams p;
  plasticity_fields().read(f, p);
  return p;
}

// A seed given without a factor is cut at half the thresholds.
constexpr double kSeedFactor = 0.5;

FractureCriterion parse_fracture(const Fields& f) {
  fracture_fields().reject_unknown(f);
  FractureCriterion s;
  fracture_fields().read(f, s);
  if (std::isinf(s.max_principal_stress) && std::isinf(s.max_plastic_strain))
    f.fail("max_principal_stress", "a threshold: max_principal_stress [Pa] and/or max_plastic_strain");
  if (f.has("seed")) {
    const Fields b = f.object("seed");
    b.reject_unknown({"point", "normal", "min", "max", "factor"});
    if (!b.has("point")) b.fail("point", "a point [x, y, z] (m) of the seed plane");
    if (!b.has("normal")) b.fail("normal", "the seed plane's normal [x, y, z]");
    s.seed_point = to_vec3(b.vec3("point", {0, 0, 0}, limits::kLength));
    auto normal = b.vec3("normal", {0, 1, 0}, limits::kDirection);
    const double n = std::hypot(normal[0], normal[1], normal[2]);
    if (!(n > 1e-12)) b.fail("normal", "a non-zero vector");
    for (double& x : normal) x /= n;
    s.seed_normal = to_vec3(normal).normalized();
    if (b.has("min") != b.has("max")) b.fail(b.has("min") ? "max" : "min", "both corners of the seed's box, or neither");
    if (b.has("min")) {
      s.seed_min = to_vec3(b.vec3("min", {0, 0, 0}, limits::kLength));
      s.seed_max = to_vec3(b.vec3("max", {0, 0, 0}, limits::kLength));
      for (int k = 0; k < 3; ++k)
        if (s.seed_min[k] > s.seed_max[k]) b.fail("max", "a box with min <= max in every coordinate");
    }
    s.seed_factor = b.number("factor", kSeedFactor);
    if (!(s.seed_factor > 0 && s.seed_factor <= 1)) b.fail("factor", "a fraction of the thresholds in (0, 1]");
  }
  return s;
}

AxisScaledGoal parse_plastic_goal(const Fields& f) {
  plastic_goal_fields().reject_unknown(f);
  const auto scale = f.vec3("scale", {1, 1, 1}, limits::kScale);
  for (double x : scale)
    if (!(x > 0)) f.fail("scale", "per-axis scales > 0 (a goal must not be flat or inverted)");
  return AxisScaledGoal{to_vec3(scale), to_vec3(f.vec3("center", {0, 0, 0}, limits::kLength))};
}

// $.solids[i].fiber into the solid.
void parse_fiber(const Fields& f, SolidSpec& solid) {
  fiber_fields().reject_unknown(f);
  solid.fiber_direction = f.vec3("direction", solid.fiber_direction, limits::kDirection);
  const auto& d = solid.fiber_direction;
  if (std::hypot(d[0], d[1], d[2]) < 1e-12) f.fail("direction", "a non-zero vector");
  FiberMaterial fiber;
  fiber_fields().read(f, fiber);  // k_passive, k_active, max_contraction
  solid.material.fiber = fiber;
  solid.material.activation = parse_track(f, "activation", 0.0);
  for (const auto& [t, a] : solid.material.activation.keys)
    if (a > 1) f.fail("activation", "activation levels in [0, 1]");
}

// $.solids[i].initial_shape into the solid.
void parse_solid_initial_shape(const Fields& f, const std::filesystem::path& dir, bool check_files, SolidSpec& solid) {
  initial_shape_fields().reject_unknown(f);
  if (f.has("file") == f.has("scramble"))
    f.fail("file", "either a \"file\" or a \"scramble\"", f.has("file") ? "both" : "neither");
  if (f.has("file")) {
    for (const char* k : {"seed", "size"})
      if (f.has(k)) f.fail(k, std::string("no \"") + k + "\" with a file (it belongs to a scramble)");
    solid.initial_shape = parse_mesh_path(f, "file", dir, check_files);
    if (f.has("transform")) solid.initial_transform = parse_transform(f.object("transform"));
    return;
  }
  if (f.has("transform"))
    f.fail("transform", "no transform with a scramble (it scrambles the solid's transformed rest shape)");
  const std::string name = f.string("scramble");
  const auto kind = scramble_kind_from_name(name);
  if (!kind) f.fail("scramble", "one of " + scramble_kind_names());
  Scramble s;
  s.kind = *kind;
  initial_shape_fields().read(f, s);  // seed
  if (*kind == ScrambleKind::Box) {
    if (!f.has("size")) f.fail("size", "the box's edge [m] (a box scramble needs a size)");
    s.size = f.number("size");
    if (!(s.size > 0 && s.size <= limits::kLength)) f.fail("size", "a box edge > 0 [m], at most 1e6");
  } else if (f.has("size")) {
    f.fail("size", "no \"size\" on a " + name + " scramble (only a box has one)");
  }
  solid.scramble = s;
}

MotionScript parse_motion(const Fields& f) {
  f.reject_unknown({"velocity", "spin_axis", "spin_rate", "translate_keys", "rotate_keys"});
  MotionScript m;
  const bool keyed = f.has("translate_keys") || f.has("rotate_keys");
  const bool constant = f.has("velocity") || f.has("spin_rate") || f.has("spin_axis");
  if (keyed && constant)
    f.fail("translate_keys", "either keyframes or a constant velocity/spin, not both");
  if (constant) {
    m.kind = MotionScript::Kind::ConstantVelocity;
    m.velocity = to_vec3(f.vec3("velocity", vec3_json(m.velocity), limits::kSpeed));
    const auto axis = f.vec3("spin_axis", vec3_json(m.spin_axis), limits::kDirection);
    if (std::hypot(axis[0], axis[1], axis[2]) < 1e-12) f.fail("spin_axis", "a non-zero axis");
    m.spin_axis = to_vec3(axis);
    m.spin_rate = f.number_in("spin_rate", m.spin_rate, -limits::kAngularSpeed, limits::kAngularSpeed);
  }
  if (keyed) {
    m.kind = MotionScript::Kind::Keyframed;
    double last = -INFINITY;
    if (f.has("translate_keys")) {
      const auto& v = f.raw("translate_keys");
      if (!v.is_array() || v.empty()) f.fail("translate_keys", "an array of [time, [x, y, z]] keys");
      for (std::size_t i = 0; i < v.size(); ++i) {
        const auto& k = v[i];
        if (!k.is_array() || k.size() != 2 || !k[0].is_number() || !k[1].is_array() || k[1].size() != 3)
          f.fail("translate_keys", "[time, [x, y, z]] keys", "element " + std::to_string(i) + ": " + describe(k));
        const auto p = bounded_vec3(k[1], limits::kLength);
        if (!p)
          f.fail("translate_keys", "positions: " + vec3_expected(limits::kLength),
                 "element " + std::to_string(i) + ": " + describe(k));
        const double t = k[0].get<double>();
        if (!(std::abs(t) <= limits::kTime) || t < last)
          f.fail("translate_keys", "times in [-1e9, 1e9] s in increasing order", "element " + std::to_string(i));
        last = t;
        m.translate_keys.push_back(TranslationKey{t, to_vec3(*p)});
      }
    }
    last = -INFINITY;
    if (f.has("rotate_keys")) {
      const auto& v = f.raw("rotate_keys");
      if (!v.is_array() || v.empty()) f.fail("rotate_keys", "an array of [time, [ax, ay, az], degrees] keys");
      for (std::size_t i = 0; i < v.size(); ++i) {
        const auto& k = v[i];
        if (!k.is_array() || k.size() != 3 || !k[0].is_number() || !k[1].is_array() || k[1].size() != 3 ||
            !k[2].is_number())
          f.fail("rotate_keys", "[time, [ax, ay, az], degrees] keys", "element " + std::to_string(i) + ": " + describe(k));
        RotationKey key{k[0].get<double>(), Vec3::Zero(), k[2].get<double>()};
        const auto axis = bounded_vec3(k[1], limits::kDirection);
        if (!axis)
          f.fail("rotate_keys", "axes: " + vec3_expected(limits::kDirection), "element " + std::to_string(i) + ": " + describe(k));
        key.axis = to_vec3(*axis);
        if (!(std::abs(key.degrees) <= limits::kDegrees))
          f.fail("rotate_keys", "angles in [-1e6, 1e6] degrees", "element " + std::to_string(i) + ": " + describe(k));
        if (std::hypot(key.axis[0], key.axis[1], key.axis[2]) < 1e-12)
          f.fail("rotate_keys", "non-zero axes", "element " + std::to_string(i));
        if (!(std::abs(key.t) <= limits::kTime) || key.t < last)
          f.fail("rotate_keys", "times in [-1e9, 1e9] s in increasing order", "element " + std::to_string(i));
        last = key.t;
        m.rotate_keys.push_back(key);
      }
    }
  }
  return m;
}

// An animated body's `after_end` (a sequence's or a skinned body's): "hold" or "loop".
AnimationEnd read_after_end(const Fields& f) {
  const std::string v = f.string("after_end", "hold");
  if (v != "hold" && v != "loop") f.fail("after_end", "\"hold\" or \"loop\"");
  return v == "loop" ? AnimationEnd::Loop : AnimationEnd::Hold;
}
const char* after_end_name(AnimationEnd e) { return e == AnimationEnd::Loop ? "loop" : "hold"; }

// The frames of a "sequence" collider: `frames` {pattern, first, last} or `files` [...], paths
// relative to the scene's folder. With check_files every frame file must exist (a stat each;
// frame 0 is read and checked when the world is built, later frames when the run reaches them).
void parse_sequence(const Fields& f, const std::filesystem::path& dir, bool check_files, ColliderSpec& c) {
  BodySequenceSettings& q = c.sequence;
  if (f.has("frames") == f.has("files"))
    f.fail("frames", "either \"frames\": {\"pattern\", \"first\", \"last\"} or a \"files\" list",
           f.has("frames") ? "both" : "neither");
  if (f.has("frames")) {
    const Fields fr = f.object("frames");
    fr.reject_unknown({"pattern", "first", "last"});
    const std::string pattern = fr.string("pattern");
    c.first_frame = fr.integer("first", 0, 0, 100000000);
    if (!fr.has("last")) fr.fail("last", "the number of the last frame");
    c.last_frame = fr.integer("last", 0, 0, 100000000);
    if (c.last_frame < c.first_frame) fr.fail("last", "a last frame >= first (" + std::to_string(c.first_frame) + ")");
    c.frames_pattern = (std::filesystem::absolute(dir / pattern)).lexically_normal().string();
    try {
      q.files = expand_frame_pattern(c.frames_pattern, c.first_frame, c.last_frame);
    } catch (const std::invalid_argument& e) {
      fr.fail("pattern", "a pattern with one {N} or {N:0W} placeholder", e.what());
    }
    if (check_files)
      for (std::size_t k = 0; k < q.files.size(); ++k)
        if (const std::string problem = input_file_problem(q.files[k]); !problem.empty())
          fr.fail("pattern", "existing frame files",
                  "\"" + q.files[k] + "\" (frame " + std::to_string(c.first_frame + static_cast<int>(k)) +
                      "), which " + as_clause(problem));
  } else {
    const auto& v = f.raw("files");
    if (!v.is_array() || v.empty()) f.fail("files", "a non-empty array of frame file names");
    for (std::size_t k = 0; k < v.size(); ++k) {
      if (!v[k].is_string()) f.fail("files", "file names (strings)", "element " + std::to_string(k) + ": " + describe(v[k]));
      const std::filesystem::path p = std::filesystem::absolute(dir / v[k].get<std::string>()).lexically_normal();
      if (check_files)
        if (const std::string problem = input_file_problem(p); !problem.empty())
          f.fail("files", "existing frame files",
                 "\"" + p.string() + "\" (element " + std::to_string(k) + "), which " + as_clause(problem));
      q.files.push_back(p.string());
    }
  }
  if (!f.has("fps")) f.fail("fps", "the sequence's frame rate [frames/s]");
  q.fps = f.number_in("fps", q.fps, 1e-3, 1e6);
  if (f.has("start_time") && f.has("start_frame"))
    f.fail("start_frame", "either start_time or start_frame, not both");
  q.start_time = f.number_in("start_time", q.start_time, -1e9, 1e9);
  if (f.has("start_frame")) {
    c.start_frame = f.integer("start_frame", 0, 0, static_cast<int>(q.files.size()) - 1);
    q.start_time = -*c.start_frame / q.fps;
  }
  q.after_end = read_after_end(f);
}

// A "skinned" collider's file and clip (its name, or its index as a number or a string) and timing.
void parse_skinned(const Fields& f, const std::filesystem::path& dir, bool check_files, ColliderSpec& c) {
  SkinnedBodySettings& k = c.skinned;
  if (!f.has("file")) f.fail("file", "the character's file (glTF, FBX, Collada, .x: anything assimp reads with bones)");
  c.character = parse_mesh_path(f, "file", dir, check_files);
  if (f.has("clip")) {
    const auto& v = f.raw("clip");
    if (v.is_number_integer() && v.get<long long>() >= 0) c.clip = std::to_string(v.get<long long>());
    else if (v.is_string() && !v.get<std::string>().empty()) c.clip = v.get<std::string>();
    else f.fail("clip", "the clip's name (a string) or its index (an integer >= 0)");
  }
  k.start_time = f.number_in("start_time", k.start_time, -1e9, 1e9);
  k.pre_roll = f.number_in("pre_roll", k.pre_roll, 0, 1e6);
  k.after_end = read_after_end(f);
}

// A mesh, sequence or skinned collider's or a cloth coupling's contact (read by its table): the
// offset below its query radius.
void check_contact(const Fields& f, const MeshSurfaceOptions& contact) {
  try {
    validate(contact);  // the module's rule: offset below query_radius
  } catch (const std::invalid_argument&) {
    f.fail("offset", "an offset below query_radius (" + std::to_string(contact.query_radius) + " m)");
  }
}

ColliderSpec parse_collider(const Fields& f, const std::filesystem::path& dir, bool check_files) {
  const auto& table = ColliderSpec::fields();
  table.reject_unknown(f);
  ColliderSpec c;
  c.name = f.object_name("name");
  // Every type's; the others are read by type below (a plane reads none of them).
  rows_of(table, {"type", "friction"}).read(f, c);
  if (c.type != "sequence")
    for (const char* k : {"frames", "files", "fps", "start_frame"})
      if (f.has(k)) f.fail(k, std::string("no \"") + k + "\" on a " + c.type + " collider (it belongs to a sequence)");
  if (c.type != "skinned")
    for (const char* k : {"file", "clip", "pre_roll", "loop_blend"})
      if (f.has(k)) f.fail(k, std::string("no \"") + k + "\" on a " + c.type + " collider (it belongs to a skinned body)");
  if (c.type != "sequence" && c.type != "skinned")
    for (const char* k : {"start_time", "after_end"})
      if (f.has(k))
        f.fail(k, std::string("no \"") + k + "\" on a " + c.type + " collider (it belongs to a sequence or a skinned body)");
  // An animated body: its file or frames give its shape and motion.
  if (c.type == "skinned" || c.type == "sequence") {
    const std::string what = c.type == "skinned" ? "a skinned body (its file" : "a sequence (its frames";
    for (const char* k : {"point", "normal", "radius", "half_extents", "half_height", "teeth", "outer_radius",
                          "root_radius", "thickness", "clearance", "mesh", "motion"})
      if (f.has(k)) f.fail(k, std::string("no \"") + k + "\" on " + what + " give its shape and motion)");
    if (c.type == "skinned") {
      parse_skinned(f, dir, check_files, c);
      rows_of(table, {"loop_blend"}).read(f, c);
      if (c.skinned.loop_blend > 0 && c.skinned.after_end != AnimationEnd::Loop)
        f.fail("loop_blend", "0 with after_end \"" + std::string(after_end_name(c.skinned.after_end)) +
                                 "\" (a blend is for a loop)");
    } else {
      parse_sequence(f, dir, check_files, c);
    }
    rows_of(table, {"query_radius", "offset"}).read(f, c);
    check_contact(f, c.contact);
    c.transform = parse_transform(f.object_or_empty("transform"));
    return c;
  }
  if (c.type == "plane") {
    for (const char* k : {"radius", "half_extents", "half_height", "teeth", "mesh", "transform", "motion"})
      if (f.has(k)) f.fail(k, std::string("no \"") + k + "\" on a plane (a plane is static: point and normal)");
    c.point = f.vec3("point", c.point, limits::kLength);
    c.normal = f.vec3("normal", c.normal, limits::kDirection);
    if (std::hypot(c.normal[0], c.normal[1], c.normal[2]) < 1e-12) f.fail("normal", "a non-zero vector");
    return c;
  }
  if (c.type != "mesh" && f.has("offset"))
    f.fail("offset", "no \"offset\" on an analytic collider (mesh, sequence and skinned only)");
  // Every analytic size is checked whatever the type; type and friction again, unchanged.
  table.read(f, c);
  c.half_extents = f.vec3("half_extents", c.half_extents, limits::kLength);
  for (double h : c.half_extents)
    if (!(h > 0)) f.fail("half_extents", "three half extents > 0");
  if (c.type == "gears") {
    try {
      validate(c.gears.gear);  // the module's rule: root below outer (the table checked the rest)
    } catch (const std::invalid_argument&) {
      f.fail("root_radius", "a root radius below outer_radius");
    }
  }
  if (c.type == "mesh") {
    c.mesh = parse_mesh_path(f, "mesh", dir, check_files);
    check_contact(f, c.contact);
  }
  c.transform = parse_transform(f.object_or_empty("transform"));
  c.motion = parse_motion(f.object_or_empty("motion"));
  if (c.motion.kind == MotionScript::Kind::Keyframed && f.has("transform"))
    f.fail("transform", "no transform with keyframed motion (the keys are absolute poses)");
  if (c.type != "mesh" && f.object_or_empty("transform").has("scale"))
    f.fail("transform", "no scale on an analytic collider (set its radius or extents)");
  return c;
}

// $.render into the scene's render settings and camera.
void parse_render(const Fields& f, Scene& scene) {
  render_fields().reject_unknown(f);
  render_fields().read(f, scene.render);
  if (f.has("camera")) {
    const Fields c = f.object("camera");
    camera_fields().reject_unknown(c);
    renders::Camera camera;
    camera.position = to_vec3(c.vec3("position", vec3_json(camera.position), limits::kLength));
    camera.target = to_vec3(c.vec3("target", vec3_json(camera.target), limits::kLength));
    camera_fields().read(c, camera);
    if ((camera.position - camera.target).norm() < 1e-9) c.fail("target", "a target different from the camera position");
    scene.camera = camera;
  }
}

// Parse the value of a --set assignment: JSON if it parses (numbers, arrays, true, "text"),
// otherwise the raw text as a string.
// Text is kept only if it is valid UTF-8 (JSON strings are; the scene is written back out as
// JSON). Nesting deeper than kMaxJsonDepth is an error, not plain text.
nlohmann::json parse_override_value(const std::string& text, const std::string& origin) {
  if (auto value = try_parse_json(text, origin)) return std::move(*value);
  nlohmann::json plain = text;
  try {
    (void)plain.dump();  // throws for invalid UTF-8
  } catch (const nlohmann::json::exception&) {
    throw InputError(origin + ": the value is neither JSON nor valid UTF-8 text");
  }
  return plain;
}

// Apply "a.b.0.c=value" to j. Objects get missing keys created; arrays take an index.
void apply_override(nlohmann::json& j, const std::string& assignment, const std::string& origin) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(origin + ": \"" + assignment + "\": expected path.to.field=value");
  const std::string path = assignment.substr(0, eq);
  nlohmann::json* node = &j;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (key.empty()) throw InputError(origin + ": \"" + path + "\": empty component in the field path");
    if (node->is_array()) {
      std::size_t idx = 0;
      try {
        std::size_t used = 0;
        idx = std::stoul(key, &used);
        if (used != key.size()) throw std::invalid_argument(key);
      } catch (const std::exception&) {
        throw InputError(origin + ": \"" + path + "\": \"" + key + "\" must be an array index");
      }
      if (idx >= node->size())
        throw InputError(origin + ": \"" + path + "\": index " + key + " is past the end of an array of " +
                         std::to_string(node->size()));
      node = &(*node)[idx];
    } else if (node->is_object() || node->is_null()) {
      node = &(*node)[key];
    } else {
      throw InputError(origin + ": \"" + path + "\": \"" + key + "\" is inside a " + node->type_name() +
                       ", not an object or array");
    }
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  *node = parse_override_value(assignment.substr(eq + 1), origin + ": " + path);
}

}  // namespace scene_detail

using namespace scene_detail;

Scene parse_scene(const nlohmann::json& j, const std::filesystem::path& file, bool check_files) {
  const std::string fname = file.string();
  Fields root(j, fname, "$");
  Scene::fields().reject_unknown(root);
  Scene s;
  s.file = file;
  s.name = root.string("name", file.stem().string());
  Scene::fields().read(root, s);  // fps, frames
  s.gravity = root.vec3("gravity", s.gravity, limits::kAcceleration);

  const Fields solver = root.object_or_empty("solver");
  solver_fields().reject_unknown(solver);
  solver_fields().read(solver, s);

  const Fields sc = root.object_or_empty("self_collision");
  self_collision_fields().reject_unknown(sc);
  self_collision_fields().read(sc, s);
  try {
    collisions::validate(s.self_collision);  // the module's rule: ccd_distance below the thickness
  } catch (const std::invalid_argument&) {
    sc.fail("ccd_distance", "a distance below the thickness (" + format_number(s.self_collision.thickness) + " m)",
            format_number(s.self_collision.ccd_distance) + (sc.has("ccd_distance") ? "" : " (its default)"));
  }

  const Fields settle = root.object_or_empty("settle");
  settle_fields().reject_unknown(settle);
  settle_fields().read(settle, s);
  if (s.solver.settle.gravity_ramp > 0 && s.solver.settle.gravity)
    settle.fail("gravity_ramp", "0 while the settle has gravity (a ramp brings it back after a settle with "
                                "`gravity` false)", format_number(s.solver.settle.gravity_ramp));

  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  std::set<std::string> names;
  // Each name is checked where it is read (Fields::object_name), then for uniqueness here.
  auto unique_name = [&](const Fields& f, const std::string& name) {
    if (!names.insert(name).second) f.fail("name", "a name unique in the scene", "a second \"" + name + "\"");
  };

  if (j.contains("solids")) {
    if (!j["solids"].is_array()) root.fail("solids", "an array of solid objects");
    for (std::size_t i = 0; i < j["solids"].size(); ++i) {
      Fields f(j["solids"][i], fname, "$.solids[" + std::to_string(i) + "]");
      SolidSpec::fields().reject_unknown(f);
      SolidSpec solid;
      if (f.has("cloth_coupling")) {
        const Fields c = f.object("cloth_coupling");
        cloth_coupling_fields().reject_unknown(c);
        cloth_coupling_fields().read(c, solid);
        auto& cc = solid.cloth_coupling;
        check_contact(c, cc.surface);
        if (c.has("cloths")) {
          const auto& v = c.raw("cloths");
          if (!v.is_array()) c.fail("cloths", "an array of cloth names");
          for (std::size_t k = 0; k < v.size(); ++k) {
            if (!v[k].is_string()) c.fail("cloths", "cloth names", "element " + std::to_string(k) + ": " + describe(v[k]));
            cc.cloths.push_back(v[k].get<std::string>());
          }
        }
      }
      solid.name = f.object_name("name");
      SolidSpec::fields().read(f, solid);  // mesh_resolution, self_collision
      unique_name(f, solid.name);
      solid.mesh = parse_mesh_path(f, "mesh", dir, check_files);
      solid.transform = parse_transform(f.object_or_empty("transform"));
      solid.velocity = f.vec3("velocity", solid.velocity, limits::kSpeed);
      parse_material(f.object_or_empty("material"), solid);
      solid.pin_boxes = parse_pin_boxes(f, &solid.pin_box_motions);
      auto& plasticity = solid.material.plasticity;
      if (f.has("plasticity")) plasticity = parse_plasticity(f.object("plasticity"));
      if (f.has("plastic_goal")) {
        if (!plasticity) f.fail("plastic_goal", "a \"plasticity\" block as well (control steers plastic flow)");
        if (plasticity->preserve_volume)
          f.fail("plastic_goal", "plasticity.preserve_volume false (ITF04 7: a goal rarely preserves volume)");
        solid.plastic_goal = parse_plastic_goal(f.object("plastic_goal"));
      }
      if (f.has("fiber")) parse_fiber(f.object("fiber"), solid);
      if (solid.model.model == ModelKind::MassSpring)  // springs replace the FE elasticity these act on
        for (const char* key : {"plasticity", "plastic_goal", "fiber"})
          if (f.has(key)) f.fail(key, "no \"" + std::string(key) + "\" block with material.model \"mass_spring\" (springs have no F)");
      if (f.has("initial_shape")) parse_solid_initial_shape(f.object("initial_shape"), dir, check_files, solid);
      if (f.has("fracture")) {
        solid.fracture = parse_fracture(f.object("fracture"));
        if (std::isfinite(solid.fracture->max_plastic_strain) && !plasticity)
          f.fail("fracture", "a \"plasticity\" block as well for max_plastic_strain (without it Fp stays the identity)");
        if (solid.model.model == ModelKind::MassSpring)
          f.fail("fracture", "a finite-element material.model (the virtual node algorithm cuts tets; springs have "
                             "no stress to cut by)");
      }
      s.solids.push_back(std::move(solid));
    }
  }
  if (j.contains("cloths")) {
    if (!j["cloths"].is_array()) root.fail("cloths", "an array of cloth objects");
    for (std::size_t i = 0; i < j["cloths"].size(); ++i) {
      ClothSpec c = parse_cloth(Fields(j["cloths"][i], fname, "$.cloths[" + std::to_string(i) + "]"), dir, check_files);
      unique_name(Fields(j["cloths"][i], fname, "$.cloths[" + std::to_string(i) + "]"), c.name);
      s.cloths.push_back(std::move(c));
    }
  }
  if (s.solids.empty() && s.cloths.empty()) root.fail("solids", "at least one solid or cloth object");
  // Couplings and attachments name objects of the other kind.
  for (std::size_t i = 0; i < s.solids.size(); ++i)
    for (std::size_t k = 0; k < s.solids[i].cloth_coupling.cloths.size(); ++k) {
      const std::string& name = s.solids[i].cloth_coupling.cloths[k];
      if (std::none_of(s.cloths.begin(), s.cloths.end(), [&](const ClothSpec& c) { return c.name == name; }))
        Fields(j["solids"][i]["cloth_coupling"], fname, "$.solids[" + std::to_string(i) + "].cloth_coupling")
            .fail("cloths", "names of cloths of the scene", "element " + std::to_string(k) + ": \"" + name + "\"");
    }
  for (std::size_t i = 0; i < s.cloths.size(); ++i)
    for (std::size_t k = 0; k < s.cloths[i].attachments.size(); ++k) {
      const std::string& name = s.cloths[i].attachments[k].first;
      if (std::none_of(s.solids.begin(), s.solids.end(), [&](const SolidSpec& o) { return o.name == name; }))
        Fields(j["cloths"][i]["attachments"][k], fname,
               "$.cloths[" + std::to_string(i) + "].attachments[" + std::to_string(k) + "]")
            .fail("solid", "the name of a solid of the scene", "\"" + name + "\"");
    }
  // Cloth and garment scenes take large implicit steps unless they say otherwise (a cloth's
  // in-plane stiffness would cost hundreds of explicit substeps a frame).
  if (!solver.has("integrator")) s.solver.integrator = s.cloths.empty() ? Integrator::ITF04 : Integrator::Implicit;
  if (s.solver.integrator == Integrator::Implicit && !solver.has("max_dt")) s.solver.max_dt = 0.5 / s.fps;
  parse_render(root.object_or_empty("render"), s);
  if (j.contains("quick")) {
    if (!j["quick"].is_object()) root.fail("quick", "an object of field overrides, e.g. {\"frames\": 30}");
    s.quick = j["quick"];
  }

  if (j.contains("colliders")) {
    if (!j["colliders"].is_array()) root.fail("colliders", "an array of colliders");
    for (std::size_t i = 0; i < j["colliders"].size(); ++i) {
      const Fields f(j["colliders"][i], fname, "$.colliders[" + std::to_string(i) + "]");
      ColliderSpec c = parse_collider(f, dir, check_files);
      unique_name(f, c.name);
      // The world holds its kinematic bodies during a settle; an analytic collider's motion is
      // queried by time inside the collision processing and the self-collision layer, and would
      // not wait.
      const bool analytic = c.type != "sequence" && c.type != "skinned" && c.type != "mesh" && c.type != "plane";
      if (s.solver.settle.duration > 0 && analytic && c.motion.kind != MotionScript::Kind::Fixed)
        f.fail("motion", "no motion with a settle phase (settle.duration " + format_number(s.solver.settle.duration) +
                             " s): only mesh sequences and skinned characters wait for the settle's end",
               "a " + c.type + " with a motion");
      s.colliders.push_back(std::move(c));
    }
  }
  return s;
}

Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides, bool quick) {
  require_input_file(file, "scene file", kMaxSceneBytes);
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open the scene file");
  return scene_from_json(parse_json(in, file.string()), file, overrides, quick);
}

Scene scene_from_json(nlohmann::json j, const std::filesystem::path& file, const std::vector<std::string>& overrides,
                      bool quick) {
  if (quick && j.is_object() && j.contains("quick") && j["quick"].is_object()) {
    const nlohmann::json q = j["quick"];
    for (auto it = q.begin(); it != q.end(); ++it)
      apply_override(j, it.key() + "=" + it.value().dump(), file.string() + ": $.quick." + it.key());
  }
  for (const auto& o : overrides) apply_override(j, o, "--set");
  return parse_scene(j, file);
}

namespace scene_detail {
nlohmann::json track_json(const ScalarTrack& t) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& [time, v] : t.keys) a.push_back({time, v});
  return a;
}

nlohmann::json transform_json(const Transform& t) {
  return {{"scale", t.scale}, {"rotate_degrees", t.rotate_degrees}, {"translate", t.translate}};
}

nlohmann::json pin_boxes_json(const std::vector<PinBox>& boxes, const std::vector<MotionScript>* motions) {
  nlohmann::json a = nlohmann::json::array();
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    nlohmann::json b{{"min", boxes[k].min}, {"max", boxes[k].max}};
    // Only a moving box says so: the scene as run (and its hash) is unchanged for held boxes.
    if (motions && k < motions->size() && (*motions)[k].kind != MotionScript::Kind::Fixed)
      b["motion"] = motion_json((*motions)[k]);
    a.push_back(std::move(b));
  }
  return a;
}

nlohmann::json motion_json(const MotionScript& m) {
  nlohmann::json j = nlohmann::json::object();
  if (m.kind == MotionScript::Kind::ConstantVelocity) {
    j = {{"velocity", vec3_json(m.velocity)}, {"spin_axis", vec3_json(m.spin_axis)}, {"spin_rate", m.spin_rate}};
  } else if (m.kind == MotionScript::Kind::Keyframed) {
    if (!m.translate_keys.empty()) {
      j["translate_keys"] = nlohmann::json::array();
      for (const auto& k : m.translate_keys) j["translate_keys"].push_back({k.t, vec3_json(k.translation)});
    }
    if (!m.rotate_keys.empty()) {
      j["rotate_keys"] = nlohmann::json::array();
      for (const auto& k : m.rotate_keys) j["rotate_keys"].push_back({k.t, vec3_json(k.axis), k.degrees});
    }
  }
  return j;
}

nlohmann::json plasticity_json(const PlasticParams& p) { return fields_json(plasticity_fields(), p); }

nlohmann::json solid_initial_shape_json(const SolidSpec& o) {
  if (!o.initial_shape.empty()) {
    nlohmann::json j{{"file", o.initial_shape.string()}};
    if (o.initial_transform) j["transform"] = transform_json(*o.initial_transform);
    return j;
  }
  nlohmann::json j = fields_json(initial_shape_fields(), *o.scramble);  // seed
  j["scramble"] = std::string(scramble_kind_name(o.scramble->kind));
  if (o.scramble->kind == ScrambleKind::Box) j["size"] = o.scramble->size;
  return j;
}

nlohmann::json solid_json(const SolidSpec& o) {
  nlohmann::json j = fields_json(o);  // mesh_resolution, self_collision
  j["name"] = o.name;
  j["cloth_coupling"] = fields_json(cloth_coupling_fields(), o);
  j["cloth_coupling"]["cloths"] = o.cloth_coupling.cloths;
  j["mesh"] = o.mesh.string();
  j["transform"] = transform_json(o.transform);
  j["velocity"] = o.velocity;
  j["material"] = fields_json(material_fields(), o);
  j["material"]["strength"] = track_json(o.material.strength);
  j["pin_boxes"] = pin_boxes_json(o.pin_boxes, &o.pin_box_motions);
  if (o.material.plasticity) j["plasticity"] = plasticity_json(*o.material.plasticity);
  if (const auto& c = o.fracture) {
    nlohmann::json f = fields_json(fracture_fields(), *c);
    if (c->seed_factor < 1) {
      nlohmann::json sj{{"point", vec3_json(c->seed_point)}, {"normal", vec3_json(c->seed_normal)},
                        {"factor", c->seed_factor}};
      if (c->seed_min.allFinite()) sj["min"] = vec3_json(c->seed_min), sj["max"] = vec3_json(c->seed_max);
      f["seed"] = sj;
    }
    j["fracture"] = f;
  }
  if (o.plastic_goal)
    j["plastic_goal"] = {{"scale", vec3_json(o.plastic_goal->scale)}, {"center", vec3_json(o.plastic_goal->center)}};
  if (o.material.fiber) {
    j["fiber"] = fields_json(fiber_fields(), *o.material.fiber);  // k_passive, k_active, max_contraction
    j["fiber"]["direction"] = o.fiber_direction;
    j["fiber"]["activation"] = track_json(o.material.activation);
  }
  if (!o.initial_shape.empty() || o.scramble) j["initial_shape"] = solid_initial_shape_json(o);
  return j;
}

// The fields of c's type only (parse_collider).
nlohmann::json collider_json(const ColliderSpec& c) {
  const auto& table = ColliderSpec::fields();
  nlohmann::json j{{"name", c.name}};
  rows_of(table, {"type", "friction"}).write(j, c);
  if (c.type == "plane") {
    j["point"] = c.point;
    j["normal"] = c.normal;
    return j;
  }
  if (c.type == "sphere") rows_of(table, {"radius"}).write(j, c);
  if (c.type == "box") j["half_extents"] = c.half_extents;
  if (c.type == "cylinder") rows_of(table, {"radius", "half_height"}).write(j, c);
  if (c.type == "gears") rows_of(table, {"teeth", "outer_radius", "root_radius", "thickness", "clearance"}).write(j, c);
  if (c.type == "mesh") {
    j["mesh"] = c.mesh.string();
    rows_of(table, {"query_radius", "offset"}).write(j, c);
  }
  if (c.type == "skinned") {
    const SkinnedBodySettings& k = c.skinned;
    j["file"] = c.character.string();
    j["clip"] = c.clip;
    j["start_time"] = k.start_time;
    j["pre_roll"] = k.pre_roll;
    j["after_end"] = after_end_name(k.after_end);
    rows_of(table, {"loop_blend", "query_radius", "offset"}).write(j, c);
    j["transform"] = transform_json(c.transform);
    return j;
  }
  if (c.type == "sequence") {
    const BodySequenceSettings& q = c.sequence;
    if (!c.frames_pattern.empty())
      j["frames"] = {{"pattern", c.frames_pattern}, {"first", c.first_frame}, {"last", c.last_frame}};
    else
      j["files"] = q.files;
    j["fps"] = q.fps;
    if (c.start_frame) j["start_frame"] = *c.start_frame;
    else j["start_time"] = q.start_time;
    j["after_end"] = after_end_name(q.after_end);
    rows_of(table, {"query_radius", "offset"}).write(j, c);
    j["transform"] = transform_json(c.transform);
    return j;
  }
  if (c.motion.kind != MotionScript::Kind::Keyframed) {
    j["transform"] = transform_json(c.transform);
    if (c.type != "mesh") j["transform"].erase("scale");  // analytic shapes are sized, not scaled
  }
  j["motion"] = motion_json(c.motion);
  return j;
}
}  // namespace scene_detail

nlohmann::json to_json(const Scene& s) {
  nlohmann::json j;
  j["name"] = s.name;
  Scene::fields().write(j, s);  // fps, frames
  j["gravity"] = s.gravity;
  j["solver"] = fields_json(solver_fields(), s);
  j["self_collision"] = fields_json(self_collision_fields(), s);
  j["settle"] = fields_json(settle_fields(), s);
  j["solids"] = nlohmann::json::array();
  for (const auto& o : s.solids) j["solids"].push_back(solid_json(o));
  j["cloths"] = nlohmann::json::array();
  for (const auto& c : s.cloths) j["cloths"].push_back(cloth_json(c));
  j["colliders"] = nlohmann::json::array();
  for (const auto& c : s.colliders) j["colliders"].push_back(collider_json(c));
  j["render"] = fields_json(render_fields(), s.render);  // width, height, ground
  if (s.camera) {
    j["render"]["camera"] = fields_json(camera_fields(), *s.camera);  // fov_degrees
    j["render"]["camera"]["position"] = vec3_json(s.camera->position);
    j["render"]["camera"]["target"] = vec3_json(s.camera->target);
  }
  return j;
}

}  // namespace invfem::app
