#include "invfem/collisions/colliders/rigid_body.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace invfem {

RigidBody::RigidBody(std::string name, std::shared_ptr<const ImplicitSurface> implicit, double friction,
                     TriangleSurface body_surface, Motion motion, bool surface_is_shape)
    : name_(std::move(name)),
      implicit_(std::move(implicit)),
      friction_(friction),
      body_(std::move(body_surface)),
      motion_(std::move(motion)),
      surface_is_shape_(surface_is_shape),
      world_(body_) {
  if (!implicit_) throw std::invalid_argument("rigid body \"" + name_ + "\": no implicit surface");
  if (!(friction_ >= 0)) throw std::invalid_argument("rigid body \"" + name_ + "\": friction must be >= 0");
  world_.source = name_;
}

void RigidBody::move_to(double t) {
  if (t != time_) posed_ = false;
  time_ = t;
}

const TriangleSurface* RigidBody::surface() const {
  if (!body_.x.rows()) return nullptr;
  if (!posed_) {
    const RigidTransform T = motion_.body_to_world(time_);
    for (Eigen::Index i = 0; i < body_.x.rows(); ++i) world_.x.row(i) = T.apply(body_.x.row(i).transpose()).transpose();
    posed_ = true;
  }
  return &world_;
}

Points RigidBody::surface_velocities() const {
  const TriangleSurface* s = surface();
  if (!s) return {};
  Points v(s->x.rows(), 3);
  for (Eigen::Index i = 0; i < v.rows(); ++i) v.row(i) = motion_.velocity(s->x.row(i).transpose(), time_).transpose();
  return v;
}

std::unique_ptr<RigidCollisions> make_rigid_collisions(const std::vector<std::shared_ptr<RigidBody>>& bodies,
                                                       std::vector<SolidCoupling> couplings) {
  std::vector<RigidCollider> colliders;
  for (const auto& b : bodies) colliders.push_back({b->implicit(), b->friction()});
  return std::make_unique<RigidCollisions>(std::move(colliders), std::move(couplings));
}

namespace {

constexpr double kPi = std::numbers::pi;

void add_quad(std::vector<Eigen::Vector3i>& t, int a, int b, int c, int d) {
  t.emplace_back(a, b, c);
  t.emplace_back(a, c, d);
}

TriangleSurface to_surface(const std::vector<Vec3>& v, const std::vector<Eigen::Vector3i>& t, std::string source) {
  TriangleSurface s;
  s.source = std::move(source);
  s.x.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) s.x.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  s.tris.resize(static_cast<Eigen::Index>(t.size()), 3);
  for (std::size_t i = 0; i < t.size(); ++i) s.tris.row(static_cast<Eigen::Index>(i)) = t[i].transpose();
  return s;
}

}  // namespace

TriangleSurface sphere_triangles(double r) {
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
  return to_surface(v, t, "sphere");
}

TriangleSurface prism_triangles(const std::vector<Vec2>& profile, double h, bool axis_is_y) {
  auto point = [&](const Vec2& p, double z) { return axis_is_y ? Vec3(p.x(), z, -p.y()) : Vec3(p.x(), p.y(), z); };
  const int n = static_cast<int>(profile.size());
  std::vector<Vec3> v{point(Vec2::Zero(), -h), point(Vec2::Zero(), h)};
  for (const auto& p : profile) v.push_back(point(p, -h));
  for (const auto& p : profile) v.push_back(point(p, h));
  std::vector<Eigen::Vector3i> t;
  for (int i = 0; i < n; ++i) {
    const int a = 2 + i, b = 2 + (i + 1) % n, A = a + n, B = b + n;
    t.emplace_back(0, b, a);  // bottom cap faces -axis
    t.emplace_back(1, A, B);  // top cap faces +axis
    add_quad(t, a, b, B, A);  // side
  }
  return to_surface(v, t, "prism");
}

TriangleSurface cylinder_triangles(double radius, double half_height) {
  std::vector<Vec2> circle;
  for (int i = 0; i < 48; ++i) circle.push_back(radius * Vec2(std::cos(2 * kPi * i / 48), std::sin(2 * kPi * i / 48)));
  TriangleSurface s = prism_triangles(circle, half_height, true);
  s.source = "cylinder";
  return s;
}

TriangleSurface box_triangles(const Vec3& e) {
  std::vector<Vec3> v;
  for (int k = 0; k < 8; ++k) v.emplace_back((k & 1 ? 1 : -1) * e.x(), (k & 2 ? 1 : -1) * e.y(), (k & 4 ? 1 : -1) * e.z());
  std::vector<Eigen::Vector3i> t;
  add_quad(t, 0, 4, 6, 2);  // -x
  add_quad(t, 1, 3, 7, 5);  // +x
  add_quad(t, 0, 1, 5, 4);  // -y
  add_quad(t, 2, 6, 7, 3);  // +y
  add_quad(t, 0, 2, 3, 1);  // -z
  add_quad(t, 4, 5, 7, 6);  // +z
  return to_surface(v, t, "box");
}

}  // namespace invfem
