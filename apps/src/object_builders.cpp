#include "object_builders.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/world/pins.hpp"
#include "invfem/core/math/plasticity_control.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "collider_builders.hpp"
#include "invfem/shells/cloth_object.hpp"
#include "invfem/shells/garment.hpp"
#include "invfem/shells/shapes.hpp"
#include "invfem/solids/bcc_mesher.hpp"
#include "invfem/solids/initial_shape.hpp"
#include "invfem/solids/scramble.hpp"
#include "invfem/solids/solid_object.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_mesh_io.hpp"
#include "collider_builders.hpp"
#include "json_reader.hpp"
#include "material_factory.hpp"
#include "solid_surface_check.hpp"
#include "welds_file.hpp"
#include "invfem/collisions/certificate/intersection_count.hpp"

namespace invfem::app {

namespace {
Vec3 to_vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// One pin group per box: every node whose rest position lies in it, held still.
std::vector<PinGroup> pins_in_boxes(const Points& X, const std::vector<PinBox>& boxes, const std::string& what,
                                    const std::vector<MotionScript>* motions = nullptr) {
  std::vector<PinGroup> pins;
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    std::vector<int> nodes = nodes_in_box(X, to_vec(boxes[b].min), to_vec(boxes[b].max));
    if (nodes.empty()) throw InputError(what + ": pin_boxes[" + std::to_string(b) + "] contains no node");
    std::optional<Motion> motion;
    if (motions && b < motions->size() && (*motions)[b].kind != MotionScript::Kind::Fixed) {
      Vec3 centre = Vec3::Zero();
      for (int i : nodes) centre += X.row(i).transpose();
      motion = make_motion((*motions)[b], RigidTransform{}, centre / double(nodes.size()));
    }
    pins.push_back(make_pin_group(X, std::move(nodes), std::move(motion), what));
  }
  return pins;
}

// The solid's starting positions (a file in the mesh's node order, or a scramble of the
// transformed rest positions). Reading errors name the solid and the file.
Points initial_positions(const SolidSpec& spec, const TetMesh& mesh) {
  try {
    if (spec.scramble) return scramble_positions(mesh.X, *spec.scramble);
    Points x = read_initial_positions(spec.initial_shape.string(), mesh);
    apply_transform(spec.initial_transform.value_or(spec.transform), x,
                    "initial_shape file " + spec.initial_shape.string());
    return x;
  } catch (const std::exception& e) {
    throw InputError("solid \"" + spec.name + "\": initial_shape: " + e.what());
  }
}

}  // namespace

bool is_tet_mesh_file(const std::filesystem::path& p) {
  const std::string e = p.extension().string();
  return e == ".vtk" || e == ".mesh" || e == ".msh";
}

Mat3 rotation_of(const Transform& t) {
  constexpr double kDeg = 3.14159265358979323846 / 180;
  return (Eigen::AngleAxisd(t.rotate_degrees[2] * kDeg, Vec3::UnitZ()) *
          Eigen::AngleAxisd(t.rotate_degrees[1] * kDeg, Vec3::UnitY()) *
          Eigen::AngleAxisd(t.rotate_degrees[0] * kDeg, Vec3::UnitX()))
      .toRotationMatrix();
}

void apply_transform(const Transform& t, Points& X, const std::string& what) {
  const Mat3 R = rotation_of(t);
  const Vec3 shift = to_vec(t.translate);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const Vec3 p = t.scale * R * X.row(i).transpose() + shift;
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinate) {
      std::ostringstream m;
      m.precision(6);
      m << what << ": the transform (scale " << t.scale << ", translate [" << t.translate[0] << ", " << t.translate[1]
        << ", " << t.translate[2] << "]) puts node " << i << " at (" << p.x() << ", " << p.y() << ", " << p.z() << "), "
        << (p.allFinite() ? "beyond" : "not finite, and not within") << " the " << kMaxCoordinate
        << " m a scene's coordinates may reach: check its scale and translate";
      throw InputError(m.str());
    }
    X.row(i) = p.transpose();
  }
}

void check_object_size(const Points& X, double scale, const std::string& what) {
  if (X.rows() == 0) return;
  const double h = (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm();
  std::ostringstream m;
  m.precision(6);
  if (h > kMaxDiagonal)
    m << what << ": bounding-box diagonal " << h << " m exceeds " << kMaxDiagonal
      << " m; the mesh is probably in other units (mm?) or its scale is wrong: e.g. \"scale\": "
      << scale * std::pow(10.0, -std::ceil(std::log10(h)));
  else if (h < kMinDiagonal)
    m << what << ": bounding-box diagonal " << h << " m is below " << kMinDiagonal
      << " m; the mesh is probably in other units or its scale is wrong: e.g. \"scale\": "
      << scale * std::pow(10.0, std::ceil(std::log10(1.0 / std::max(h, 1e-300))));
  else
    return;
  throw InputError(m.str());
}

SolidObject build_solid(const SolidSpec& spec, const Scene& scene, TetMesh* mesh_out, LoadWarnings& warnings) {
  TetMesh mesh;
  try {
    if (is_tet_mesh_file(spec.mesh)) {
      mesh = read_tet_mesh(spec.mesh.string());
      apply_transform(spec.transform, mesh.X, "solid \"" + spec.name + "\"");
    } else {
      // A closed surface: tet-mesh it by the BCC lattice (after the transform, so the
      // resolution is in world units of the object's own size).
      TriangleSurface surface = load_triangle_surface(spec.mesh.string());
      apply_transform(spec.transform, surface.x, "solid \"" + spec.name + "\"");
      CheckedBccMesh meshed = check_and_bcc_mesh(surface, spec.mesh.string(), spec.meshing);
      for (const auto& w : meshed.check.warnings) warnings.add_printed(w);
      const BccMeshReport& r = meshed.result.report;
      std::cerr << "meshed " << spec.mesh.filename().string() << ": " << r.tets << " tets, volume ratio "
                << meshed.volume_ratio_text();
      std::cerr << ", dihedral angles " << r.min_dihedral_deg << "-" << r.max_dihedral_deg << " degrees\n";
      mesh = std::move(meshed.result.mesh);
    }
    const TetMeshReport report = validate_and_orient(mesh);
    for (const auto& w : report.warnings) warnings.add(spec.mesh.string() + ": " + w);
    if (!report.unused_nodes.empty())
      throw MeshError(spec.mesh.string() + ": " + std::to_string(report.unused_nodes.size()) +
                      " nodes belong to no tetrahedron (first: node " + std::to_string(report.unused_nodes[0]) +
                      "); they would have no mass");
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // MeshError, loader and mesher errors name the file
    throw InputError(std::string("solid \"") + spec.name + "\": " + e.what());
  }
  const std::string what = scene.file.string() + ": solid \"" + spec.name + "\"";
  SolidObjectParams params;
  params.velocity = to_vec(spec.velocity);
  params.gravity = to_vec(scene.gravity);
  params.pins = pins_in_boxes(mesh.X, spec.pin_boxes, what, &spec.pin_box_motions);
  if (!spec.initial_shape.empty() || spec.scramble) params.initial_positions = initial_positions(spec, mesh);
  try {
    TetMaterial material = make_tet_material(spec, scene.cfl);
    if (spec.plastic_goal) {
      const Points goal = axis_scaled_goal(mesh.X, *spec.plastic_goal);
      material.plastic_goal_log = make_plastic_goal(mesh.X, mesh.tets, goal).log_Fp_goal;
    }
    // Material space is the transformed rest mesh, so a direction in world axes at rest is
    // already a material direction.
    if (material.fiber) material.fiber_directions.assign(mesh.tets.rows(), to_vec(spec.fiber_direction).normalized());
    params.material = std::move(material);
    params.mass_spring = make_mass_spring(spec, scene.cfl);
    if (mesh_out) *mesh_out = mesh;
    return make_solid(spec.name, mesh, std::move(params));
  } catch (const std::invalid_argument& e) {
    throw InputError(what + ": " + e.what());
  }
}

namespace {

// The vertices a selection picks (boxes select by position at the start of the run): a pin's, an
// attachment's, a stitch's or pin_vertices' indices, checked against the mesh before narrowing;
// `what` names it in errors.
std::vector<int> pinned_vertices(const VertexSelection& s, const Garment& g, const Points& x0, const std::string& what) {
  try {
    return selected_vertices(s, g, x0, what);
  } catch (const std::invalid_argument& e) {
    throw InputError(s.group.empty() ? e.what() : what + ": " + e.what());
  }
}

// Warnings a cloth earns at load, each with its count and first example (a solid's surface gets
// its own in solid_surface_check): a pattern whose scale is far from the mesh's (outside
// [kPatternScaleLow, kPatternScaleHigh]: a rest shape that much smaller or larger than the garment,
// usually a texture layout in [0, 1] read as a pattern), and a start that crosses itself (the
// certificate's count, seams exempt as in `invfem check`), which the self-collision layer cannot
// undo.
// A pattern rest shape a thousand times off the garment (a pattern in nanometres, or a unit
// mix-up no sewing pattern has) is refused: its rest lengths would put the cloth under forces
// that fling it (a 1e-8 pattern, or 1e150 before the OBJ reader's range).
constexpr double kPatternScaleLow = 0.5, kPatternScaleHigh = 2;  // a sewing pattern is the garment's size
constexpr double kPatternScaleRefused = 1e3;
void warn_about_cloth_start(const ClothSpec& spec, const Garment& g, const Points& x0, LoadWarnings& warnings) {
  const std::string file = spec.mesh.empty() ? "cloth \"" + spec.name + "\"" : spec.mesh.string();
  const double s = pattern_scale(g);
  if (spec.rest_shape == "pattern" && s > 0 && (s < 1 / kPatternScaleRefused || s > kPatternScaleRefused)) {
    std::ostringstream e;
    e << file << ": the pattern's edges (vt) are a median " << s << " times the mesh's, outside [1e-3, 1e3]: "
      << "with rest_shape \"pattern\" the cloth would rest at that size; give the pattern in the mesh's unit, or "
      << "rest_shape \"mesh\"";
    throw InputError(e.str());
  }
  if (s > 0 && (s < kPatternScaleLow || s > kPatternScaleHigh)) {
    std::ostringstream w;
    w << file << ": the pattern's edges are a median " << s << " times the mesh's (outside [" << kPatternScaleLow
      << ", " << kPatternScaleHigh << "]): its vt may be a texture layout, not a pattern in "
      << "metres; the rest shape is that much " << (s < 1 ? "smaller" : "larger") << " than the garment";
    warnings.add(w.str());
  }
  TriangleSurface start{x0, g.surface.tris, file};
  std::vector<Weld> seams;
  for (const Stitch& st : g.stitches) seams.push_back(stitch_weld(st));
  const certificate::IntersectionCount c = certificate::count_intersections({&start}, {welds_from_seams(seams).welds}, 1);
  if (c.self_total() > 0) {
    std::ostringstream w;
    w << file << ": the cloth starts crossing itself: " << c.self_total()
      << " pairs of triangles intersect (first: triangles " << c.examples[0].triangle_a << " and "
      << c.examples[0].triangle_b << "); the self-collision layer keeps crossings from forming, it does not undo "
      << "them (`invfem check OUT --frames 0-0`)";
    warnings.add(w.str());
  }
}

Garment load_cloth_geometry(const ClothSpec& spec) {
  if (!spec.mesh.empty()) {
    Garment g = load_garment(spec.mesh.string(), GarmentLoadOptions{spec.rest_shape == "pattern"});
    if (!spec.initial_shape.empty()) load_initial_shape(g, spec.initial_shape.string());
    return g;
  }
  if (spec.half_torus) return garment_from_surface(make_half_torus(*spec.half_torus));
  return garment_from_surface(make_grid(spec.grid));
}

}  // namespace

SimObject build_cloth(const ClothSpec& spec, const Scene& scene, LoadWarnings& warnings) {
  const std::string what = "cloth \"" + spec.name + "\"";
  const std::string where = scene.file.string() + ": " + what;
  Garment g;
  try {
    g = load_cloth_geometry(spec);
  } catch (const std::exception& e) {
    throw InputError(what + ": " + e.what());
  }
  for (const auto& [keyword, count] : g.ignored)
    std::cerr << "note: " << spec.mesh.string() << ": " << count << " '" << keyword << "' line" << (count > 1 ? "s" : "")
              << " not used\n";
  apply_transform(spec.transform, g.surface.x, where);
  if (g.initial)
    apply_transform(spec.initial_transform.value_or(spec.transform), *g.initial, where + ": initial shape");
  check_object_size(g.surface.x, spec.transform.scale, where);
  if (g.initial)
    check_object_size(*g.initial, spec.initial_transform.value_or(spec.transform).scale, where + ": initial shape");
  const Points& x0 = g.initial ? *g.initial : g.surface.x;
  warn_about_cloth_start(spec, g, x0, warnings);
  ClothObjectParams params = spec.params;
  if (!spec.stitches_from_mesh) g.stitches.clear();
  for (std::size_t k = 0; k < spec.extra_stitches.size(); ++k) {
    const auto& s = spec.extra_stitches[k];
    const std::vector<int> v = pinned_vertices(VertexSelection{{s.vertices.begin(), s.vertices.end()}, {}, {}}, g, x0,
                                               where + ": stitches.list[" + std::to_string(k) + "]");
    params.extra_stitches.push_back(Stitch{v[0], v[1], v[2], s.r});
  }
  params.gravity = to_vec(scene.gravity);
  if (scene.solver.integrator != Integrator::Implicit) params.strain_limit = 1;  // a barrier: implicit only
  const std::vector<int> pin_vertices = pinned_vertices(VertexSelection{spec.pin_vertices, {}, {}}, g, x0, where + ": pin_vertices");
  try {
    params.mass_spring = make_mass_spring(spec);
    if (!params.mass_spring) params.model = make_isotropic_model(spec.model);
    if (!pin_vertices.empty())
      params.pins.push_back(make_pin_group(x0, pin_vertices, std::nullopt, what + ": pin_vertices"));
    for (auto& pin : pins_in_boxes(x0, spec.pin_boxes, where)) params.pins.push_back(std::move(pin));
    for (std::size_t k = 0; k < spec.pins.size(); ++k) {
      const auto& [selection, script] = spec.pins[k];
      const std::string pin_what = where + ": pins[" + std::to_string(k) + "]";
      std::vector<int> nodes = pinned_vertices(selection, g, x0, pin_what);
      if (nodes.empty()) throw InputError(pin_what + " selects no vertex");
      std::optional<Motion> motion;
      if (script.kind != MotionScript::Kind::Fixed) {
        Vec3 centre = Vec3::Zero();
        for (int i : nodes) centre += x0.row(i).transpose();
        motion = make_motion(script, RigidTransform{}, centre / double(nodes.size()));
      }
      params.pins.push_back(make_pin_group(x0, std::move(nodes), std::move(motion), pin_what));
    }
    SimObject cloth = make_cloth_object(spec.name, g, std::move(params));
    // Attached vertices, embedded in their solid by build_world (the solid is built there). Named
    // by JSON path when the spec is one of the scene's (it always is from build_world).
    const auto index = std::find_if(scene.cloths.begin(), scene.cloths.end(),
                                    [&](const ClothSpec& c) { return &c == &spec; }) - scene.cloths.begin();
    for (std::size_t k = 0; k < spec.attachments.size(); ++k) {
      const auto& [solid, selection] = spec.attachments[k];
      const std::string a_what =
          index < static_cast<std::ptrdiff_t>(scene.cloths.size())
              ? scene.file.string() + ": $.cloths[" + std::to_string(index) + "].attachments[" + std::to_string(k) +
                    "] (" + what + ")"
              : where + ": attachments[" + std::to_string(k) + "]";
      const std::vector<int> nodes = pinned_vertices(selection, g, x0, a_what);
      if (nodes.empty()) throw InputError(a_what + " selects no vertex");
      AttachmentGroup group{solid, {}};
      for (int i : nodes) group.vertices.push_back(Attachment{i});
      cloth.attachments.push_back(std::move(group));
    }
    return cloth;
  } catch (const std::invalid_argument& e) {
    throw InputError(scene.file.string() + ": " + e.what());
  }
}

}  // namespace invfem::app
