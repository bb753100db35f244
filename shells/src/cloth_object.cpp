#include "invfem/shells/cloth_object.hpp"

#include "invfem/core/world/pins.hpp"
#include "invfem/core/math/triangle_kernel.hpp"

namespace invfem {

namespace {

// triangle_normal of every triangle at positions x.
std::vector<Vec3> face_normals(const Points& x, const Tris& tris) {
  std::vector<Vec3> n(static_cast<std::size_t>(tris.rows()));
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    n[t] = triangle_normal(x, tris, t);
  return n;
}

}  // namespace

SimObject make_cloth_object(const std::string& name, const Garment& garment, ClothObjectParams p) {
  const std::string what = "cloth \"" + name + "\"";
  const TriangleSurface& surface = garment.surface;
  const Points& x0 = garment.initial ? *garment.initial : surface.x;
  SimObject o;
  o.name = name;
  o.stage = kClothStage;
  o.auto_preconditioner = Preconditioner::BlockJacobi;  // the multigrid's rigid modes do not help a shell
  TriangleRest rest = garment.pattern.empty() ? make_triangle_rest(surface.x, surface.tris, what)
                                               : make_triangle_rest(garment.pattern, surface.tris, surface.x.rows(), what);
  o.body.x = x0;
  o.body.v = Points(x0.rows(), 3);
  o.body.v.rowwise() = p.velocity.transpose();
  o.body.mass = lumped_triangle_masses(rest, p.density * p.thickness);
  o.body.gravity = p.gravity;
  // In-plane: the membrane (ITF04 section 8), or the mass-spring baseline's edge springs.
  std::unique_ptr<Force> in_plane;
  std::unique_ptr<StrainLimitForce> strain_limit;
  if (!(p.strain_limit >= 1) || !std::isfinite(p.strain_limit))
    throw std::invalid_argument(what + ": strain_limit must be finite and >= 1 (1: none), got " +
                                std::to_string(p.strain_limit));
  if (p.strain_limit > 1) {
    // The barrier's stiffness kappa: the in-plane wave modulus (E / (1 - nu^2) for a linear
    // membrane), so that the stiffness it adds, kappa b'', equals the membrane's an eighth of the
    // way into its width (b'' = 1), is six times it halfway (b'' = 6.4) and grows without bound.
    const double kappa = p.mass_spring ? p.mass_spring->young : wave_modulus(plane_stress(p.model));
    strain_limit = std::make_unique<StrainLimitForce>(rest, StrainLimitParams{p.strain_limit, kappa, p.thickness},
                                                      what + ": strain limit");
  }
  std::vector<double> lengths;  // of the stitches' seams, from the rest data
  std::vector<Stitch> stitches = garment.stitches;
  stitches.insert(stitches.end(), p.extra_stitches.begin(), p.extra_stitches.end());
  if (!stitches.empty()) lengths = seam_lengths(stitches, rest);
  if (p.mass_spring) {
    if (p.inversion != InversionReference::None || p.plasticity)
      throw std::invalid_argument(what + ": mass-spring cloth takes no inversion test and no in-plane plasticity");
    in_plane = std::make_unique<EdgeSpringForce>(triangle_edge_springs(rest, p.mass_spring->young, p.thickness),
                                                 x0.rows(), p.mass_spring->params, what + ": springs");
  } else {
    MembraneParams mp{p.model, p.thickness, p.damping, p.plasticity, {}};
    if (p.inversion == InversionReference::Rest)
      mp.inversion_normals = face_normals(garment.pattern.empty() ? surface.x : x0, surface.tris);
    else if (p.inversion == InversionReference::Direction)
      mp.inversion_normals.assign(static_cast<std::size_t>(surface.tris.rows()), p.inversion_direction);
    in_plane = std::make_unique<MembraneForce>(std::move(rest), mp, what);
  }
  auto bending = std::make_unique<BendingForce>(surface.x, surface.tris, p.bending, what);
  // A pattern is flat: a garment's rest bend angle is 0 along every hinge.
  if (!garment.pattern.empty()) bending->set_rest_angles(std::vector<double>(bending->hinges().size(), 0.0));
  in_plane->update_positions(o.body.x, 0.0);
  bending->update_positions(o.body.x, 0.0);
  std::unique_ptr<StitchForce> stitch;
  StitchForce* seams = nullptr;  // the stitch force, once it is among o.forces
  std::vector<Weld> welds;  // in nodes; in surface vertices once the surface exists
  for (const Stitch& st : stitches) welds.push_back(stitch_weld(st));
  if (!stitches.empty()) {
    stitch = std::make_unique<StitchForce>(std::move(stitches), std::move(lengths), x0.rows(), p.stitch, what, o.body.x);
    stitch->update_positions(o.body.x, 0.0);
  }
  o.forces.push_back(std::move(in_plane));
  o.forces.push_back(std::move(bending));
  if (stitch) {
    seams = stitch.get();
    o.forces.push_back(std::move(stitch));
  }
  if (strain_limit) {
    strain_limit->update_positions(o.body.x, 0.0);
    o.forces.push_back(std::move(strain_limit));
  }
  o.pins = std::move(p.pins);
  set_pinned_velocities(o, 0.0);
  o.surface = extract_surface(o.body.x, surface.tris, o.surface_nodes);
  o.surface.source = surface.source;
  // The source's texture coordinates and panels go to every output frame (same triangle order).
  o.surface.uv = surface.uv;
  o.surface.uv_tris = surface.uv_tris;
  o.surface.groups = surface.groups;
  o.surface.triangle_group = surface.triangle_group;
  std::vector<int> vertex_of(static_cast<std::size_t>(o.body.x.rows()), -1);
  for (std::size_t s = 0; s < o.surface_nodes.size(); ++s) vertex_of[static_cast<std::size_t>(o.surface_nodes[s])] = static_cast<int>(s);
  auto surface_vertex = [&](int node) { return node < 0 ? -1 : vertex_of[static_cast<std::size_t>(node)]; };
  std::vector<Weld> surface_welds;
  for (const Weld& w : welds) {  // a stitch on a vertex no triangle uses joins nothing
    const Weld s{surface_vertex(w.i), surface_vertex(w.j), surface_vertex(w.k), w.r};
    if (s.i >= 0 && s.j >= 0 && (w.k < 0 || s.k >= 0)) surface_welds.push_back(s);
  }
  if (seams) seams->set_seams(std::move(surface_welds));
  return o;
}

SimObject make_cloth_object(const std::string& name, const TriangleSurface& surface, ClothObjectParams params) {
  Garment g;
  g.surface = surface;
  return make_cloth_object(name, g, std::move(params));
}

}  // namespace invfem
