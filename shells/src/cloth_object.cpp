#include "invfem/shells/cloth_object.hpp"

#include "invfem/core/pins.hpp"
#include "invfem/core/triangle_kernel.hpp"

namespace invfem {

SimObject make_cloth_object(const std::string& name, const TriangleSurface& surface, ClothObjectParams p) {
  const std::string what = "cloth \"" + name + "\"";
  SimObject o;
  o.name = name;
  o.kind = ObjectKind::Cloth;
  auto membrane =
      std::make_unique<MembraneForce>(surface.x, surface.tris, MembraneParams{p.model, p.thickness, p.damping}, what);
  o.body.x = surface.x;
  o.body.v = Points(surface.x.rows(), 3);
  o.body.v.rowwise() = p.velocity.transpose();
  o.body.mass = lumped_triangle_masses(membrane->rest(), p.density * p.thickness);
  o.body.gravity = p.gravity;
  auto bending = std::make_unique<BendingForce>(surface.x, surface.tris, p.bending, what);
  membrane->update_positions(o.body.x, 0.0);
  bending->update_positions(o.body.x, 0.0);
  o.forces.push_back(std::move(membrane));
  o.forces.push_back(std::move(bending));
  o.pins = std::move(p.pins);
  set_pinned_velocities(o, 0.0);
  o.surface = extract_surface(surface.x, surface.tris, o.surface_nodes);
  o.surface.source = surface.source;
  return o;
}

}  // namespace invfem
