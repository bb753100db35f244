#pragma once
// Inside/outside and closest-point queries against a triangle surface, for the BCC mesher.
// The core's SurfaceBvh (Embree) does the ray casting (parity) and the closest-point search; the
// generalized winding number (sum of signed solid angles / 4 pi) is the fallback for surfaces
// that are not closed.
#include <optional>
#include <string>
#include <vector>

#include "invfem/core/geometry/surface_bvh.hpp"


namespace invfem {

// RayParity: odd number of surface crossings along a ray (needs a closed surface; see
// is_closed). WindingNumber: generalized winding number > 1/2 (works with holes; cost is
// O(triangles) per point). Auto: RayParity if the surface is closed, else WindingNumber.
enum class InsideMethod { RayParity, WindingNumber, Auto };

const char* to_string(InsideMethod m);

class InsideTest {
 public:
  // Validates the surface (validate_surface) and builds its BVH. Throws std::invalid_argument
  // naming surface.source for bad input, std::runtime_error if Embree fails.
  explicit InsideTest(const TriangleSurface& surface);

  // Undirected edges used by an odd number of triangles: the mod-2 boundary of the surface.
  // Zero means every ray from a point off the surface crosses it an even number of times on its
  // way to infinity, so parity is well defined (self-intersections and non-manifold edges used
  // 4 times are allowed).
  int open_edges() const { return open_edges_; }
  bool is_closed() const { return open_edges_ == 0; }

  // Parity of unique crossings along three fixed, generic ray directions; the majority answer
  // is returned (a ray that grazes an edge or vertex can miscount, two rays rarely both do).
  // The BVH works in float (surface_bvh.hpp), so points within about 1e-6 x (bounding-box size)
  // of the surface may be classified either way.
  bool inside_ray_parity(const Vec3& p) const;

  // Generalized winding number of p (1 inside a closed outward-oriented surface, -1 inside an
  // inward-oriented one, 0 outside, about +-1/2 across a hole). Exact sum over all triangles, in
  // double. `inside` with WindingNumber uses |w| > 1/2, so orientation does not matter.
  double winding_number(const Vec3& p) const;

  // Point on the surface closest to p (BVH point query, distances in double).
  // `distance` (optional) receives |p - result|.
  Vec3 closest_point(const Vec3& p, double* distance = nullptr) const;

  // Same, searching only within `radius` of p (faster); nullopt if no triangle is that close.
  std::optional<Vec3> closest_point_within(const Vec3& p, double radius) const;

  // One flag per row of P (1 inside). Parallel over points (TBB). With RayParity on a surface
  // that is not closed, throws std::invalid_argument naming the surface and its open edges.
  std::vector<char> inside(const Points& P, InsideMethod method) const;

  // The method `inside` actually uses for `method` (Auto resolved).
  InsideMethod resolve(InsideMethod method) const;

  // Signed volume enclosed by the triangles (enclosed_signed_volume, surface.hpp).
  double signed_volume() const;

  const TriangleSurface& surface() const { return bvh_.surface(); }

 private:
  SurfaceBvh bvh_;
  Points normals_;              // #F x 3 unnormalized face normals (b-a)x(c-a)
  int open_edges_ = 0;
};

}  // namespace invfem
