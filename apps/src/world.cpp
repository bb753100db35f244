#include "world.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iostream>

#include "invfem/solids/mass.hpp"
#include "invfem/solids/mesh_error.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_mesh_io.hpp"
#include "json_fields.hpp"
#include "material_factory.hpp"

namespace invfem::app {

namespace {

Vec3 to_vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

void apply_transform(const Transform& t, Points& X) {
  constexpr double kDeg = 3.14159265358979323846 / 180;
  const Mat3 R = (Eigen::AngleAxisd(t.rotate_degrees[2] * kDeg, Vec3::UnitZ()) *
                  Eigen::AngleAxisd(t.rotate_degrees[1] * kDeg, Vec3::UnitY()) *
                  Eigen::AngleAxisd(t.rotate_degrees[0] * kDeg, Vec3::UnitX()))
                     .toRotationMatrix();
  const Vec3 shift = to_vec(t.translate);
  for (Eigen::Index i = 0; i < X.rows(); ++i) X.row(i) = (t.scale * R * X.row(i).transpose() + shift).transpose();
}

SolidObject make_solid(const SolidSpec& spec, const Scene& scene) {
  SolidObject o;
  o.name = spec.name;
  try {
    o.rest = read_tet_mesh(spec.mesh.string());
    apply_transform(spec.transform, o.rest.X);
    const TetMeshReport report = validate_and_orient(o.rest);
    for (const auto& w : report.warnings) std::cerr << "warning: " << spec.mesh.string() << ": " << w << "\n";
    if (!report.unused_nodes.empty())
      throw MeshError(spec.mesh.string() + ": " + std::to_string(report.unused_nodes.size()) +
                      " nodes belong to no tetrahedron (first: node " + std::to_string(report.unused_nodes[0]) +
                      "); they would have no mass");
  } catch (const MeshError& e) {
    throw InputError(std::string("solid \"") + spec.name + "\": " + e.what());
  }
  const int n = static_cast<int>(o.rest.X.rows());
  o.surface = compact_surface(boundary_triangles(o.rest.tets), n);
  o.body.x = o.rest.X;
  o.body.v = Points(n, 3);
  o.body.v.rowwise() = to_vec(spec.velocity).transpose();
  o.body.mass = lumped_masses(o.rest.X, o.rest.tets, spec.material.density);
  o.body.gravity = to_vec(scene.gravity);
  TetMaterial material;
  try {
    material = make_tet_material(spec.material, scene.solver.cfl);
  } catch (const std::invalid_argument& e) {
    throw InputError(scene.file.string() + ": solid \"" + spec.name + "\": " + e.what());
  }
  o.force = std::make_unique<TetSolidForce>(make_tet_rest(o.rest.X, o.rest.tets), std::move(material));
  o.force->update_positions(o.body.x, 0.0);
  return o;
}

}  // namespace

World::World(const Scene& scene) : scene_(scene) {
  for (const auto& spec : scene.solids) solids_.push_back(make_solid(spec, scene));
  std::vector<RigidCollider> colliders;
  for (const auto& c : scene.colliders)
    colliders.push_back({std::make_shared<PlaneSurface>(to_vec(c.point), to_vec(c.normal)), c.friction});
  collisions_ = std::make_unique<RigidCollisions>(std::move(colliders));
}

void World::advance_to(double t_end, FrameReport& report) {
  const CGSettings cg{scene_.solver.cg_tolerance, scene_.solver.cg_max_iterations};
  // Land exactly on t_end: the last substep is shortened (ITF04's scheme takes variable dt).
  while (time_ < t_end - 1e-12 * std::max(1.0, t_end)) {
    double dt = std::min(scene_.solver.max_dt, t_end - time_);
    for (const auto& o : solids_) dt = std::min(dt, o.force->stable_time_step(o.body.mass));
    // Avoid a sliver step at the end of the frame: split what is left evenly.
    const double left = t_end - time_;
    dt = left / std::ceil(left / dt - 1e-9);
    for (auto& o : solids_) {
      const std::vector<Force*> forces{o.force.get()};
      const StepStats s = newmark_step(o.body, forces, collisions_.get(), {}, time_, dt, cg);
      report.cg_iterations += s.half_step.iterations + s.trapezoid.iterations;
      report.cg_all_converged = report.cg_all_converged && s.half_step.converged && s.trapezoid.converged;
      report.colliding_nodes = s.colliding_nodes;
    }
    time_ += dt;
    ++report.substeps;
  }
  time_ = t_end;
}

void World::measure(FrameReport& r) const {
  for (const auto& o : solids_) {
    const Body& b = o.body;
    r.kinetic += 0.5 * (b.mass.asDiagonal() * b.v).cwiseProduct(b.v).sum();
    r.gravity -= ((b.mass.transpose() * b.x) * b.gravity).value();
    r.elastic += o.force->elastic_energy();
    r.inverted += o.force->inverted_count();
    r.elements += static_cast<int>(o.rest.tets.rows());
    r.min_det_F = std::min(r.min_det_F, o.force->min_det_F());
    const auto& rest = o.force->rest();
    for (std::size_t e = 0; e < rest.volume.size(); ++e) {
      r.volume += rest.volume[e] * o.force->det_F()[e];
      r.rest_volume += rest.volume[e];
    }
  }
}

}  // namespace invfem::app
