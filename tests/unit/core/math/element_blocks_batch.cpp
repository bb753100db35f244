// Tests of tet_upper_blocks_batch (diagonal_space_hessian.hpp), the SIMD form of element_blocks:
// the same bits as element_blocks written through ElementMatrices::set_block, for tets whose node
// indices come in every order, over batch lengths that end inside a vector.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>
#include <vector>

#include "invfem/core/math/diagonal_space_hessian.hpp"
#include "invfem/core/math/element_matrices.hpp"
#include "random_matrices.hpp"

namespace invfem {
namespace {

TEST(ElementBlocksBatch, GivesTheBitsOfElementBlocks) {
  std::mt19937 rng(2005);
  std::normal_distribution<double> normal;
  for (const int n : {1, 7, 8, 9, 61}) {
    std::vector<DiagonalSpaceHessian> h(n);
    std::vector<Diagonalization3> d(n);
    std::vector<Mat34> beta(n);
    std::vector<double> scale(n);
    ElementMatrices reference;
    reference.resize(n, 4, ElementMatrices::Form::Upper);
    for (int i = 0; i < n; ++i) {
      const Mat3 A = test::random_matrix(rng);
      h[i].diagonal = A + A.transpose();
      for (Mat2& P : h[i].pairs) {
        const double off = normal(rng);
        P << normal(rng), off, off, normal(rng);
      }
      d[i].U = test::random_rotation(rng);
      d[i].V = test::random_rotation(rng);
      for (int q = 0; q < 12; ++q) beta[i].data()[q] = normal(rng);
      scale[i] = std::abs(normal(rng));
      std::array<int, 4> order{0, 1, 2, 3};  // node indices in a random order
      std::shuffle(order.begin(), order.end(), rng);
      for (int k = 0; k < 4; ++k) reference.nodes(i, k) = 4 * i + order[static_cast<std::size_t>(k)];
      element_blocks(h[i], d[i].U, d[i].V, beta[i], scale[i], [&](int k, int l, const Mat3& block) {
        reference.set_block(i, k, l, block, block.transpose());
      });
    }
    std::vector<double> flat(static_cast<std::size_t>(n) * kHessianEntries);
    for (int i = 0; i < n; ++i) flatten(h[i], flat.data() + kHessianEntries * i);
    std::vector<double> out(reference.values.size(), -1.0);
    tet_upper_blocks_batch(static_cast<std::size_t>(n), flat.data(), d.data(), beta.data(), scale.data(),
                           reference.nodes.data(), out.data());
    for (std::size_t q = 0; q < out.size(); ++q)
      ASSERT_EQ(std::memcmp(&out[q], &reference.values[q], sizeof(double)), 0)
          << "batch of " << n << ": tet " << q / 90 << ", value " << q % 90 << ": " << out[q] << " against "
          << reference.values[q];
  }
}

}  // namespace
}  // namespace invfem
