#include "collider_builders.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "invfem/collisions/analytic_surfaces.hpp"
#include "invfem/collisions/gear.hpp"
#include "invfem/collisions/mesh_surface.hpp"
#include "invfem/collisions/moving_surface.hpp"
#include "invfem/shells/triangle_mesh.hpp"
#include "json_fields.hpp"
#include "object_builders.hpp"

namespace invfem::app {

namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 to_vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

Motion make_motion(const ColliderSpec& c) {
  RigidTransform pose;
  pose.rotation = rotation_of(c.transform);
  pose.translation = to_vec(c.transform.translate);
  const MotionSpec& m = c.motion;
  switch (m.kind) {
    case MotionSpec::Kind::Fixed:
      return Motion::fixed(pose);
    case MotionSpec::Kind::ConstantVelocity:
      return Motion::constant_velocity(pose, pose.translation, to_vec(m.velocity), to_vec(m.spin_axis).normalized(),
                                       m.spin_rate);
    case MotionSpec::Kind::Keyframed: {
      std::vector<TranslationKey> tk;
      for (const auto& [t, p] : m.translate_keys) tk.push_back({t, to_vec(p)});
      std::vector<RotationKey> rk;
      for (const auto& k : m.rotate_keys) rk.push_back({k.t, to_vec(k.axis).normalized(), k.degrees});
      return Motion::keyframed(tk, rk);
    }
  }
  return Motion::fixed(pose);
}

// Closed triangle meshes of the analytic shapes in their body frames, outward winding.
void add_quad(std::vector<Eigen::Vector3i>& t, int a, int b, int c, int d) {
  t.emplace_back(a, b, c);
  t.emplace_back(a, c, d);
}

TriangleMesh to_mesh(const std::vector<Vec3>& v, const std::vector<Eigen::Vector3i>& t) {
  TriangleMesh m;
  m.X.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.X.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  m.tris.resize(static_cast<Eigen::Index>(t.size()), 3);
  for (std::size_t i = 0; i < t.size(); ++i) m.tris.row(static_cast<Eigen::Index>(i)) = t[i].transpose();
  return m;
}

TriangleMesh sphere_mesh(double r) {
  const int nu = 32, nv = 16;
  std::vector<Vec3> v{Vec3(0, r, 0)};
  for (int j = 1; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double th = kPi * j / nv, ph = 2 * kPi * i / nu;
      v.emplace_back(r * std::sin(th) * std::cos(ph), r * std::cos(th), -r * std::sin(th) * std::sin(ph));
    }
  v.emplace_back(0, -r, 0);
  std::vector<Eigen::Vector3i> t;
  const int south = static_cast<int>(v.size()) - 1;
  auto id = [&](int j, int i) { return 1 + (j - 1) * nu + (i % nu); };
  for (int i = 0; i < nu; ++i) t.emplace_back(0, id(1, i), id(1, i + 1));
  for (int j = 1; j < nv - 1; ++j)
    for (int i = 0; i < nu; ++i) add_quad(t, id(j, i), id(j + 1, i), id(j + 1, i + 1), id(j, i + 1));
  for (int i = 0; i < nu; ++i) t.emplace_back(south, id(nv - 1, i + 1), id(nv - 1, i));
  return to_mesh(v, t);
}

// A prism over a star-shaped closed polygon (counter-clockwise about `axis`), from -h to +h
// along the axis; `up` maps (x, y, h) in the profile plane to the body frame.
TriangleMesh prism_mesh(const std::vector<Vec2>& profile, double h, bool axis_is_y) {
  auto point = [&](const Vec2& p, double z) { return axis_is_y ? Vec3(p.x(), z, -p.y()) : Vec3(p.x(), p.y(), z); };
  const int n = static_cast<int>(profile.size());
  std::vector<Vec3> v{point(Vec2::Zero(), -h), point(Vec2::Zero(), h)};
  for (const auto& p : profile) v.push_back(point(p, -h));
  for (const auto& p : profile) v.push_back(point(p, h));
  std::vector<Eigen::Vector3i> t;
  for (int i = 0; i < n; ++i) {
    const int a = 2 + i, b = 2 + (i + 1) % n, A = a + n, B = b + n;
    t.emplace_back(0, b, a);   // bottom cap faces -axis
    t.emplace_back(1, A, B);   // top cap faces +axis
    add_quad(t, a, b, B, A);   // side
  }
  return to_mesh(v, t);
}

TriangleMesh box_mesh(const Vec3& e) {
  std::vector<Vec3> v;
  for (int k = 0; k < 8; ++k) v.emplace_back((k & 1 ? 1 : -1) * e.x(), (k & 2 ? 1 : -1) * e.y(), (k & 4 ? 1 : -1) * e.z());
  std::vector<Eigen::Vector3i> t;
  add_quad(t, 0, 4, 6, 2);  // -x
  add_quad(t, 1, 3, 7, 5);  // +x
  add_quad(t, 0, 1, 5, 4);  // -y
  add_quad(t, 2, 6, 7, 3);  // +y
  add_quad(t, 0, 2, 3, 1);  // -z
  add_quad(t, 4, 5, 7, 6);  // +z
  return to_mesh(v, t);
}

ColliderBody body(const std::string& name, std::shared_ptr<const ImplicitSurface> s, double friction,
                  const TriangleMesh& mesh, Motion motion) {
  return ColliderBody{name, std::move(s), friction, mesh.X, mesh.tris, std::move(motion)};
}

}  // namespace

Points ColliderBody::world_vertices(double t) const {
  const RigidTransform T = motion.body_to_world(t);
  Points out(body_vertices.rows(), 3);
  for (Eigen::Index i = 0; i < body_vertices.rows(); ++i)
    out.row(i) = T.apply(body_vertices.row(i).transpose()).transpose();
  return out;
}

std::vector<std::string> collider_body_names(const ColliderSpec& c) {
  if (c.type == "plane") return {};
  if (c.type == "gears") return {c.name + "_1", c.name + "_2"};
  return {c.name};
}

std::vector<ColliderBody> build_colliders(const Scene& scene) {
  std::vector<ColliderBody> out;
  for (const auto& c : scene.colliders) {
    const std::string what = scene.file.string() + ": collider \"" + c.name + "\": ";
    try {
      if (c.type == "plane") {
        out.push_back({c.name, std::make_shared<PlaneSurface>(to_vec(c.point), to_vec(c.normal)), c.friction, {}, {},
                       Motion{}});
      } else if (c.type == "gears") {
        if (c.motion.kind == MotionSpec::Kind::Keyframed ||
            (c.motion.kind == MotionSpec::Kind::ConstantVelocity && to_vec(c.motion.velocity).norm() > 0))
          throw InputError(what + "gears turn in place: give motion.spin_rate only");
        GearPairParams p;
        p.gear.teeth = c.teeth;
        p.gear.outer_radius = c.outer_radius;
        p.gear.root_radius = c.root_radius;
        p.gear.thickness = c.thickness;
        p.center = to_vec(c.transform.translate);
        p.orientation = rotation_of(c.transform);
        p.spin_rate = c.motion.spin_rate;
        p.clearance = c.clearance;
        const GearPair pair = make_gear_pair(p);
        int k = 1;
        for (const auto& g : {pair.first, pair.second}) {
          const auto& gear = dynamic_cast<const GearSurface&>(g->body());
          std::vector<Vec2> profile;
          const int samples = 16 * c.teeth;
          for (int i = 0; i < samples; ++i) {
            const double th = 2 * kPi * i / samples;
            profile.push_back(gear.tooth_radius(th) * Vec2(std::cos(th), std::sin(th)));
          }
          out.push_back(body(c.name + "_" + std::to_string(k++), g, c.friction, prism_mesh(profile, c.thickness / 2, false),
                             g->motion()));
        }
      } else if (c.type == "mesh") {
        if (c.motion.kind != MotionSpec::Kind::Fixed) throw InputError(what + "a mesh collider is static (no motion yet)");
        TriangleMesh mesh = load_triangle_mesh(c.mesh.string());
        apply_transform(c.transform, mesh.X);
        MeshSurfaceOptions options;
        options.query_radius = c.query_radius;
        auto surface = std::make_shared<MeshSurface>(mesh.X, mesh.tris, options);
        out.push_back(body(c.name, surface, c.friction, mesh, Motion{}));
      } else {
        std::shared_ptr<const ImplicitSurface> shape;
        TriangleMesh mesh;
        if (c.type == "sphere") {
          shape = std::make_shared<SphereSurface>(Vec3::Zero(), c.radius);
          mesh = sphere_mesh(c.radius);
        } else if (c.type == "box") {
          shape = std::make_shared<BoxSurface>(to_vec(c.half_extents));
          mesh = box_mesh(to_vec(c.half_extents));
        } else {  // cylinder, axis y
          shape = std::make_shared<CappedCylinderSurface>(c.radius, c.half_height);
          std::vector<Vec2> circle;
          for (int i = 0; i < 48; ++i) circle.push_back(c.radius * Vec2(std::cos(2 * kPi * i / 48), std::sin(2 * kPi * i / 48)));
          mesh = prism_mesh(circle, c.half_height, true);
        }
        Motion motion = make_motion(c);
        out.push_back(body(c.name, std::make_shared<MovingSurface>(shape, motion), c.friction, mesh, motion));
      }
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError(what + e.what());
    }
  }
  return out;
}

}  // namespace invfem::app
