#pragma once
// Choosing pinned nodes (world.hpp PinGroup) the ways a scene names them.
#include <optional>
#include <string>
#include <vector>

#include "invfem/core/world/world.hpp"

namespace invfem {

// The rows of X inside the axis-aligned box [lo, hi] (bounds included), ascending.
std::vector<int> nodes_in_box(const Points& X, const Vec3& lo, const Vec3& hi);

// A pin group holding `nodes` at their rows of X (their anchors), moved by `motion` if given.
// Throws std::invalid_argument naming `what` for an empty list or a node outside [0, X.rows()).
PinGroup make_pin_group(const Points& X, std::vector<int> nodes, std::optional<Motion> motion,
                        const std::string& what);

// Sets the velocity of every pinned node of `object` to its group's velocity at time t (zero for
// a group held still), so the first step starts consistent with the pins.
void set_pinned_velocities(SimObject& object, double t);

}  // namespace invfem
