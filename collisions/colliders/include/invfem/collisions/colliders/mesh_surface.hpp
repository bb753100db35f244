#pragma once
// A closed triangle mesh as an implicit surface (ITF04 section 10: the Buddha as a collider for
// its cape). For a point x the closest point p on the mesh (vertex, edge or face) is found with
// the core's SurfaceBvh (an Embree point query with exact double point-triangle distances); |phi| = |x - p| and the
// sign comes from the angle-weighted pseudo-normal of p's feature (face normal inside a face,
// sum of the adjacent face normals on an edge, angle-weighted vertex normal at a vertex),
// which decides exactly on which side of a closed, consistently oriented mesh x lies. The normal
// is the unit direction x - p or p - x, whichever points outward.
//
// The mesh can deform (a simulated solid's boundary as a one-way collider): update() refits
// the BVH and the velocity of the closest point is the barycentric blend of the vertex
// velocities (x_now - x_before) / dt, or of velocities the caller gives (update(x, v)).
//
// Time arguments are ignored: queries see the mesh as of the last update. Queries are
// thread-safe between updates; update() must not run concurrently with queries.
#include <limits>
#include <memory>

#include "invfem/collisions/colliders/implicit_surface.hpp"
#include "invfem/core/geometry/surface.hpp"

namespace invfem {

struct MeshSurfaceOptions {
  // Contact distance [m]. A point with no mesh point within it gets phi = +query_radius, a
  // normal pointing away from the mesh's box center and zero velocity: it is treated as outside
  // and far, even if it lies deep inside the mesh. Infinity = exact everywhere (slower).
  double query_radius = std::numeric_limits<double>::infinity();
  // The collision surface lies this far outside the mesh [m], >= 0 and below query_radius:
  // phi = signed distance - offset. Projected vertices then rest at this gap, not on the mesh,
  // so the self-collision layer, which keeps a positive gap to the mesh's triangles, starts each
  // step from a state it can keep (a vertex exactly on a triangle is a contact it cannot undo).
  double offset = 0;
};

// Throws std::invalid_argument naming the field: query_radius not > 0, offset not in
// [0, query_radius).
void validate(const MeshSurfaceOptions& options);

// The contact a scene gives a body's mesh (a mesh collider, an animated body, a solid coupled to
// cloth): searched within 5 cm, the collision surface 1 mm outside, a gap the self-collision
// layer can keep.
inline constexpr MeshSurfaceOptions kBodyContact{0.05, 1e-3};

struct MeshClosestPoint {
  bool found = false;              // false: nothing within the query radius
  int triangle = -1;
  Vec3 point = Vec3::Zero();       // p, the closest point of the mesh
  Vec3 barycentric = Vec3::Zero(); // p = sum_i b_i x(tris(triangle, i))
  double distance = 0;             // |x - p|
  double phi = 0;                  // +distance outside, -distance inside, minus the offset
  Vec3 normal = Vec3::UnitZ();     // outward unit
  Vec3 velocity = Vec3::Zero();    // of the material point at p
};

class MeshSurface final : public ImplicitSurface {
 public:
  // The surface's triangles are counter-clockwise seen from outside. Throws
  // std::invalid_argument (empty mesh, non-finite or out-of-float-range position, index out of
  // range, naming the vertex/triangle) or std::runtime_error (Embree failure).
  explicit MeshSurface(const TriangleSurface& surface, MeshSurfaceOptions options = {});
  ~MeshSurface() override;
  MeshSurface(const MeshSurface&) = delete;
  MeshSurface& operator=(const MeshSurface&) = delete;

  // New vertex positions (same count and topology) after a step of length dt > 0: refits the
  // BVH and sets the vertex velocities to (x - previous) / dt.
  void update(const Points& x, double dt);
  // New vertex positions with their velocities given (#V x 3 each; a body whose motion is known,
  // such as an interpolated mesh sequence): refits the BVH; the closest point's velocity is the
  // barycentric blend of `v`. Throws std::invalid_argument for a wrong shape or a non-finite
  // velocity; the surface is then unchanged.
  void update(const Points& x, const Points& v);

  MeshClosestPoint closest(const Vec3& x) const;

  double phi(const Vec3& x, double t) const override;
  Vec3 normal(const Vec3& x, double t) const override;
  Vec3 velocity(const Vec3& x, double t) const override;
  // phi(x) when the closest point lies within the query radius and x is outside the collision
  // surface, else 0: the distance to the mesh is 1-Lipschitz and a point cannot change sides of a
  // closed mesh without crossing it, so every y nearer x than phi(x) has phi(y) > 0.
  double clearance(const Vec3& x, double t) const override;
  // A fresh number at construction and at every update().
  std::uint64_t version() const override;

  const TriangleSurface& surface() const;
  double query_radius() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  // phi, normal and velocity at the same x share one query (per-thread cache).
  const MeshClosestPoint& cached(const Vec3& x) const;
};

}  // namespace invfem
