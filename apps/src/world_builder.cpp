#include "world_builder.hpp"

#include <algorithm>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "collider_builders.hpp"
#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/collisions/colliders/rigid_collisions.hpp"
#include "invfem/core/world/attachment_embedding.hpp"
#include "invfem/collisions/self_collision/self_collision_pass.hpp"
#include "invfem/solids/fracture_pass.hpp"
#include "json_reader.hpp"
#include "object_builders.hpp"
#include "field_table.hpp"

namespace invfem::app {

namespace {
// An object that starts wholly inside a rigid collider: its deepest node lies deeper inside than
// the object measures across (bounding-box diagonal), so with a convex shape such as the ground
// plane every node is inside. Collision processing would move every node to the collider's
// surface in the first step, flattening the object and jumping it metres or kilometres (a ground
// plane raised 10 km above a sphere did), and the self-collision layer then meets every pair of
// the flattened surface at once, step after step, which ran for hours. A scene error: say so.
void check_not_inside_colliders(const Scene& scene, const std::vector<SimObject>& objects, const Colliders& colliders) {
  for (const auto& rigid : colliders.rigid) {
    for (const SimObject& o : objects) {
      const Points& x = o.body.x;
      if (x.rows() == 0) continue;
      const double size = (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm();
      Eigen::Index deepest = 0;
      double phi_min = std::numeric_limits<double>::infinity();
      for (Eigen::Index i = 0; i < x.rows(); ++i) {
        const double phi = rigid->implicit()->phi(x.row(i).transpose(), 0.0);
        if (phi < phi_min) phi_min = phi, deepest = i;
      }
      if (phi_min < -size)
        throw InputError(scene.file.string() + ": object \"" + o.name + "\" starts inside collider \"" + rigid->name() +
                         "\": its node " + std::to_string(deepest) + " lies " + std::to_string(-phi_min) +
                         " m inside, more than the object measures across (" + std::to_string(size) +
                         " m); move the object or the collider");
    }
  }
}
}  // namespace

namespace {

// The self-collision layer keeps surfaces `thickness` apart: at or above a surface's typical edge
// length it would hold the neighbouring vertices of one surface apart, pushing the mesh off itself
// and pumping energy into it, so a thickness that large is refused.
void check_thickness(const Scene& scene, const World& world) {
  std::set<std::string> excluded;
  for (const auto& o : scene.solids)
    if (!o.self_collision) excluded.insert(o.name);
  for (const auto& c : scene.cloths)
    if (!c.self_collision) excluded.insert(c.name);
  for (const SimObject& o : world.objects()) {
    const Tris& t = o.surface.tris;
    if (t.rows() == 0 || excluded.count(o.name)) continue;
    std::vector<double> lengths;
    lengths.reserve(static_cast<std::size_t>(t.rows()) * 3);
    for (Eigen::Index f = 0; f < t.rows(); ++f)
      for (int k = 0; k < 3; ++k) lengths.push_back((o.surface.x.row(t(f, k)) - o.surface.x.row(t(f, (k + 1) % 3))).norm());
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
    const double median = lengths[lengths.size() / 2];
    if (scene.self_collision.thickness >= median)
      throw InputError(scene.file.string() + ": $.self_collision.thickness: expected a thickness below the median edge " +
                       "length of \"" + o.name + "\" (" + format_number(median) + " m), found " +
                       format_number(scene.self_collision.thickness) +
                       " m: the layer would hold its neighbouring vertices apart");
  }
}

// An object that starts through an animated or mesh body (a garment placed through the
// character): the certificate's count of crossing pairs between its surface and the body's at
// t = 0. Neither the collision processing nor the self-collision layer undoes a crossing that is
// there from the start: a warning with the count (--strict refuses it). Analytic colliders have
// no exact triangles (check_not_inside_colliders judges them).
void warn_about_starts_through_bodies(const Scene& scene, const World& world, LoadWarnings& warnings) {
  for (const auto& k : world.kinematic_bodies()) {
    const TriangleSurface* body = k->surface();
    if (!body || !k->surface_is_shape() || body->tris.rows() == 0) continue;
    for (const SimObject& o : world.objects()) {
      if (o.surface.tris.rows() == 0) continue;
      const certificate::IntersectionCount c = certificate::count_intersections({&o.surface, body}, {}, 1, {0, 0});
      if (c.cross_total() == 0) continue;
      warnings.add(scene.file.string() + ": \"" + o.name + "\" starts through body \"" + k->name() + "\": " +
                   std::to_string(c.cross_total()) + " pairs of their triangles intersect (first: its triangle " +
                   std::to_string(c.examples[0].triangle_a) + " and the body's " +
                   std::to_string(c.examples[0].triangle_b) +
                   "); the collisions keep crossings from forming, they do not undo them: place the object "
                   "outside the body (`invfem check OUT --frames 0-0` lists the pairs)");
    }
  }
}

}  // namespace

World build_world(const Scene& scene, Colliders* typed, LoadWarnings* warnings) {
  LoadWarnings printed_only;
  LoadWarnings& warn = warnings ? *warnings : printed_only;
  std::vector<SimObject> objects;
  std::vector<FracturingSolid> fracturing;
  for (const auto& spec : scene.solids) {
    TetMesh mesh;
    SolidObject solid = build_solid(spec, scene, &mesh, warn);
    objects.push_back(std::move(solid.object));
    if (!spec.fracture) continue;
    FracturingSolid f{spec.name, std::move(mesh), *spec.fracture, solid.tet_force};
    fracturing.push_back(std::move(f));
  }
  for (const auto& spec : scene.cloths) objects.push_back(build_cloth(spec, scene, warn));
  // Attached cloth vertices: embedded in their solid at the start (scene.cpp checked the names).
  for (SimObject& cloth : objects)
    for (AttachmentGroup& group : cloth.attachments) {
      const auto solid = std::find_if(objects.begin(), objects.end(), [&](const SimObject& o) {
        return o.stage == kSolidStage && o.name == group.target;
      });
      if (solid == objects.end())
        throw InputError(scene.file.string() + ": cloth \"" + cloth.name + "\" is attached to \"" + group.target +
                         "\", which is no solid of the scene");
      std::vector<int> nodes;
      for (const Attachment& a : group.vertices) nodes.push_back(a.node);
      group.vertices = embed_attachments(*solid, cloth.body.x, nodes);
    }
  std::vector<SolidCoupling> couplings;
  for (const auto& spec : scene.solids)
    if (spec.cloth_coupling_enabled && !scene.cloths.empty()) {
      couplings.push_back(spec.cloth_coupling);
      couplings.back().solid = spec.name;
    }
  Colliders colliders = build_colliders(scene);
  check_not_inside_colliders(scene, objects, colliders);
  if (typed) typed->rigid = colliders.rigid, typed->sequences = colliders.sequences;
  try {
    World world(scene.solver, std::move(objects), std::move(colliders.bodies),
                std::make_unique<RigidCollisions>(std::move(colliders.collision), std::move(couplings)));
    warn_about_starts_through_bodies(scene, world, warn);
    if (scene.self_collision_enabled) {
      check_thickness(scene, world);
      collisions::SelfCollisionSettings s = scene.self_collision;
      for (const auto& o : scene.solids)
        if (!o.self_collision) s.excluded.push_back(o.name);
      for (const auto& c : scene.cloths)
        if (!c.self_collision) s.excluded.push_back(c.name);
      // The analytic colliders' exact shapes, which the layer keeps its vertices out of.
      std::vector<std::shared_ptr<const ImplicitSurface>> analytic;
      for (const auto& rigid : colliders.rigid)
        if (!rigid->surface_is_shape()) analytic.push_back(rigid->implicit());
      world.add_pass(std::make_unique<collisions::SelfCollisionPass>(s, std::move(analytic)));
    }
    // Fracture runs after the self-collision layer: the layer reads the step's start positions
    // (StepPassInput::x_start), which hold the topology before a cut; the layer rebuilds its mesh
    // at the next step, when the start positions hold the new one.
    if (!fracturing.empty()) world.add_pass(std::make_unique<FracturePass>(std::move(fracturing)));
    return world;
  } catch (const std::invalid_argument& e) {
    throw InputError(scene.file.string() + ": " + e.what());
  }
}

StepPlan plan_steps(const World& world, const Scene& scene) {
  StepPlan p;
  p.dt = world.step_size();
  p.substeps = world.substeps_for(1 / scene.fps);
  p.limit = scene.solver.max_substeps;
  return p;
}

std::string substep_advice(const Scene& scene) {
  std::string a = scene.solver.integrator == Integrator::ITF04
                      ? "the itf04 step is limited by the stiffest, lightest element (young, strength, density, "
                        "poisson near 0.5): solver.integrator \"implicit\" takes steps of max_dt instead"
                      : "solver.max_dt sets the implicit step: raise it";
  return a + "; solver.max_substeps_per_frame (now " + std::to_string(scene.solver.max_substeps) +
         ") is the limit";
}

}  // namespace invfem::app
