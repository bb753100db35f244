#include "invfem/core/solve/node_filter.hpp"

namespace invfem {

void NodeFilter::assign(Eigen::Index n, const NodeConstraints& fixed) {
  if (static_cast<Eigen::Index>(S_.size()) != n) {
    S_.assign(static_cast<std::size_t>(n), Mat3::Identity());
    constrained_.assign(static_cast<std::size_t>(n), 0);
    listed_.clear();
  }
  for (int i : listed_) {
    S_[static_cast<std::size_t>(i)].setIdentity();
    constrained_[static_cast<std::size_t>(i)] = 0;
  }
  listed_.clear();
  for (const NodeConstraint& c : fixed) {
    const auto i = static_cast<std::size_t>(c.node);
    if (!constrained_[i]) listed_.push_back(c.node);
    constrained_[i] = 1;
    if (c.kind == NodeConstraint::Kind::Full) {
      S_[i].setZero();
      continue;
    }
    const Vec3 q = S_[i] * c.normal;  // the normal's part not constrained yet
    const double len = q.norm();
    if (len > 1e-9) S_[i] -= (q / len) * (q / len).transpose();
  }
}

Mat3 NodeFilter::filtered(Eigen::Index i, Eigen::Index j, const Mat3& Aij) const {
  if (!constrained(i) && !constrained(j)) return Aij;
  Mat3 K = S(i) * Aij * S(j);
  if (i == j) K += Mat3::Identity() - S(i);
  return K;
}

void NodeFilter::apply(Points& v) const {
  for (int i : listed_) v.row(i) = (S(i) * v.row(i).transpose()).transpose();
}

}  // namespace invfem
