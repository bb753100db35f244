#include "collider_builders.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "invfem/collisions/colliders/analytic_surfaces.hpp"
#include "invfem/collisions/colliders/body_sequence.hpp"
#include "invfem/collisions/colliders/gear.hpp"
#include "invfem/collisions/colliders/mesh_surface.hpp"
#include "invfem/collisions/colliders/moving_surface.hpp"
#include "invfem/collisions/colliders/skinned_body.hpp"
#include "invfem/core/io/skinned_file.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "json_reader.hpp"
#include "object_builders.hpp"

namespace invfem::app {

namespace {

Vec3 to_vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// The collider's pose at rest; its spin turns about its translate point.
Motion collider_motion(const ColliderSpec& c) {
  RigidTransform pose;
  pose.rotation = rotation_of(c.transform);
  pose.translation = to_vec(c.transform.translate);
  return make_motion(c.motion, pose, pose.translation);
}

}  // namespace

std::vector<std::string> collider_body_names(const ColliderSpec& c) {
  if (c.type == "plane") return {};
  if (c.type == "gears") return {c.name + "_1", c.name + "_2"};
  return {c.name};
}

Colliders build_colliders(const Scene& scene) {
  Colliders colliders;
  std::vector<std::shared_ptr<RigidBody>> out;  // this collider's rigid bodies
  for (const auto& c : scene.colliders) {
    const std::string what = scene.file.string() + ": collider \"" + c.name + "\": ";
    out.clear();
    try {
      if (c.type == "sequence") {
        BodySequenceSettings s = c.sequence;
        s.linear = c.transform.scale * rotation_of(c.transform);
        s.translation = to_vec(c.transform.translate);
        s.friction = c.friction;
        s.mesh = c.contact;
        auto body = std::make_shared<BodySequence>(c.name, std::move(s));
        colliders.collision.push_back({body->implicit(), body->friction()});
        colliders.sequences.push_back(body);
        colliders.bodies.push_back(std::move(body));
      } else if (c.type == "skinned") {
        SkinnedCharacter character = read_skinned_character(c.character.string());
        SkinnedBodySettings s = c.skinned;
        s.clip = find_clip(character, c.clip);
        s.linear = c.transform.scale * rotation_of(c.transform);
        s.translation = to_vec(c.transform.translate);
        s.friction = c.friction;
        s.mesh = c.contact;
        auto body = std::make_shared<SkinnedBody>(c.name, std::move(character), std::move(s));
        colliders.collision.push_back({body->implicit(), body->friction()});
        colliders.bodies.push_back(std::move(body));
      } else if (c.type == "plane") {
        out.push_back(std::make_shared<RigidBody>(c.name, std::make_shared<PlaneSurface>(to_vec(c.point), to_vec(c.normal)),
                                                  c.friction, TriangleSurface{}, Motion{}));
      } else if (c.type == "gears") {
        if (c.motion.kind == MotionScript::Kind::Keyframed ||
            (c.motion.kind == MotionScript::Kind::ConstantVelocity && c.motion.velocity.norm() > 0))
          throw InputError(what + "gears turn in place: give motion.spin_rate only");
        GearPairParams p = c.gears;
        p.center = to_vec(c.transform.translate);
        p.orientation = rotation_of(c.transform);
        p.spin_rate = c.motion.spin_rate;
        const GearPair pair = make_gear_pair(p);
        int k = 1;
        for (const auto& [g, shape] : {std::pair{pair.first, pair.first_shape}, std::pair{pair.second, pair.second_shape}})
          out.push_back(std::make_shared<RigidBody>(c.name + "_" + std::to_string(k++), g, c.friction,
                                                    gear_triangles(*shape), g->motion()));
      } else if (c.type == "mesh") {
        if (c.motion.kind != MotionScript::Kind::Fixed) throw InputError(what + "a mesh collider is static (no motion yet)");
        TriangleSurface mesh = load_triangle_surface(c.mesh.string());
        apply_transform(c.transform, mesh.x, what.substr(0, what.size() - 2));
        auto surface = std::make_shared<MeshSurface>(mesh, c.contact);
        out.push_back(std::make_shared<RigidBody>(c.name, surface, c.friction, std::move(mesh), Motion{}, true));
      } else {
        std::shared_ptr<const ImplicitSurface> shape;
        TriangleSurface mesh;
        if (c.type == "sphere") {
          shape = std::make_shared<SphereSurface>(Vec3::Zero(), c.radius);
          mesh = sphere_triangles(c.radius);
        } else if (c.type == "box") {
          shape = std::make_shared<BoxSurface>(to_vec(c.half_extents));
          mesh = box_triangles(to_vec(c.half_extents));
        } else {  // cylinder, axis y
          shape = std::make_shared<CappedCylinderSurface>(c.radius, c.half_height);
          mesh = cylinder_triangles(c.radius, c.half_height);
        }
        Motion motion = collider_motion(c);
        out.push_back(std::make_shared<RigidBody>(c.name, std::make_shared<MovingSurface>(shape, motion), c.friction,
                                                  std::move(mesh), motion));
      }
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError(what + e.what());
    }
    for (auto& b : out) {
      colliders.collision.push_back({b->implicit(), b->friction()});
      colliders.rigid.push_back(b);
      colliders.bodies.push_back(std::move(b));
    }
  }
  return colliders;
}

}  // namespace invfem::app
