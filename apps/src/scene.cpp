#include "scene.hpp"

#include <cmath>
#include <fstream>
#include <set>

#include "json_fields.hpp"

namespace invfem::app {

namespace {

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
    if (!std::isfinite(t) || !std::isfinite(x) || x < 0)
      f.fail(key, "finite times and values >= 0", "element " + std::to_string(i) + ": " + describe(k));
    if (t < last_t) f.fail(key, "keys sorted by time", "element " + std::to_string(i) + ": " + describe(k));
    last_t = t;
    track.keys.emplace_back(t, x);
  }
  return track;
}

MaterialSpec parse_material(const Fields& f) {
  f.reject_unknown({"model", "young", "poisson", "density", "damping", "compression_limit",
                    "hardening_deformation", "hardening_strength", "strength"});
  MaterialSpec m;
  m.model = f.string("model", m.model);
  static const std::set<std::string> models{"rotated_linear", "neo_hookean", "stvk", "spline"};
  if (!models.count(m.model)) f.fail("model", "one of rotated_linear, neo_hookean, stvk, spline");
  m.young = f.number_in("young", m.young, 0, 1e13);
  m.poisson = f.number("poisson", m.poisson);
  if (!(m.poisson > -1 && m.poisson < 0.5))
    f.fail("poisson", "a Poisson's ratio in (-1, 0.5) (0.5 is incompressible: use 0.49 or less)");
  m.density = f.number("density", m.density);
  if (!(m.density > 0)) f.fail("density", "a density > 0 [kg/m^3]");
  m.damping = f.number_in("damping", m.damping, 0, 10);
  m.compression_limit = f.number("compression_limit", m.compression_limit);
  if (!(m.compression_limit > 0 && m.compression_limit < 1)) f.fail("compression_limit", "a number in (0, 1)");
  m.hardening_deformation = f.number("hardening_deformation", m.hardening_deformation);
  if (!(m.hardening_deformation > 0 && m.hardening_deformation < 1))
    f.fail("hardening_deformation", "a number in (0, 1)");
  m.hardening_strength = f.number_in("hardening_strength", m.hardening_strength, 1, 1e3);
  m.strength = parse_track(f, "strength", 1.0);
  return m;
}

Transform parse_transform(const Fields& f) {
  f.reject_unknown({"scale", "rotate_degrees", "translate"});
  Transform t;
  t.scale = f.number("scale", t.scale);
  if (!(t.scale > 0)) f.fail("scale", "a scale > 0");
  t.rotate_degrees = f.vec3("rotate_degrees", t.rotate_degrees);
  t.translate = f.vec3("translate", t.translate);
  return t;
}

ClothMaterialSpec parse_cloth_material(const Fields& f) {
  f.reject_unknown({"young", "poisson", "density", "thickness", "damping", "bending_stiffness", "bending_damping"});
  ClothMaterialSpec m;
  m.young = f.number_in("young", m.young, 0, 1e13);
  m.poisson = f.number("poisson", m.poisson);
  if (!(m.poisson > -1 && m.poisson < 0.5)) f.fail("poisson", "a Poisson's ratio in (-1, 0.5)");
  m.density = f.number("density", m.density);
  if (!(m.density > 0)) f.fail("density", "a density > 0 [kg/m^3]");
  m.thickness = f.number("thickness", m.thickness);
  if (!(m.thickness > 0 && m.thickness < 1)) f.fail("thickness", "a thickness in (0, 1) [m]");
  m.damping = f.number_in("damping", m.damping, 0, 10);
  m.bending_stiffness = f.number_in("bending_stiffness", m.bending_stiffness, 0, 1e6);
  m.bending_damping = f.number_in("bending_damping", m.bending_damping, 0, 1e6);
  return m;
}

ClothSpec parse_cloth(const Fields& f, const std::filesystem::path& dir, bool check_files) {
  f.reject_unknown({"name", "mesh", "grid", "transform", "velocity", "material", "pin_vertices", "pin_box"});
  ClothSpec c;
  c.name = f.string("name");
  if (f.has("mesh") && f.has("grid")) f.fail("grid", "either \"mesh\" or \"grid\", not both");
  if (f.has("mesh")) {
    c.mesh = std::filesystem::absolute(dir / f.string("mesh")).lexically_normal();
    if (check_files && !std::filesystem::exists(c.mesh))
      f.fail("mesh", "an existing mesh file", "\"" + c.mesh.string() + "\", which does not exist");
  } else {
    const Fields g = f.object_or_empty("grid");
    g.reject_unknown({"width", "height", "nx", "ny"});
    c.grid.width = g.number_in("width", c.grid.width, 1e-4, 1e4);
    c.grid.height = g.number_in("height", c.grid.height, 1e-4, 1e4);
    c.grid.nx = g.integer("nx", c.grid.nx, 1, 2000);
    c.grid.ny = g.integer("ny", c.grid.ny, 1, 2000);
  }
  c.transform = parse_transform(f.object_or_empty("transform"));
  c.velocity = f.vec3("velocity", c.velocity);
  c.material = parse_cloth_material(f.object_or_empty("material"));
  if (f.has("pin_vertices")) {
    const auto& v = f.raw("pin_vertices");
    if (!v.is_array()) f.fail("pin_vertices", "an array of vertex indices");
    for (const auto& i : v) {
      if (!i.is_number_integer() || i.get<long long>() < 0)
        f.fail("pin_vertices", "vertex indices >= 0", describe(i));
      c.pin_vertices.push_back(i.get<int>());
    }
  }
  if (f.has("pin_box")) {
    const Fields b = f.object("pin_box");
    b.reject_unknown({"min", "max"});
    c.has_pin_box = true;
    c.pin_box_min = b.vec3("min", c.pin_box_min);
    c.pin_box_max = b.vec3("max", c.pin_box_max);
    for (int k = 0; k < 3; ++k)
      if (c.pin_box_min[k] > c.pin_box_max[k]) b.fail("max", "a box with min <= max in every coordinate");
  }
  return c;
}

RenderSpec parse_render(const Fields& f) {
  f.reject_unknown({"width", "height", "ground", "camera"});
  RenderSpec r;
  r.width = f.integer("width", r.width, 16, 8192);
  r.height = f.integer("height", r.height, 16, 8192);
  r.ground = f.boolean("ground", r.ground);
  if (f.has("camera")) {
    const Fields c = f.object("camera");
    c.reject_unknown({"position", "target", "fov_degrees"});
    r.camera.automatic = false;
    r.camera.position = c.vec3("position", r.camera.position);
    r.camera.target = c.vec3("target", r.camera.target);
    r.camera.fov_degrees = c.number_in("fov_degrees", r.camera.fov_degrees, 1, 170);
    const auto& p = r.camera.position;
    const auto& t = r.camera.target;
    if (std::hypot(p[0] - t[0], p[1] - t[1], p[2] - t[2]) < 1e-9)
      c.fail("target", "a target different from the camera position");
  }
  return r;
}

// Parse the value of a --set assignment: JSON if it parses (numbers, arrays, true, "text"),
// otherwise the raw text as a string.
nlohmann::json parse_override_value(const std::string& text) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error&) {
    return text;
  }
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
  *node = parse_override_value(assignment.substr(eq + 1));
}

}  // namespace

Scene parse_scene(const nlohmann::json& j, const std::filesystem::path& file, bool check_files) {
  const std::string fname = file.string();
  Fields root(j, fname, "$");
  root.reject_unknown({"name", "fps", "frames", "gravity", "solver", "solids", "cloths", "colliders", "render", "quick"});
  Scene s;
  s.file = file;
  s.name = root.string("name", file.stem().string());
  s.fps = root.number_in("fps", s.fps, 1, 10000);
  s.frames = root.integer("frames", s.frames, 0, 1000000);
  s.gravity = root.vec3("gravity", s.gravity);

  const Fields solver = root.object_or_empty("solver");
  solver.reject_unknown({"cfl", "max_dt", "cg_tolerance", "cg_max_iterations"});
  s.solver.cfl = solver.number_in("cfl", s.solver.cfl, 1e-3, 1);
  s.solver.max_dt = solver.number_in("max_dt", s.solver.max_dt, 1e-9, 1);
  s.solver.cg_tolerance = solver.number_in("cg_tolerance", s.solver.cg_tolerance, 1e-14, 1e-1);
  s.solver.cg_max_iterations = solver.integer("cg_max_iterations", s.solver.cg_max_iterations, 1, 100000);

  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  std::set<std::string> names;
  auto unique_name = [&](const Fields& f, const std::string& name) {
    if (name.empty()) f.fail("name", "a non-empty name");
    if (name.find_first_of("/\\") != std::string::npos) f.fail("name", "a name without slashes");
    if (!names.insert(name).second) f.fail("name", "a name unique in the scene", "a second \"" + name + "\"");
  };

  if (j.contains("solids")) {
    if (!j["solids"].is_array()) root.fail("solids", "an array of solid objects");
    for (std::size_t i = 0; i < j["solids"].size(); ++i) {
      Fields f(j["solids"][i], fname, "$.solids[" + std::to_string(i) + "]");
      f.reject_unknown({"name", "mesh", "transform", "velocity", "material"});
      SolidSpec solid;
      solid.name = f.string("name");
      unique_name(f, solid.name);
      solid.mesh = std::filesystem::absolute(dir / f.string("mesh")).lexically_normal();
      if (check_files && !std::filesystem::exists(solid.mesh))
        f.fail("mesh", "an existing mesh file", "\"" + solid.mesh.string() + "\", which does not exist");
      solid.transform = parse_transform(f.object_or_empty("transform"));
      solid.velocity = f.vec3("velocity", solid.velocity);
      solid.material = parse_material(f.object_or_empty("material"));
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
  s.render = parse_render(root.object_or_empty("render"));
  if (j.contains("quick")) {
    if (!j["quick"].is_object()) root.fail("quick", "an object of field overrides, e.g. {\"frames\": 30}");
    s.quick = j["quick"];
  }

  if (j.contains("colliders")) {
    if (!j["colliders"].is_array()) root.fail("colliders", "an array of colliders");
    for (std::size_t i = 0; i < j["colliders"].size(); ++i) {
      Fields f(j["colliders"][i], fname, "$.colliders[" + std::to_string(i) + "]");
      f.reject_unknown({"name", "type", "point", "normal", "friction"});
      ColliderSpec c;
      c.name = f.string("name");
      unique_name(f, c.name);
      c.type = f.string("type", c.type);
      if (c.type != "plane") f.fail("type", "\"plane\" (the only collider type so far)");
      c.point = f.vec3("point", c.point);
      c.normal = f.vec3("normal", c.normal);
      if (std::hypot(c.normal[0], c.normal[1], c.normal[2]) < 1e-12) f.fail("normal", "a non-zero vector");
      c.friction = f.number_in("friction", c.friction, 0, 100);
      s.colliders.push_back(c);
    }
  }
  return s;
}

Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides, bool quick) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open the scene file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(file.string() + ": not valid JSON: " + e.what());
  }
  if (quick && j.is_object() && j.contains("quick") && j["quick"].is_object()) {
    const nlohmann::json q = j["quick"];
    for (auto it = q.begin(); it != q.end(); ++it)
      apply_override(j, it.key() + "=" + it.value().dump(), file.string() + ": $.quick." + it.key());
  }
  for (const auto& o : overrides) apply_override(j, o, "--set");
  return parse_scene(j, file);
}

namespace {
nlohmann::json track_json(const ScalarTrack& t) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& [time, v] : t.keys) a.push_back({time, v});
  return a;
}
}  // namespace

nlohmann::json to_json(const Scene& s) {
  nlohmann::json j;
  j["name"] = s.name;
  j["fps"] = s.fps;
  j["frames"] = s.frames;
  j["gravity"] = s.gravity;
  j["solver"] = {{"cfl", s.solver.cfl}, {"max_dt", s.solver.max_dt}, {"cg_tolerance", s.solver.cg_tolerance},
                 {"cg_max_iterations", s.solver.cg_max_iterations}};
  j["solids"] = nlohmann::json::array();
  for (const auto& o : s.solids) {
    const auto& m = o.material;
    j["solids"].push_back(
        {{"name", o.name},
         {"mesh", o.mesh.string()},
         {"transform", {{"scale", o.transform.scale}, {"rotate_degrees", o.transform.rotate_degrees},
                        {"translate", o.transform.translate}}},
         {"velocity", o.velocity},
         {"material", {{"model", m.model}, {"young", m.young}, {"poisson", m.poisson}, {"density", m.density},
                       {"damping", m.damping}, {"compression_limit", m.compression_limit},
                       {"hardening_deformation", m.hardening_deformation},
                       {"hardening_strength", m.hardening_strength}, {"strength", track_json(m.strength)}}}});
  }
  j["cloths"] = nlohmann::json::array();
  for (const auto& c : s.cloths) {
    const auto& m = c.material;
    nlohmann::json cj{{"name", c.name},
                      {"transform", {{"scale", c.transform.scale}, {"rotate_degrees", c.transform.rotate_degrees},
                                     {"translate", c.transform.translate}}},
                      {"velocity", c.velocity},
                      {"material", {{"young", m.young}, {"poisson", m.poisson}, {"density", m.density},
                                    {"thickness", m.thickness}, {"damping", m.damping},
                                    {"bending_stiffness", m.bending_stiffness}, {"bending_damping", m.bending_damping}}},
                      {"pin_vertices", c.pin_vertices}};
    if (c.mesh.empty())
      cj["grid"] = {{"width", c.grid.width}, {"height", c.grid.height}, {"nx", c.grid.nx}, {"ny", c.grid.ny}};
    else
      cj["mesh"] = c.mesh.string();
    if (c.has_pin_box) cj["pin_box"] = {{"min", c.pin_box_min}, {"max", c.pin_box_max}};
    j["cloths"].push_back(cj);
  }
  j["render"] = {{"width", s.render.width}, {"height", s.render.height}, {"ground", s.render.ground}};
  if (!s.render.camera.automatic)
    j["render"]["camera"] = {{"position", s.render.camera.position}, {"target", s.render.camera.target},
                             {"fov_degrees", s.render.camera.fov_degrees}};
  j["colliders"] = nlohmann::json::array();
  for (const auto& c : s.colliders)
    j["colliders"].push_back({{"name", c.name}, {"type", c.type}, {"point", c.point}, {"normal", c.normal},
                              {"friction", c.friction}});
  return j;
}

}  // namespace invfem::app
