#include "invfem/collisions/self_collision/self_collision_pass.hpp"

namespace invfem::collisions {

void SelfCollisionPass::adopt_resumed() {
  if (!resumed_) return;
  if (resumed_->end.rows() == mesh_.x0.rows() && resumed_->recovering_tets.size() == boundary_tets_.size()) {
    end_ = std::move(resumed_->end);
    left_crossable_ = resumed_->left_crossable;
    tangle_ages_ = std::move(resumed_->tangle_ages);
    recovering_tets_ = std::move(resumed_->recovering_tets);
  }
  resumed_.reset();
}

}  // namespace invfem::collisions
