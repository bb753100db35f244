#pragma once
// Exact orientation predicates for the intersection certificate (`invfem check`). Each returns the
// sign (-1, 0 or +1) of a determinant of its double inputs taken as exact real numbers: never a
// wrong sign, never a "nearly zero". A floating-point evaluation is used when its static error
// bound (Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust geometric
// predicates", the first-stage bounds of orient2d and orient3d) proves the sign; otherwise every
// double is converted exactly to an integer times a power of two and the determinant is evaluated
// in GMP integers. Inputs must be finite (the certificate rejects NaN and infinity before).
//
// The certificate owns these: the collision response (collisions/ outside certificate/) never
// calls them, so one bug cannot both make and hide an intersection.
#include "invfem/core/math/types.hpp"

namespace invfem::certificate {

// sign of det [b - a, c - a] = (b - a) x (c - a): +1 when a, b, c turn counter-clockwise.
int orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

// sign of det [b - a, c - a, d - a] = ((b - a) x (c - a)) . (d - a): +1 when d lies on the side of
// the plane (a, b, c) that the normal of the counter-clockwise triangle a, b, c points to, 0 when
// the four points are coplanar.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The same signs always through the exact GMP evaluation (tests compare the two).
int orient2d_exact(const Vec2& a, const Vec2& b, const Vec2& c);
int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace invfem::certificate
