#pragma once
// Per-element matrices, the currency between a force and the implicit integrator's assembly
// (implicit_step.hpp): a force writes one (3a x 3a) matrix per element of a nodes, in one of the
// forms below; the integrator scatters them into its BlockSparseMatrix with one helper
// (block_sparse.hpp).
//
// Three forms, one per set (row/column 3 k + r is coordinate r of the element's k-th node
// nodes(e, k); every matrix is symmetric):
//  - Dense: element e's matrix is values[e * (3a)^2 ...], column-major (triangles, springs);
//  - Upper: per node pair k <= l of the element (distinct nodes), one 3x3 block, column-major,
//    packed in the order (0,0), (0,1), ..., (0,a-1), (1,1), ...: 9 a (a + 1) / 2 numbers (90 for
//    a tet against 144, 54 for a triangle against 81). The pair's block is the one whose rows
//    belong to the node with the smaller index, (k, l) if nodes(e, k) < nodes(e, l), else (l, k):
//    exactly the block the assembly reads (it gathers the matrix's upper triangle, by node
//    index), so a matrix that is not symmetric to the bit (a sum of products in another order
//    for (l, k)) assembles to the same bits as in the dense form. The other block of the pair is
//    taken as its transpose. Tets and membrane triangles;
//  - Outer: element e's matrix is s u u^T, stored as values[e * (3a + 1) ...] = (u (3a), s) with
//    s >= 0: a bending hinge's Gauss-Newton stiffness and its damping. 3a + 1 numbers instead of
//    (3a)^2 (13 against 144 for a hinge): the hinges are most of a cloth's element data, and the
//    assembly's cost is reading it. Entry (i, j) is (s u_i) u_j, the same products, in the same
//    order, as the dense s * u * u^T of Eigen, so both forms assemble to the same bits.
#include <vector>

#include <Eigen/Core>

#include "invfem/core/math/types.hpp"

namespace invfem {

struct ElementMatrices {
  enum class Form { Dense, Upper, Outer };
  int arity = 0;  // nodes per element: 4 for tets and hinges, 3 for triangles and stitches, 2 for edge springs
  Form form = Form::Dense;
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> nodes;  // m x arity
  std::vector<double> values;  // m stride(): (3 arity)^2, 9 arity (arity + 1) / 2 or 3 arity + 1

  Eigen::Index count() const { return nodes.rows(); }
  int size() const { return 3 * arity; }  // rows of one element matrix
  // Numbers stored per element.
  int stride() const {
    switch (form) {
      case Form::Dense: return size() * size();
      case Form::Upper: return 9 * arity * (arity + 1) / 2;
      case Form::Outer: break;
    }
    return size() + 1;
  }
  // Upper form: the index of node pair (k, l), k <= l, in the packed order.
  int upper_block(int k, int l) const { return k * arity - k * (k - 1) / 2 + (l - k); }
  // Upper form: stores block (k, l), k <= l, of element e's matrix, given with the block (l, k)
  // that is its counterpart (the same matrix transposed when the element matrix is exactly
  // symmetric): the one the pair keeps is chosen by node index (above).
  void set_block(Eigen::Index e, int k, int l, const Mat3& kl, const Mat3& lk) {
    Eigen::Map<Mat3>(values.data() + e * stride() + 9 * upper_block(k, l)) = nodes(e, k) < nodes(e, l) ? kl : lk;
  }
  // Upper form: element e's blocks from its whole N x N matrix (N = 3 arity).
  template <int N> void set_upper(Eigen::Index e, const Eigen::Matrix<double, N, N>& K) {
    for (int k = 0; k < arity; ++k)
      for (int l = k; l < arity; ++l)
        set_block(e, k, l, K.template block<3, 3>(3 * k, 3 * l), K.template block<3, 3>(3 * l, 3 * k));
  }
  // Holds m elements of `a` nodes in form f with room for their values: a force forming its set
  // again keeps the node lists then (a set from Force::stiffness_pattern or damping_pattern has the
  // lists but no values).
  bool shaped(Eigen::Index m, int a, Form f) const {
    return arity == a && form == f && count() == m &&
           values.size() == static_cast<std::size_t>(m) * static_cast<std::size_t>(stride());
  }
  // Frees the values, the node lists and form kept: the set Force::stiffness_pattern and
  // damping_pattern give.
  void release_values() { std::vector<double>().swap(values); }
  // Sizes the arrays for m elements of `a` nodes in the given form (keeping the allocation when
  // it fits).
  void resize(Eigen::Index m, int a, Form f = Form::Dense) {
    arity = a;
    form = f;
    nodes.resize(m, a);
    values.resize(static_cast<std::size_t>(m) * static_cast<std::size_t>(stride()));
  }
  // Outer form: element e's u (N = 3 arity) and s.
  template <int N> Eigen::Map<Eigen::Matrix<double, N, 1>> outer_vector(Eigen::Index e) {
    return Eigen::Map<Eigen::Matrix<double, N, 1>>(values.data() + e * (N + 1));
  }
  double& outer_scale(Eigen::Index e) { return values[static_cast<std::size_t>(e * stride() + size())]; }
  // Element e's whole matrix, any form (tests and checks; the assembly reads the blocks in
  // place).
  Eigen::MatrixXd dense(Eigen::Index e) const {
    const int n = size();
    const double* v = values.data() + e * stride();
    if (form == Form::Dense) return Eigen::Map<const Eigen::MatrixXd>(v, n, n);
    if (form == Form::Upper) {
      Eigen::MatrixXd K(n, n);
      for (int k = 0; k < arity; ++k)
        for (int l = k; l < arity; ++l) {
          const Eigen::Map<const Mat3> b(v + 9 * upper_block(k, l));
          const bool kept_kl = nodes(e, k) < nodes(e, l);
          K.block<3, 3>(3 * k, 3 * l) = kept_kl ? Mat3(b) : Mat3(b.transpose());
          K.block<3, 3>(3 * l, 3 * k) = kept_kl ? Mat3(b.transpose()) : Mat3(b);
        }
      return K;
    }
    const Eigen::Map<const Eigen::VectorXd> u(v, n);
    return (v[n] * u) * u.transpose();
  }
  // Dense form: element e's matrix as a fixed-size map, N = 3 arity.
  template <int N> Eigen::Map<Eigen::Matrix<double, N, N>> matrix(Eigen::Index e) {
    return Eigen::Map<Eigen::Matrix<double, N, N>>(values.data() + e * N * N);
  }
  template <int N> Eigen::Map<const Eigen::Matrix<double, N, N>> matrix(Eigen::Index e) const {
    return Eigen::Map<const Eigen::Matrix<double, N, N>>(values.data() + e * N * N);
  }
};

// K_e = scale G^T H G for an element whose deformation gradient is F = sum_k x_k beta_k^T
// (F is 3 x D, beta_k the gradient of node k's shape function, D = 3 for a tet, 2 for a
// triangle): H is dP/dF (3D x 3D on column-major vec(F), vec index r + 3 c), beta is D x (D+1)
// (column k = beta_k), and block (a, b) of the result is
//   K_ab(r, s) = scale sum_{c,d} beta_a(c) H(r + 3 c, s + 3 d) beta_b(d).
template <int D>
Eigen::Matrix<double, 3 * (D + 1), 3 * (D + 1)> element_matrix_from_dPdF(const Eigen::Matrix<double, 3 * D, 3 * D>& H,
                                                                       const Eigen::Matrix<double, D, D + 1>& beta,
                                                                       double scale) {
  // Hb_b = H (beta_b kron I3): 3D x 3 per node b.
  Eigen::Matrix<double, 3 * D, 3 * (D + 1)> Hb;
  for (int b = 0; b <= D; ++b) {
    Hb.template block<3 * D, 3>(0, 3 * b).setZero();
    for (int d = 0; d < D; ++d) Hb.template block<3 * D, 3>(0, 3 * b) += beta(d, b) * H.template block<3 * D, 3>(0, 3 * d);
  }
  Eigen::Matrix<double, 3 * (D + 1), 3 * (D + 1)> out;
  for (int a = 0; a <= D; ++a)
    for (int b = 0; b <= D; ++b) {
      Mat3 k = Mat3::Zero();
      for (int c = 0; c < D; ++c) k += beta(c, a) * Hb.template block<3, 3>(3 * c, 3 * b);
      out.template block<3, 3>(3 * a, 3 * b) = scale * k;
    }
  return out;
}

// The shape-function gradients of a tet (D = 3) or triangle (D = 2) from Dm^-1 (D x D): rows of
// Dm^-1 are the gradients of nodes 1..D, node 0's is minus their sum.
template <int D> Eigen::Matrix<double, D, D + 1> shape_gradients(const MatD<D>& Dm_inv) {
  Eigen::Matrix<double, D, D + 1> beta;
  beta.col(0) = -Dm_inv.colwise().sum().transpose();
  beta.template rightCols<D>() = Dm_inv.transpose();
  return beta;
}

}  // namespace invfem
