#pragma once
// The pieces of amg.hpp's smoothed-aggregation multigrid shared by its source files: the scalar CSR
// levels, their product, the node graph and its aggregation.
#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <vector>

#include "invfem/core/solve/amg.hpp"

namespace invfem::amg {

using Csr = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

// y = A x for a compressed A, parallel over rows, each row summed in column order.
void multiply(const Csr& A, const Eigen::VectorXd& x, Eigen::VectorXd& y);

// Nodes group dofs: node a owns dofs [node_start[a], node_start[a + 1]). The graph joins two nodes
// whose block of A holds a nonzero entry; weight = the block's squared Frobenius norm.
struct NodeGraph {
  std::vector<int> start;     // nodes + 1
  std::vector<int> neighbor;  // start[a] .. start[a + 1]: node a's neighbours, in first-seen order
  std::vector<double> weight; // same layout
};
NodeGraph node_graph(const Csr& A, const std::vector<int>& node_start);

// Vanek, Mandel, Brezina 1996, section 3: pass 1 roots an aggregate at every node whose neighbours
// are all free, taking them in; pass 2 joins each node left to the aggregate of its strongest
// neighbour from pass 1 (one exists: otherwise pass 1 would have rooted it). A node without
// neighbours (a pinned node, whose row of K is the identity) joins none: the smoother alone
// solves it. Nodes are visited in index order, so the result is deterministic.
// Returns the number of aggregates; aggregate_of[a] = -1 for a node in none.
int aggregate(const NodeGraph& g, std::vector<int>& aggregate_of);

struct Level {
  Csr A;                     // this level's matrix (level 0: K)
  Eigen::VectorXd inv_diag;  // 1 / diag(A)
  double lambda_max = 0;     // of D^-1 A, by power iteration
  Eigen::VectorXd eigenvector;  // the power iteration's last vector, to warm-start a re-estimate
  Csr P, R;                  // prolongator to the next level and R = P^T (empty on the coarsest)
  mutable Eigen::VectorXd x, b, r, d, t;  // V-cycle scratch
};

// lambda_max(D^-1 A) by `iterations` of the power method from level.eigenvector (set to a fixed
// start vector when empty); stores the vector back.
void estimate_lambda_max(Level& level, int iterations);

}  // namespace invfem::amg

namespace invfem {

struct AmgPreconditioner::Hierarchy {
  std::vector<amg::Level> levels;   // level 0: K
  Eigen::LDLT<Eigen::MatrixXd> coarsest;  // the last level, factorized densely when small enough
  bool direct = false;
  Eigen::Index nodes = 0;           // the pattern of A that level 0 was built from
  std::size_t blocks = 0;
};

}  // namespace invfem

namespace invfem::amg {

// x = the V-cycle from zero on levels l, l + 1, ... of h applied to b.
void v_cycle(const AmgPreconditioner::Hierarchy& h, std::size_t l, const Eigen::VectorXd& b, Eigen::VectorXd& x);

}  // namespace invfem::amg

