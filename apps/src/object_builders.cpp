#include "object_builders.hpp"

#include <Eigen/Geometry>
#include <iostream>

#include "invfem/core/materials/lame.hpp"
#include "invfem/shells/bending_force.hpp"
#include "invfem/shells/membrane_force.hpp"
#include "invfem/shells/triangle_mesh.hpp"
#include "invfem/solids/mass.hpp"
#include "invfem/solids/mesh_error.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_mesh_io.hpp"
#include "json_fields.hpp"
#include "material_factory.hpp"

namespace invfem::app {

namespace {
Vec3 to_vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

Body make_body(const Points& X, Eigen::VectorXd mass, const std::array<double, 3>& velocity, const Scene& scene) {
  Body b;
  b.x = X;
  b.v = Points(X.rows(), 3);
  b.v.rowwise() = to_vec(velocity).transpose();
  b.mass = std::move(mass);
  b.gravity = to_vec(scene.gravity);
  return b;
}
}  // namespace

void apply_transform(const Transform& t, Points& X) {
  constexpr double kDeg = 3.14159265358979323846 / 180;
  const Mat3 R = (Eigen::AngleAxisd(t.rotate_degrees[2] * kDeg, Vec3::UnitZ()) *
                  Eigen::AngleAxisd(t.rotate_degrees[1] * kDeg, Vec3::UnitY()) *
                  Eigen::AngleAxisd(t.rotate_degrees[0] * kDeg, Vec3::UnitX()))
                     .toRotationMatrix();
  const Vec3 shift = to_vec(t.translate);
  for (Eigen::Index i = 0; i < X.rows(); ++i) X.row(i) = (t.scale * R * X.row(i).transpose() + shift).transpose();
}

SimObject build_solid(const SolidSpec& spec, const Scene& scene) {
  SimObject o;
  o.name = spec.name;
  o.kind = SimObject::Kind::Solid;
  TetMesh mesh;
  try {
    mesh = read_tet_mesh(spec.mesh.string());
    apply_transform(spec.transform, mesh.X);
    const TetMeshReport report = validate_and_orient(mesh);
    for (const auto& w : report.warnings) std::cerr << "warning: " << spec.mesh.string() << ": " << w << "\n";
    if (!report.unused_nodes.empty())
      throw MeshError(spec.mesh.string() + ": " + std::to_string(report.unused_nodes.size()) +
                      " nodes belong to no tetrahedron (first: node " + std::to_string(report.unused_nodes[0]) +
                      "); they would have no mass");
  } catch (const MeshError& e) {
    throw InputError(std::string("solid \"") + spec.name + "\": " + e.what());
  }
  const int n = static_cast<int>(mesh.X.rows());
  o.surface = compact_surface(boundary_triangles(mesh.tets), n);
  o.tets = mesh.tets;
  o.body = make_body(mesh.X, lumped_masses(mesh.X, mesh.tets, spec.material.density), spec.velocity, scene);
  TetMaterial material;
  try {
    material = make_tet_material(spec.material, scene.solver.cfl);
  } catch (const std::invalid_argument& e) {
    throw InputError(scene.file.string() + ": solid \"" + spec.name + "\": " + e.what());
  }
  auto force = std::make_unique<TetSolidForce>(make_tet_rest(mesh.X, mesh.tets), std::move(material));
  force->update_positions(o.body.x, 0.0);
  o.solid = force.get();
  o.forces.push_back(std::move(force));
  return o;
}

SimObject build_cloth(const ClothSpec& spec, const Scene& scene) {
  SimObject o;
  o.name = spec.name;
  o.kind = SimObject::Kind::Cloth;
  const std::string what = "cloth \"" + spec.name + "\"";
  TriangleMesh mesh;
  try {
    // A grid lies in the x-z plane (y up), centred on the origin, before the transform.
    mesh = spec.mesh.empty()
               ? make_grid(spec.grid.width, spec.grid.height, spec.grid.nx, spec.grid.ny,
                           Vec3(-spec.grid.width / 2, 0, -spec.grid.height / 2), Vec3::UnitX(), Vec3::UnitZ())
               : load_triangle_mesh(spec.mesh.string());
  } catch (const std::exception& e) {
    throw InputError(what + ": " + e.what());
  }
  apply_transform(spec.transform, mesh.X);
  const int n = static_cast<int>(mesh.X.rows());
  const auto& m = spec.material;
  Lame lame;
  try {
    lame = lame_from_young_poisson(m.young, m.poisson, what);
    auto membrane = std::make_unique<MembraneForce>(
        mesh.X, mesh.tris, MembraneParams{RotatedLinear{lame.mu, lame.lambda}, m.thickness, m.damping}, what);
    o.body = make_body(mesh.X, lumped_triangle_masses(membrane->rest(), m.density * m.thickness), spec.velocity,
                       scene);
    auto bending = std::make_unique<BendingForce>(mesh.X, mesh.tris,
                                                  BendingParams{m.bending_stiffness, m.bending_damping}, what);
    membrane->update_positions(o.body.x, 0.0);
    bending->update_positions(o.body.x, 0.0);
    o.forces.push_back(std::move(membrane));
    o.forces.push_back(std::move(bending));
  } catch (const std::invalid_argument& e) {
    throw InputError(scene.file.string() + ": " + e.what());
  }
  for (int i : spec.pin_vertices) {
    if (i >= n)
      throw InputError(scene.file.string() + ": " + what + ": pin_vertices has vertex " + std::to_string(i) +
                       " but the mesh has " + std::to_string(n) + " vertices");
    o.pinned.push_back({i, NodeConstraint::Kind::Full, Vec3::Zero(), Vec3::Zero()});
  }
  if (spec.has_pin_box) {
    const Vec3 lo = to_vec(spec.pin_box_min), hi = to_vec(spec.pin_box_max);
    int count = 0;
    for (int i = 0; i < n; ++i) {
      const Vec3 x = mesh.X.row(i).transpose();
      if ((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all()) {
        o.pinned.push_back({i, NodeConstraint::Kind::Full, Vec3::Zero(), Vec3::Zero()});
        ++count;
      }
    }
    if (count == 0) throw InputError(scene.file.string() + ": " + what + ": pin_box contains no vertex of the cloth");
  }
  for (const auto& p : o.pinned) o.body.v.row(p.node).setZero();
  o.surface = compact_surface(mesh.tris, n);
  return o;
}

std::vector<RigidCollider> build_colliders(const Scene& scene) {
  std::vector<RigidCollider> colliders;
  for (const auto& c : scene.colliders)
    colliders.push_back({std::make_shared<PlaneSurface>(to_vec(c.point), to_vec(c.normal)), c.friction});
  return colliders;
}

}  // namespace invfem::app
