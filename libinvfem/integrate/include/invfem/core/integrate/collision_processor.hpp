#pragma once
// What the time stepper asks of rigid-body collision processing (ITF04 section 9, step 3).
// The collisions module implements it for implicit surfaces; the core only knows this interface.
#include "invfem/core/solve/node_constraint.hpp"
#include "invfem/core/math/types.hpp"

#include <limits>
#include <vector>

namespace invfem {

struct SimObject;

// A node within reach of a collider (CollisionProcessor::gaps): the collider's signed distance phi
// at the node [m] (its collision surface, offset included), outward unit normal and velocity there,
// and its Coulomb coefficient.
struct BodyGap {
  int node = -1;
  double phi = 0;
  Vec3 normal = Vec3::UnitY();
  Vec3 velocity = Vec3::Zero();
  double friction = 0;
};

class CollisionProcessor {
 public:
  virtual ~CollisionProcessor() = default;
  // Stage hooks of the world's step (world.hpp). begin_object: the process() calls that follow
  // are for this object (a processor may treat objects differently by name or stage: an earlier
  // stage's surface collides with the later stages' objects only, never with itself).
  // earlier_stages_stepped: every object of a stage below `stage` has stepped to t_new = t + dt
  // and its surface was refreshed from its nodes (objects holds all of them, those of `stage` and
  // above still at t). Both do nothing by default.
  virtual void begin_object(const SimObject& object) { (void)object; }
  virtual void earlier_stages_stepped(const std::vector<SimObject>& objects, int stage, double t_new, double dt) {
    (void)objects, (void)stage, (void)t_new, (void)dt;
  }
  // The farthest [m] a node may move in one step and still have its contact with every collider
  // found (the thinnest analytic collider's half thickness): the world splits a step whose nodes
  // would move further. Infinity by default (nothing a step could pass through).
  virtual double step_motion_limit() const { return std::numeric_limits<double>::infinity(); }
  // x_old: x(n); x_new: the predicted x~(n+1), projected in place to x(n+1); v: v(n), modified in
  // place to v~(n) (normal velocity of the object where approaching, friction with the
  // dx_N/dt term). Appends one Kind::Normal constraint per colliding node, whose normal velocity
  // the trapezoid solve then holds fixed. Returns the number of colliding nodes. skip (one flag
  // per node, or null): nodes flagged non-zero are left as they are and get no constraint (the
  // implicit step's nodes already held, whose answer it would not use).
  virtual int process(const Points& x_old, Points& x_new, Points& v, double t_new, double dt,
                      NodeConstraints& constraints, const std::vector<char>* skip = nullptr) = 0;
  // Body contact as a barrier (body_barrier.hpp): out = one BodyGap per node and collider with
  // phi(x_i, t) < reach, in node order then collider order; nothing by default. Same threading and
  // current-object rules as process.
  virtual void gaps(const Points& x, double t, double reach, std::vector<BodyGap>& out) {
    (void)x, (void)t, (void)reach;
    out.clear();
  }
};

}  // namespace invfem
