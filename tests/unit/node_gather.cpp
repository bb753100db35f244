// Tests of NodeGather (node_gather.hpp) through the tet and triangle scatters: in parallel, they
// give the bits of the serial loops over elements they replace, whatever the thread count; and a
// node index outside the node range is an error naming the element.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include "invfem/core/tet_kernel.hpp"
#include "invfem/core/triangle_kernel.hpp"

namespace invfem {
namespace {

bool same_bits(const Points& a, const Points& b) {
  return a.rows() == b.rows() && std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

// m elements of `arity` distinct random nodes of n, a tenth of them on node 7 (a node in thousands
// of elements, as a pin or an apex is), in several node gather chunks (n > 2048).
template <class Elements> Elements random_elements(Eigen::Index m, int arity, int n, std::mt19937& rng) {
  Elements E(m, arity);
  std::uniform_int_distribution<int> node(0, n - 1);
  for (Eigen::Index e = 0; e < m; ++e)
    for (int k = 0; k < arity; ++k) {
      int i = (e % 10 == 0 && k == e % arity) ? 7 : node(rng);
      for (int l = 0; l < k; ++l)
        if (E(e, l) == i) i = (i + 1) % n, l = -1;  // distinct within the element
      E(e, k) = i;
    }
  return E;
}

template <class M> std::vector<M> random_forces(std::size_t m, std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  std::vector<M> G(m);
  for (M& x : G)
    for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = std::ldexp(g(rng), static_cast<int>(rng() % 40) - 20);
  return G;
}

Points random_start(Eigen::Index n, std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  Points f(n, 3);
  for (Eigen::Index i = 0; i < f.size(); ++i) f.data()[i] = g(rng);
  return f;
}

TEST(NodeGather, TetScatterGivesTheSerialLoopsBitsOnOneAndTwoThreads) {
  std::mt19937 rng(17);
  constexpr int n = 5000;
  const Tets T = random_elements<Tets>(30000, 4, n, rng);
  const std::vector<Mat3> G = random_forces<Mat3>(static_cast<std::size_t>(T.rows()), rng);
  const Points start = random_start(n, rng);
  Points serial = start;  // the loop scatter_tet_forces was before the gather
  for (Eigen::Index e = 0; e < T.rows(); ++e) {
    const Mat3& g = G[static_cast<std::size_t>(e)];
    serial.row(T(e, 0)) -= (g.col(0) + g.col(1) + g.col(2)).transpose();
    for (int k = 0; k < 3; ++k) serial.row(T(e, k + 1)) += g.col(k).transpose();
  }
  const NodeGather gather = tet_node_gather(T, n);
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Points f = start;
    scatter_tet_forces(gather, G, f);
    EXPECT_TRUE(same_bits(f, serial)) << threads << " thread(s)";
  }
  EXPECT_FALSE(same_bits(start, serial));
}

TEST(NodeGather, TriangleScatterGivesTheSerialLoopsBitsOnOneAndTwoThreads) {
  std::mt19937 rng(23);
  constexpr int n = 4100;
  const Tris T = random_elements<Tris>(25000, 3, n, rng);
  const std::vector<Mat32> G = random_forces<Mat32>(static_cast<std::size_t>(T.rows()), rng);
  const Points start = random_start(n, rng);
  Points serial = start;
  for (Eigen::Index e = 0; e < T.rows(); ++e) {
    const Mat32& g = G[static_cast<std::size_t>(e)];
    serial.row(T(e, 1)) += g.col(0).transpose();
    serial.row(T(e, 2)) += g.col(1).transpose();
    serial.row(T(e, 0)) -= (g.col(0) + g.col(1)).transpose();
  }
  const NodeGather gather = triangle_node_gather(T, n);
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Points f = start;
    scatter_triangle_forces(gather, G, f);
    EXPECT_TRUE(same_bits(f, serial)) << threads << " thread(s)";
  }
}

TEST(NodeGather, NodeOutsideTheRangeIsAnErrorNamingTheElement) {
  Tets T(2, 4);
  T << 0, 1, 2, 3, 1, 2, 3, 9;
  try {
    tet_node_gather(T, 5);
    FAIL() << "no error for node 9 of 5";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("element 1 names node 9"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace invfem
