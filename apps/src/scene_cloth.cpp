// Scene fields of a cloth, garment or shell object ($.cloths[i]); schema in apps/scenes/README.md.
#include <cmath>

#include "scene_parts.hpp"

namespace invfem::app::scene_detail {

namespace {

ClothMaterialSpec parse_cloth_material(const Fields& f) {
  ClothMaterialSpec::fields().reject_unknown(f);
  ClothMaterialSpec m;
  ClothMaterialSpec::fields().read(f, m);
  return m;
}

// The vertices a pin or an attachment selects: exactly one of "vertices", "box" or "group".
PinSpec parse_selection(const Fields& f) {
  PinSpec p;
  const int ways = int(f.has("vertices")) + int(f.has("box")) + int(f.has("group"));
  if (ways != 1) f.fail("vertices", "exactly one of \"vertices\", \"box\" or \"group\"");
  if (f.has("vertices")) p.vertices = f.index_list("vertices");
  if (f.has("box")) p.box = parse_pin_box(f.object("box"));
  if (f.has("group")) {
    p.group = f.string("group");
    if (p.group.empty()) f.fail("group", "a group name");
  }
  return p;
}

nlohmann::json stitch_list_json(const StitchSpec& s) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& e : s.list) a.push_back({e.vertices[0], e.vertices[1], e.vertices[2], e.r});
  return a;
}

nlohmann::json selection_json(const PinSpec& p) {
  nlohmann::json j;
  if (p.box) j["box"] = {{"min", p.box->min}, {"max", p.box->max}};
  else if (!p.group.empty()) j["group"] = p.group;
  else j["vertices"] = p.vertices;
  return j;
}

PinSpec parse_pin(const Fields& f) {
  f.reject_unknown({"vertices", "box", "group", "motion"});
  PinSpec p = parse_selection(f);
  p.motion = parse_motion(f.object_or_empty("motion"));
  return p;
}

AttachmentSpec parse_attachment(const Fields& f) {
  f.reject_unknown({"solid", "vertices", "box", "group"});
  AttachmentSpec a;
  a.solid = f.string("solid");
  if (a.solid.empty()) f.fail("solid", "the name of a solid");
  a.selection = parse_selection(f);
  if (f.has("vertices") && a.selection.vertices.empty()) f.fail("vertices", "at least one vertex index");
  return a;
}

StitchSpec parse_stitches(const Fields& f) {
  StitchSpec::fields().reject_unknown(f);
  StitchSpec s;
  StitchSpec::fields().read(f, s);  // from_mesh, stiffness, damping, closing_speed
  if (f.has("list")) {
    const auto& v = f.raw("list");
    if (!v.is_array()) f.fail("list", "an array of [i, j, k, r] stitches");
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto& e = v[i];
      const bool ok = e.is_array() && e.size() == 4 && e[0].is_number_integer() && e[1].is_number_integer() &&
                      e[2].is_number_integer() && e[3].is_number();
      if (!ok) f.fail("list", "[i, j, k, r] with integer vertices and a number r", "element " + std::to_string(i) + ": " + describe(e));
      StitchSpec::Extra st;
      for (std::size_t a = 0; a < 3; ++a) {
        const auto idx = json_int64(e[a]);
        if (!idx || *idx < 0) f.fail("list", "vertex indices >= 0", "element " + std::to_string(i) + ": " + describe(e));
        st.vertices[a] = *idx;
      }
      st.r = e[3].get<double>();
      if (!(st.r >= 0 && st.r <= 1)) f.fail("list", "r in [0, 1]", "element " + std::to_string(i) + ": " + describe(e));
      s.list.push_back(st);
    }
  }
  return s;
}

}  // namespace

ClothSpec parse_cloth(const Fields& f, const std::filesystem::path& dir, bool check_files) {
  ClothSpec::fields().reject_unknown(f);
  ClothSpec c;
  c.name = f.object_name("name");
  ClothSpec::fields().read(f, c);  // rest_shape, self_collision
  const int shapes = int(f.has("mesh")) + int(f.has("grid")) + int(f.has("half_torus"));
  if (shapes > 1) f.fail("mesh", "one of \"mesh\", \"grid\" or \"half_torus\", not several");
  if (f.has("mesh")) {
    c.mesh = parse_mesh_path(f, "mesh", dir, check_files);
  } else if (f.has("half_torus")) {
    const Fields h = f.object("half_torus");
    HalfTorusSpec::fields().reject_unknown(h);
    HalfTorusSpec t;
    HalfTorusSpec::fields().read(h, t);
    if (!(t.minor_radius < t.major_radius)) h.fail("minor_radius", "a tube radius below major_radius");
    c.half_torus = t;
  } else {
    const Fields g = f.object_or_empty("grid");
    GridSpec::fields().reject_unknown(g);
    GridSpec::fields().read(g, c.grid);
  }
  if (c.rest_shape == "pattern" && c.mesh.empty())
    f.fail("rest_shape", "\"mesh\" for a grid or shape (a pattern comes from a mesh file's vt lines)");
  if (f.has("initial_shape")) {
    const Fields i = f.object("initial_shape");
    i.reject_unknown({"mesh", "transform"});
    if (c.mesh.empty()) f.fail("initial_shape", "a \"mesh\" object (an initial shape needs a mesh's vertex order)");
    c.initial_shape = parse_mesh_path(i, "mesh", dir, check_files);
    if (i.has("transform")) c.initial_transform = parse_transform(i.object("transform"));
  }
  c.transform = parse_transform(f.object_or_empty("transform"));
  c.velocity = f.vec3("velocity", c.velocity, limits::kSpeed);
  c.material = parse_cloth_material(f.object_or_empty("material"));
  if (f.has("plasticity")) c.plasticity = parse_plasticity(f.object("plasticity"));
  if (f.has("bending_plasticity")) {
    const Fields b = f.object("bending_plasticity");
    BendingPlasticitySpec::fields().reject_unknown(b);
    BendingPlasticitySpec bp;
    BendingPlasticitySpec::fields().read(b, bp);
    c.bending_plasticity = bp;
  }
  if (f.has("inversion_test")) {
    const auto& v = f.raw("inversion_test");
    if (v.is_string() && (v.get<std::string>() == "none" || v.get<std::string>() == "rest")) {
      c.inversion_test = v.get<std::string>();
    } else if (v.is_array()) {
      c.inversion_test = "direction";
      c.inversion_direction = f.vec3("inversion_test", c.inversion_direction, limits::kDirection);
      if (std::hypot(c.inversion_direction[0], c.inversion_direction[1], c.inversion_direction[2]) < 1e-12)
        f.fail("inversion_test", "a non-zero direction");
    } else {
      f.fail("inversion_test", "\"none\", \"rest\" or a direction [x, y, z]");
    }
  }
  if (c.material.model == "mass_spring" && c.plasticity)
    f.fail("plasticity", "no in-plane plasticity with material.model \"mass_spring\" (springs have no F)");
  if ((c.material.model == "mass_spring" || c.material.model == "corotated") && c.inversion_test != "none")
    f.fail("inversion_test", "\"none\" with the baseline material.model \"" + c.material.model +
                                 "\" (the inversion test is ITF04's inversion handling)");
  c.stitches = parse_stitches(f.object_or_empty("stitches"));
  if (f.has("pin_vertices")) c.pin_vertices = f.index_list("pin_vertices");
  c.pin_boxes = parse_pin_boxes(f);
  if (f.has("pins")) {
    const auto& v = f.raw("pins");
    if (!v.is_array()) f.fail("pins", "an array of pins");
    for (std::size_t i = 0; i < v.size(); ++i)
      c.pins.push_back(parse_pin(Fields(v[i], f.file(), f.path_of("pins") + "[" + std::to_string(i) + "]")));
  }
  if (f.has("attachments")) {
    const auto& v = f.raw("attachments");
    if (!v.is_array()) f.fail("attachments", "an array of attachments");
    for (std::size_t i = 0; i < v.size(); ++i)
      c.attachments.push_back(
          parse_attachment(Fields(v[i], f.file(), f.path_of("attachments") + "[" + std::to_string(i) + "]")));
  }
  return c;
}

nlohmann::json cloth_json(const ClothSpec& c) {
  nlohmann::json j = fields_json(c);  // rest_shape, self_collision
  j["name"] = c.name;
  j["transform"] = transform_json(c.transform);
  j["velocity"] = c.velocity;
  j["material"] = fields_json(c.material);
  j["stitches"] = fields_json(c.stitches);
  j["stitches"]["list"] = stitch_list_json(c.stitches);
  j["pin_vertices"] = c.pin_vertices;
  j["pin_boxes"] = pin_boxes_json(c.pin_boxes);
  if (!c.mesh.empty())
    j["mesh"] = c.mesh.string();
  else if (c.half_torus)
    j["half_torus"] = fields_json(*c.half_torus);
  else
    j["grid"] = fields_json(c.grid);
  if (!c.initial_shape.empty()) {
    j["initial_shape"] = {{"mesh", c.initial_shape.string()}};
    if (c.initial_transform) j["initial_shape"]["transform"] = transform_json(*c.initial_transform);
  }
  if (c.plasticity) j["plasticity"] = plasticity_json(*c.plasticity);
  if (c.bending_plasticity) j["bending_plasticity"] = fields_json(*c.bending_plasticity);
  if (c.inversion_test == "direction")
    j["inversion_test"] = c.inversion_direction;
  else
    j["inversion_test"] = c.inversion_test;
  if (!c.attachments.empty()) {
    j["attachments"] = nlohmann::json::array();
    for (const auto& a : c.attachments) {
      nlohmann::json aj = selection_json(a.selection);
      aj["solid"] = a.solid;
      j["attachments"].push_back(aj);
    }
  }
  if (!c.pins.empty()) {
    j["pins"] = nlohmann::json::array();
    for (const auto& p : c.pins) {
      nlohmann::json pj = selection_json(p);
      pj["motion"] = motion_json(p.motion);
      j["pins"].push_back(pj);
    }
  }
  return j;
}

}  // namespace invfem::app::scene_detail
