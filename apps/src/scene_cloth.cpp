// Scene fields of a cloth, garment or shell object ($.cloths[i]); schema in apps/scenes/README.md.
#include <cmath>

#include "scene_parsing.hpp"

namespace invfem::app::scene_detail {

namespace {

// The vertices a pin or an attachment selects: exactly one of "vertices", "box" or "group".
VertexSelection parse_selection(const Fields& f) {
  VertexSelection p;
  const int ways = int(f.has("vertices")) + int(f.has("box")) + int(f.has("group"));
  if (ways != 1) f.fail("vertices", "exactly one of \"vertices\", \"box\" or \"group\"");
  if (f.has("vertices")) p.indices = f.index_list("vertices");
  if (f.has("box")) {
    const PinBox box = parse_pin_box(f.object("box"));
    p.box = {to_vec3(box.min), to_vec3(box.max)};
  }
  if (f.has("group")) {
    p.group = f.string("group");
    if (p.group.empty()) f.fail("group", "a group name");
  }
  return p;
}

nlohmann::json stitch_list_json(const std::vector<ExtraStitch>& list) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& e : list) a.push_back({e.vertices[0], e.vertices[1], e.vertices[2], e.r});
  return a;
}

nlohmann::json selection_json(const VertexSelection& p) {
  nlohmann::json j;
  if (p.box) j["box"] = {{"min", vec3_json(p.box->first)}, {"max", vec3_json(p.box->second)}};
  else if (!p.group.empty()) j["group"] = p.group;
  else j["vertices"] = p.indices;
  return j;
}

std::pair<VertexSelection, MotionScript> parse_pin(const Fields& f) {
  f.reject_unknown({"vertices", "box", "group", "motion"});
  return {parse_selection(f), parse_motion(f.object_or_empty("motion"))};
}

std::pair<std::string, VertexSelection> parse_attachment(const Fields& f) {
  f.reject_unknown({"solid", "vertices", "box", "group"});
  const std::string solid = f.string("solid");
  if (solid.empty()) f.fail("solid", "the name of a solid");
  VertexSelection selection = parse_selection(f);
  if (f.has("vertices") && selection.indices.empty()) f.fail("vertices", "at least one vertex index");
  return {solid, std::move(selection)};
}

// $.cloths[i].stitches into c.
void parse_stitches(const Fields& f, ClothSpec& c) {
  stitch_fields().reject_unknown(f);
  stitch_fields().read(f, c);  // from_mesh, stiffness, damping, closing_speed
  if (f.has("list")) {
    const auto& v = f.raw("list");
    if (!v.is_array()) f.fail("list", "an array of [i, j, k, r] stitches");
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto& e = v[i];
      const bool ok = e.is_array() && e.size() == 4 && e[0].is_number_integer() && e[1].is_number_integer() &&
                      e[2].is_number_integer() && e[3].is_number();
      if (!ok) f.fail("list", "[i, j, k, r] with integer vertices and a number r", "element " + std::to_string(i) + ": " + describe(e));
      ExtraStitch st;
      for (std::size_t a = 0; a < 3; ++a) {
        const auto idx = json_int64(e[a]);
        if (!idx || *idx < 0) f.fail("list", "vertex indices >= 0", "element " + std::to_string(i) + ": " + describe(e));
        st.vertices[a] = *idx;
      }
      st.r = e[3].get<double>();
      if (!(st.r >= 0 && st.r <= 1)) f.fail("list", "r in [0, 1]", "element " + std::to_string(i) + ": " + describe(e));
      c.extra_stitches.push_back(st);
    }
  }
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
    half_torus_fields().reject_unknown(h);
    HalfTorusParams t;
    half_torus_fields().read(h, t);
    try {
      validate(t);  // the module's rule: the tube below major_radius (the table checked the rest)
    } catch (const std::invalid_argument&) {
      h.fail("minor_radius", "a tube radius below major_radius");
    }
    c.half_torus = t;
  } else {
    const Fields g = f.object_or_empty("grid");
    grid_fields().reject_unknown(g);
    grid_fields().read(g, c.grid);
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
  c.params.velocity = to_vec3(f.vec3("velocity", vec3_json(c.params.velocity), limits::kSpeed));
  const Fields material = f.object_or_empty("material");
  cloth_material_fields().reject_unknown(material);
  cloth_material_fields().read(material, c);
  if (f.has("plasticity")) c.params.plasticity = parse_plasticity(f.object("plasticity"));
  if (f.has("bending_plasticity")) {
    const Fields b = f.object("bending_plasticity");
    bending_plasticity_fields().reject_unknown(b);
    BendingPlasticity bp;
    bending_plasticity_fields().read(b, bp);
    c.params.bending.plasticity = bp;
  }
  if (f.has("inversion_test")) {
    const auto& v = f.raw("inversion_test");
    if (v.is_string() && (v.get<std::string>() == "none" || v.get<std::string>() == "rest")) {
      c.params.inversion = v.get<std::string>() == "rest" ? InversionReference::Rest : InversionReference::None;
    } else if (v.is_array()) {
      c.params.inversion = InversionReference::Direction;
      const auto d = f.vec3("inversion_test", {0, 1, 0}, limits::kDirection);
      if (std::hypot(d[0], d[1], d[2]) < 1e-12) f.fail("inversion_test", "a non-zero direction");
      c.params.inversion_direction = to_vec3(d).normalized();
    } else {
      f.fail("inversion_test", "\"none\", \"rest\" or a direction [x, y, z]");
    }
  }
  const ModelKind model = c.model.model;
  if (model == ModelKind::MassSpring && c.params.plasticity)
    f.fail("plasticity", "no in-plane plasticity with material.model \"mass_spring\" (springs have no F)");
  if ((model == ModelKind::MassSpring || model == ModelKind::Corotated) && c.params.inversion != InversionReference::None)
    f.fail("inversion_test", "\"none\" with the baseline material.model \"" + std::string(model_kind_name(model)) +
                                 "\" (the inversion test is ITF04's inversion handling)");
  parse_stitches(f.object_or_empty("stitches"), c);
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
  j["velocity"] = vec3_json(c.params.velocity);
  j["material"] = fields_json(cloth_material_fields(), c);
  j["stitches"] = fields_json(stitch_fields(), c);
  j["stitches"]["list"] = stitch_list_json(c.extra_stitches);
  j["pin_vertices"] = c.pin_vertices;
  j["pin_boxes"] = pin_boxes_json(c.pin_boxes);
  if (!c.mesh.empty())
    j["mesh"] = c.mesh.string();
  else if (c.half_torus)
    j["half_torus"] = fields_json(half_torus_fields(), *c.half_torus);
  else
    j["grid"] = fields_json(grid_fields(), c.grid);
  if (!c.initial_shape.empty()) {
    j["initial_shape"] = {{"mesh", c.initial_shape.string()}};
    if (c.initial_transform) j["initial_shape"]["transform"] = transform_json(*c.initial_transform);
  }
  if (const auto& p = c.params.plasticity) j["plasticity"] = plasticity_json(*p);
  if (const auto& b = c.params.bending.plasticity) j["bending_plasticity"] = fields_json(bending_plasticity_fields(), *b);
  if (c.params.inversion == InversionReference::Direction)
    j["inversion_test"] = vec3_json(c.params.inversion_direction);
  else
    j["inversion_test"] = c.params.inversion == InversionReference::Rest ? "rest" : "none";
  if (!c.attachments.empty()) {
    j["attachments"] = nlohmann::json::array();
    for (const auto& [solid, selection] : c.attachments) {
      nlohmann::json aj = selection_json(selection);
      aj["solid"] = solid;
      j["attachments"].push_back(aj);
    }
  }
  if (!c.pins.empty()) {
    j["pins"] = nlohmann::json::array();
    for (const auto& [selection, motion] : c.pins) {
      nlohmann::json pj = selection_json(selection);
      pj["motion"] = motion_json(motion);
      j["pins"].push_back(pj);
    }
  }
  return j;
}

}  // namespace invfem::app::scene_detail
