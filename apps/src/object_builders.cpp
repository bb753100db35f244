#include "object_builders.hpp"

#include <Eigen/Geometry>
#include <iostream>
#include <optional>

#include "invfem/core/materials/lame.hpp"
#include "invfem/core/mesh_error.hpp"
#include "invfem/core/pins.hpp"
#include "invfem/core/plasticity_control.hpp"
#include "invfem/core/surface_io.hpp"
#include "invfem/shells/cloth_object.hpp"
#include "invfem/shells/shapes.hpp"
#include "invfem/solids/bcc_mesher.hpp"
#include "invfem/solids/solid_object.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_mesh_io.hpp"
#include "json_fields.hpp"
#include "material_factory.hpp"

namespace invfem::app {

namespace {
Vec3 to_vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// One pin group per box: every node whose rest position lies in it, held still.
std::vector<PinGroup> pins_in_boxes(const Points& X, const std::vector<PinBox>& boxes, const std::string& what) {
  std::vector<PinGroup> pins;
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    std::vector<int> nodes = nodes_in_box(X, to_vec(boxes[b].min), to_vec(boxes[b].max));
    if (nodes.empty()) throw InputError(what + ": pin_boxes[" + std::to_string(b) + "] contains no node");
    pins.push_back(make_pin_group(X, std::move(nodes), std::nullopt, what));
  }
  return pins;
}

bool is_tet_mesh_file(const std::filesystem::path& p) {
  const std::string e = p.extension().string();
  return e == ".vtk" || e == ".mesh" || e == ".msh";
}

}  // namespace

Mat3 rotation_of(const Transform& t) {
  constexpr double kDeg = 3.14159265358979323846 / 180;
  return (Eigen::AngleAxisd(t.rotate_degrees[2] * kDeg, Vec3::UnitZ()) *
          Eigen::AngleAxisd(t.rotate_degrees[1] * kDeg, Vec3::UnitY()) *
          Eigen::AngleAxisd(t.rotate_degrees[0] * kDeg, Vec3::UnitX()))
      .toRotationMatrix();
}

void apply_transform(const Transform& t, Points& X) {
  const Mat3 R = rotation_of(t);
  const Vec3 shift = to_vec(t.translate);
  for (Eigen::Index i = 0; i < X.rows(); ++i) X.row(i) = (t.scale * R * X.row(i).transpose() + shift).transpose();
}

SimObject build_solid(const SolidSpec& spec, const Scene& scene) {
  TetMesh mesh;
  try {
    if (is_tet_mesh_file(spec.mesh)) {
      mesh = read_tet_mesh(spec.mesh.string());
      apply_transform(spec.transform, mesh.X);
    } else {
      // A closed surface: tet-mesh it by the BCC lattice (after the transform, so the
      // resolution is in world units of the object's own size).
      TriangleSurface surface = load_triangle_surface(spec.mesh.string());
      apply_transform(spec.transform, surface.x);
      BccMeshOptions options;
      options.resolution = spec.mesh_resolution;
      BccMeshResult r = bcc_mesh(surface, options);
      mesh = std::move(r.mesh);
      std::cerr << "meshed " << spec.mesh.filename().string() << ": " << r.report.tets << " tets, volume ratio "
                << r.report.volume_ratio << ", dihedral angles " << r.report.min_dihedral_deg << "-"
                << r.report.max_dihedral_deg << " degrees\n";
    }
    const TetMeshReport report = validate_and_orient(mesh);
    for (const auto& w : report.warnings) std::cerr << "warning: " << spec.mesh.string() << ": " << w << "\n";
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
  params.pins = pins_in_boxes(mesh.X, spec.pin_boxes, what);
  try {
    TetMaterial material = make_tet_material(spec.material, scene.solver.cfl);
    if (spec.plasticity) {
      PlasticParams p;
      p.yield = spec.plasticity->yield;
      p.deviatoric_only = spec.plasticity->deviatoric_only;
      p.preserve_volume = spec.plasticity->preserve_volume;
      p.max_stretch = spec.plasticity->max_stretch;
      material.plasticity = p;
    }
    if (spec.plastic_goal) {
      const Points goal = axis_scaled_goal(mesh.X, to_vec(spec.plastic_goal->center), to_vec(spec.plastic_goal->scale));
      material.plastic_goal_log = make_plastic_goal(mesh.X, mesh.tets, goal).log_Fp_goal;
    }
    if (spec.fiber) {
      material.fiber = FiberMaterial{spec.fiber->k_passive, spec.fiber->k_active, spec.fiber->max_contraction};
      // Material space is the transformed rest mesh, so a direction in world axes at rest is
      // already a material direction.
      material.fiber_directions.assign(mesh.tets.rows(), to_vec(spec.fiber->direction).normalized());
      material.activation = spec.fiber->activation;
    }
    params.material = std::move(material);
    return make_solid_object(spec.name, mesh, std::move(params));
  } catch (const std::invalid_argument& e) {
    throw InputError(what + ": " + e.what());
  }
}

SimObject build_cloth(const ClothSpec& spec, const Scene& scene) {
  const std::string what = "cloth \"" + spec.name + "\"";
  TriangleSurface mesh;
  try {
    // A grid lies in the x-z plane (y up), centred on the origin, before the transform.
    mesh = spec.mesh.empty()
               ? make_grid(spec.grid.width, spec.grid.height, spec.grid.nx, spec.grid.ny,
                           Vec3(-spec.grid.width / 2, 0, -spec.grid.height / 2), Vec3::UnitX(), Vec3::UnitZ())
               : load_triangle_surface(spec.mesh.string());
  } catch (const std::exception& e) {
    throw InputError(what + ": " + e.what());
  }
  apply_transform(spec.transform, mesh.x);
  const int n = static_cast<int>(mesh.x.rows());
  const auto& m = spec.material;
  ClothObjectParams params;
  params.thickness = m.thickness;
  params.density = m.density;
  params.damping = m.damping;
  params.bending = BendingParams{m.bending_stiffness, m.bending_damping};
  params.velocity = to_vec(spec.velocity);
  params.gravity = to_vec(scene.gravity);
  for (int i : spec.pin_vertices)
    if (i >= n)
      throw InputError(scene.file.string() + ": " + what + ": pin_vertices has vertex " + std::to_string(i) +
                       " but the mesh has " + std::to_string(n) + " vertices");
  try {
    const Lame lame = lame_from_young_poisson(m.young, m.poisson, what);
    params.model = RotatedLinear{lame.mu, lame.lambda};
    if (!spec.pin_vertices.empty())
      params.pins.push_back(make_pin_group(mesh.x, spec.pin_vertices, std::nullopt, what + ": pin_vertices"));
    for (auto& g : pins_in_boxes(mesh.x, spec.pin_boxes, scene.file.string() + ": " + what))
      params.pins.push_back(std::move(g));
    return make_cloth_object(spec.name, mesh, std::move(params));
  } catch (const std::invalid_argument& e) {
    throw InputError(scene.file.string() + ": " + e.what());
  }
}

}  // namespace invfem::app
