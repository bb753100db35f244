#pragma once
// A bounding volume hierarchy over a triangle surface, built by Embree 3: the one Embree scene
// set-up of invfem, behind closest-point queries (the BCC mesher, mesh colliders) and ray casts
// (inside tests). Embree stays private to the .cpp.
//
// Embree works in float. Positions are centred on the bounding box of the construction-time
// surface and scaled to a half-diagonal of 1 before conversion ("normalized" units), so float
// rounding is ~6e-8 of the object's size wherever it sits. Distances are then recomputed exactly
// in double on the original positions (closest_point.hpp); the float BVH only culls, with a
// margin for its rounding.
//
// Queries are thread-safe between refits; refit must not run concurrently with queries.
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "invfem/core/geometry/surface.hpp"

namespace invfem {

struct SurfaceBvhOptions {
  // false: built once at high quality (a fixed surface). true: the surface moves; refit() updates
  // the hierarchy in place each step without rebuilding it.
  bool refit = false;
};

struct SurfacePoint {
  int triangle = -1;
  Vec3 point = Vec3::Zero();        // the closest point of the surface
  Vec3 barycentric = Vec3::Zero();  // point = sum_k b_k x(tris(triangle, k)); zeros mark the feature
  double distance2 = 0;
};

struct RayHit {
  float t;             // along the ray, in normalized units (see normalized_scale())
  unsigned triangle;
};

class SurfaceBvh {
 public:
  // Copies the positions and triangles. Throws std::invalid_argument naming surface.source for an
  // invalid surface (validate_surface), a surface of zero extent or a coordinate beyond float's
  // range, std::runtime_error if Embree fails.
  explicit SurfaceBvh(const TriangleSurface& surface, SurfaceBvhOptions options = {});
  ~SurfaceBvh();
  SurfaceBvh(const SurfaceBvh&) = delete;
  SurfaceBvh& operator=(const SurfaceBvh&) = delete;

  // New positions (same count) of a refit hierarchy. Throws std::invalid_argument for a wrong
  // count, a non-finite or out-of-range coordinate, or a hierarchy built without options.refit.
  void refit(const Points& x);

  // The point of the surface closest to p among those closer than `radius` (nullopt if none).
  // Exact in double: Embree visits every triangle whose float box could be that close, and the
  // best is kept with strict < (the first visited wins a tie).
  std::optional<SurfacePoint> closest_point(
      const Vec3& p, double radius = std::numeric_limits<double>::infinity()) const;

  // Every crossing of the ray p + t d (t >= 0; d unit) with a triangle, in no particular order; a
  // triangle may be reported twice (BVH spatial splits). Edges are watertight (Embree's robust
  // mode). Appends to `hits`; returns false if more than `max_hits` were found (the rest dropped).
  bool ray_hits(const Vec3& p, const Vec3& d, std::vector<RayHit>& hits, int max_hits = 256) const;

  // World length of one normalized unit (the construction-time bounding box half-diagonal).
  double normalized_scale() const;
  const TriangleSurface& surface() const { return surface_; }

 private:
  struct Embree;
  TriangleSurface surface_;
  SurfaceBvhOptions options_;
  std::unique_ptr<Embree> embree_;
};

}  // namespace invfem
