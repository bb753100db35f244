// The implicit step's friction: a lagged, smoothed Coulomb potential of its contacts.
#include "implicit_step_parts.hpp"

namespace invfem::implicit_detail {

// Coulomb friction of a sliding contact as a smoothed, lagged potential (the IPC way: Li et al.
// 2020): with the tangential slip s = T (x_i - x_i(n) - h u) relative to the body (u its velocity,
// T = I - n n^T) and eps = kStickSpeed h,
//   D = mu lambda f0(|s|),  f0(y) = y^2 / (2 eps) for y < eps, y - eps / 2 beyond,
// whose force is mu lambda along -s once slipping and a stiff spring below eps: static friction
// holds a contact to creep speeds below kStickSpeed. lambda, the normal force, is lagged (the
// last step's contact force, or for a new contact the impulse that stops it and gravity's share).
// 1e-3 m/s is IPC's usual eps_v: a much smaller eps makes the stick spring mu lambda / eps far
// stiffer, and its kink at |s| = eps stalls Newton's line search.
// Beyond eps the Newton system does not take D's exact Hessian mu lambda / |s| (T - s^ s^T), which
// has no curvature along the slip: a resting node whose net tangential force is below mu lambda
// must come back into the eps zone (2e-5 m at h = 1/50 s), but with only M / h^2 along s^ each
// Newton step sends it about mu g h^2 (1 mm) past it to slide the other way, and with tens of such
// nodes the one line search settles at a short step with the residual stuck. It takes
// mu lambda / |s| T instead, the Hessian of the quadratic that
// touches |s| at the iterate from above (iteratively reweighted least squares, Weiszfeld): each
// step decreases D's majorizer, so full steps are taken and the slip shrinks geometrically into the
// eps zone, where the Hessian is exact; it is continuous at |s| = eps. For a
// node sliding steadily, friction_hessian takes the exact Hessian after all (the majorizer's rate
// is slow where the slip is small).
constexpr double kStickSpeed = 1e-3;  // [m/s]: creep allowed under static friction

Slip slip(const NodeConstraint& c, const Points& x, const Points& x_start, double h) {
  const Mat3 T = Mat3::Identity() - c.normal * c.normal.transpose();
  const Vec3 d = x.row(c.node).transpose() - x_start.row(c.node).transpose() - h * c.velocity;
  return {T * d, T, kStickSpeed * h};
}

double friction_potential(const Contacts& k, const Points& x, const Points& x_start, double h) {
  double sum = 0;  // sequential: reproducible
  for_each_friction(k, [&](const NodeConstraint& c, double mu_lambda, std::size_t, bool) {
    const Slip sl = slip(c, x, x_start, h);
    const double y = sl.s.norm();
    sum += mu_lambda * (y < sl.eps ? y * y / (2 * sl.eps) : y - sl.eps / 2);
  });
  return sum;
}

void add_friction_gradient(const Contacts& k, const Points& x, const Points& x_start, double h, double w,
                           Points& grad) {
  for_each_friction(k, [&](const NodeConstraint& c, double mu_lambda, std::size_t, bool) {
    const Slip sl = slip(c, x, x_start, h);
    const double y = sl.s.norm();
    const double scale = y < sl.eps ? 1 / sl.eps : 1 / y;  // f0'(y) / y
    grad.row(c.node) += (w * mu_lambda * scale) * sl.s.transpose();
  });
}

// The friction Hessian of one contact, mu lambda times this (see kStickSpeed for D): T / eps in
// the stick zone (exact); beyond it, sliding, the majorizer T / |s| or the exact Hessian
// (T - s^ s^T) / |s|, which has no curvature along the slip.
// The majorizer is safe but slow where a node keeps sliding: in one dimension, with a the rest of
// the system's curvature along s^ and b = mu lambda, it converges to the slip y at the rate
// b / (a y + b) (b / a = mu g h^2), close to 1 for nodes that creep at a few eps, so Newton
// reaches its cap on a body resting on the ground. The exact Hessian is the
// Newton step there, but it sends a node whose slip should end inside the stick zone past it
// (the kink at eps). So it is taken for a node sliding steadily only: the slip at the last
// assembly of this step (last_slip) beyond eps, within 2x of this one in length and about 18
// degrees in direction, and the node's own Newton step along s^ (-g . s^ / (s^ A_ii s^), A_ii its
// diagonal block before friction, g the filtered grad E) leaving it beyond eps. Against the
// majorizer everywhere this saves Newton and CG iterations where contacts slide, though a crushed,
// stiff shell's CG prefers the majorizer's extra diagonal. Both
// Hessians are positive semi-definite; A stays definite through M.
Mat3 friction_hessian(const Slip& sl, const Vec3& last_slip, const Mat3& A_ii, const Vec3& g) {
  const double y = sl.s.norm();
  if (y <= sl.eps) return sl.T / sl.eps;
  const Vec3 s_hat = sl.s / y;
  const double y_last = last_slip.norm();
  const bool steady =
      y_last > sl.eps && last_slip.dot(sl.s) > 0.95 * y_last * y && y < 2 * y_last && y_last < 2 * y;
  const double dy = -g.dot(s_hat) / s_hat.dot(A_ii * s_hat);
  if (steady && y + dy > sl.eps) return (sl.T - s_hat * s_hat.transpose()) / y;
  return sl.T / y;
}

}  // namespace invfem::implicit_detail
