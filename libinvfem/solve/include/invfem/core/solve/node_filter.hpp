#pragma once
// The Baraff-Witkin filter S of projected_cg.hpp as one 3x3 matrix per node, for the solvers that
// need the filtered Newton system as a matrix (sparse_direct.hpp, amg.hpp):
//
//   K = S A S + (I - S),   block (i, j) = S_i A_ij S_j, plus I - S_i on the diagonal,
//
// SPD when A is, with A's sparsity: on range(S) it is S A S, on its complement the identity.
// S_i = I - Q Q^T with Q an orthonormal basis of node i's constrained directions (Gram-Schmidt over
// its Kind::Normal normals; a Kind::Full constraint fixes all three). With one constraint per node,
// as the implicit step makes them, this is project_free's filter exactly.
#include <vector>

#include "invfem/core/solve/node_constraint.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

class NodeFilter {
 public:
  // S for n nodes under `fixed` (kinds and normals; values are ignored). Resetting only the nodes
  // constrained before, so a call costs O(constraints) after the first.
  void assign(Eigen::Index n, const NodeConstraints& fixed);

  bool constrained(Eigen::Index i) const { return constrained_[static_cast<std::size_t>(i)] != 0; }
  const Mat3& S(Eigen::Index i) const { return S_[static_cast<std::size_t>(i)]; }
  // Block (i, j) of K from A_ij.
  Mat3 filtered(Eigen::Index i, Eigen::Index j, const Mat3& Aij) const;
  // v_i = S_i v_i for every constrained node (v: n x 3).
  void apply(Points& v) const;

 private:
  std::vector<Mat3> S_;
  std::vector<char> constrained_;
  std::vector<int> listed_;  // the constrained nodes, to reset them at the next assign
};

}  // namespace invfem
