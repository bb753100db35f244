#include "invfem/solids/solid_object.hpp"

#include <stdexcept>
#include <string>

#include "invfem/core/world/pins.hpp"
#include "invfem/solids/boundary.hpp"
#include "invfem/solids/mass.hpp"

namespace invfem {

SimObject make_solid_object(const std::string& name, const TetMesh& mesh, SolidObjectParams params) {
  return make_solid(name, mesh, std::move(params)).object;
}

SolidObject make_solid(const std::string& name, const TetMesh& mesh, SolidObjectParams params) {
  SolidObject out;
  SimObject& o = out.object;
  o.name = name;
  o.stage = kSolidStage;
  o.surface = extract_surface(mesh.X, boundary_triangles(mesh.tets), o.surface_nodes);
  o.surface.source = "boundary of " + mesh.source;
  o.tets = mesh.tets;
  o.body.x = mesh.X;
  if (params.initial_positions) {
    const Points& x0 = *params.initial_positions;
    if (x0.rows() != mesh.X.rows() || x0.cols() != 3)
      throw std::invalid_argument("initial positions: " + std::to_string(x0.rows()) + " x " +
                                  std::to_string(x0.cols()) + " for a mesh of " + std::to_string(mesh.X.rows()) +
                                  " nodes");
    if (!x0.allFinite()) throw std::invalid_argument("initial positions: not all finite");
    o.body.x = x0;
    o.refresh_surface();
  }
  o.body.v = Points(mesh.X.rows(), 3);
  o.body.v.rowwise() = params.velocity.transpose();
  o.body.mass = lumped_masses(mesh.X, mesh.tets, params.material.density);
  o.body.gravity = params.gravity;
  std::unique_ptr<Force> force;
  if (params.mass_spring) {
    TetRest rest = make_tet_rest(mesh.X, mesh.tets);
    EdgeSprings springs = tet_edge_springs(rest, params.mass_spring->young);
    force = std::make_unique<EdgeSpringForce>(std::move(springs), mesh.X.rows(), params.mass_spring->params,
                                              "solid \"" + name + "\": springs", std::move(rest));
  } else {
    auto tet = std::make_unique<TetSolidForce>(make_tet_rest(mesh.X, mesh.tets), std::move(params.material));
    out.tet_force = tet.get();
    force = std::move(tet);
  }
  force->update_positions(o.body.x, 0.0);
  o.forces.push_back(std::move(force));
  o.pins = std::move(params.pins);
  set_pinned_velocities(o, 0.0);
  return out;
}

}  // namespace invfem
