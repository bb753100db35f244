// The smoothed-aggregation hierarchy of amg.hpp: level 0 from the filtered block matrix, then
// aggregates, tentative and smoothed prolongators and Galerkin products down to a small level.
#include <Eigen/SVD>

#include <stdexcept>

#include "amg_internal.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem {

namespace {

using amg::Csr;
using amg::Level;

// The coarsest level is factorized densely at or below this many dofs (an LDL^T of 200 dofs is
// about 3e6 flops; a much larger coarsest level makes the dense factorization a visible share of
// a run); a level whose coarsening keeps more than kMinShrink of its dofs ends the
// hierarchy (smoothed only, no exact solve).
constexpr Eigen::Index kCoarsestDofs = 200;
constexpr double kMinShrink = 0.8;
constexpr int kMaxLevels = 10;
// Power iterations for lambda_max: from the fixed start at setup, warm-started at a refresh (the
// Newton matrix changes little between iterates).
constexpr int kSetupPowerIterations = 15;
constexpr int kRefreshPowerIterations = 5;

// K = S A S + (I - S) as a 3n x 3n CSR matrix: row 3 i + r holds, for each block (i, j) of A in
// column order, the entries (3 j + c), c = 0..2. With `pattern`, K's structure is built first.
void fill_level0(const BlockSparseMatrix& A, const NodeFilter& filter, bool pattern, Csr& K) {
  const Eigen::Index n = A.rows();
  const std::vector<int>& row_start = A.row_start();
  const std::vector<int>& col = A.columns();
  if (pattern) {
    K = Csr(3 * n, 3 * n);
    K.resizeNonZeros(static_cast<Eigen::Index>(9 * A.block_count()));
    int* outer = K.outerIndexPtr();
    int* inner = K.innerIndexPtr();
    outer[0] = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const int begin = row_start[static_cast<std::size_t>(i)], end = row_start[static_cast<std::size_t>(i) + 1];
      for (int r = 0; r < 3; ++r) {
        int p = outer[3 * i + r];
        for (int k = begin; k < end; ++k)
          for (int c = 0; c < 3; ++c) inner[p++] = 3 * col[static_cast<std::size_t>(k)] + c;
        outer[3 * i + r + 1] = p;
      }
    }
  }
  const int* outer = K.outerIndexPtr();
  double* value = K.valuePtr();
  parallel_for_each(static_cast<std::size_t>(n), 256, [&](std::size_t i) {
    const int begin = row_start[i], end = row_start[i + 1];
    for (int k = begin; k < end; ++k) {
      const Mat3 F = filter.filtered(static_cast<Eigen::Index>(i), col[static_cast<std::size_t>(k)],
                                     A.blocks()[static_cast<std::size_t>(k)]);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) value[outer[3 * i + static_cast<std::size_t>(r)] + 3 * (k - begin) + c] = F(r, c);
    }
  });
}

void set_inverse_diagonal(Level& level) {
  level.inv_diag = level.A.diagonal().cwiseInverse();
}

// The near null space at level 0: per node, the three translations and the three rotations
// e_k x (x_i - centroid), filtered by S_i (3n x 6).
Eigen::MatrixXd rigid_motions(const Points& x, const NodeFilter& filter) {
  const Eigen::Index n = x.rows();
  const Vec3 centroid = x.colwise().mean().transpose();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3 * n, 6);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 p = x.row(i).transpose() - centroid;
    Eigen::Matrix<double, 3, 6> b;
    b.leftCols<3>().setIdentity();
    for (int k = 0; k < 3; ++k) b.col(3 + k) = Vec3::Unit(k).cross(p);
    if (filter.constrained(i)) b = filter.S(i) * b;
    B.middleRows<3>(3 * i) = b;
  }
  return B;
}

// One coarsening: aggregates of `fine`'s nodes, its prolongator P (and R = P^T) stored in `fine`,
// the coarse matrix in `coarse`, and the coarse nodes (one per aggregate) and near null space.
// Returns false when the graph has no aggregate.
bool coarsen(Level& fine, const std::vector<int>& node_start, const Eigen::MatrixXd& B, Level& coarse,
             std::vector<int>& coarse_node_start, Eigen::MatrixXd& coarse_B) {
  const amg::NodeGraph graph = amg::node_graph(fine.A, node_start);
  std::vector<int> aggregate_of;
  const int count = amg::aggregate(graph, aggregate_of);
  if (count == 0) return false;
  std::vector<std::vector<int>> dofs(static_cast<std::size_t>(count));  // per aggregate, ascending
  for (std::size_t a = 0; a + 1 < node_start.size(); ++a)
    if (aggregate_of[a] >= 0)
      for (int d = node_start[a]; d < node_start[a + 1]; ++d) dofs[static_cast<std::size_t>(aggregate_of[a])].push_back(d);

  // B_a = Q_a R_a by a thin SVD, B_a = U S V^T: Q_a = U_k, R_a = S_k V_k^T with k the numerical
  // rank (an aggregate of two nodes cannot tell the rotation about their axis: rank 5 of 6).
  std::vector<Eigen::MatrixXd> Q(static_cast<std::size_t>(count)), R(static_cast<std::size_t>(count));
  parallel_for_each(static_cast<std::size_t>(count), 64, [&](std::size_t a) {
    Eigen::MatrixXd Ba(static_cast<Eigen::Index>(dofs[a].size()), B.cols());
    for (std::size_t r = 0; r < dofs[a].size(); ++r) Ba.row(static_cast<Eigen::Index>(r)) = B.row(dofs[a][r]);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Ba, Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& s = svd.singularValues();
    Eigen::Index k = 0;
    while (k < s.size() && s[k] > 1e-10 * s[0]) ++k;
    Q[a] = svd.matrixU().leftCols(k);
    R[a] = s.head(k).asDiagonal() * svd.matrixV().leftCols(k).transpose();
  });
  coarse_node_start.assign(1, 0);
  for (std::size_t a = 0; a < Q.size(); ++a)
    coarse_node_start.push_back(coarse_node_start.back() + static_cast<int>(Q[a].cols()));
  const int coarse_dofs = coarse_node_start.back();
  if (coarse_dofs == 0) return false;

  std::vector<Eigen::Triplet<double>> entries;
  coarse_B.resize(coarse_dofs, B.cols());
  for (std::size_t a = 0; a < Q.size(); ++a) {
    for (std::size_t r = 0; r < dofs[a].size(); ++r)
      for (Eigen::Index c = 0; c < Q[a].cols(); ++c)
        entries.emplace_back(dofs[a][r], coarse_node_start[a] + static_cast<int>(c), Q[a](static_cast<Eigen::Index>(r), c));
    coarse_B.middleRows(coarse_node_start[a], R[a].rows()) = R[a];
  }
  Csr P0(fine.A.rows(), coarse_dofs);
  P0.setFromTriplets(entries.begin(), entries.end());

  // P = (I - w D^-1 A) P0, w = 4 / (3 lambda_max): the damped Jacobi step that smooths P0's
  // columns (Vanek et al. 1996, section 4).
  const double w = 4.0 / (3.0 * fine.lambda_max);
  const Csr AP0 = fine.A * P0;
  const Csr smoothing = (-w * fine.inv_diag).asDiagonal() * AP0;
  fine.P = P0 + smoothing;
  fine.P.makeCompressed();
  fine.R = fine.P.transpose();
  fine.R.makeCompressed();
  const Csr AP = fine.A * fine.P;
  coarse.A = fine.R * AP;
  coarse.A.makeCompressed();
  return true;
}

// The dense LDL^T of the last level, its exact solve in the V-cycle; when that level is not found
// definite, direct stays false and the V-cycle smooths it instead.
void factorize_coarsest(AmgPreconditioner::Hierarchy& h) {
  h.coarsest.compute(Eigen::MatrixXd(h.levels.back().A));
  h.direct = h.coarsest.info() == Eigen::Success && (h.coarsest.vectorD().array() > 0).all();
}

}  // namespace

AmgPreconditioner::AmgPreconditioner() = default;
AmgPreconditioner::~AmgPreconditioner() = default;
AmgPreconditioner::AmgPreconditioner(AmgPreconditioner&&) noexcept = default;
AmgPreconditioner& AmgPreconditioner::operator=(AmgPreconditioner&&) noexcept = default;

void AmgPreconditioner::setup(const BlockSparseMatrix& A, const NodeConstraints& fixed, const Points& x) {
  if (A.storage() != BlockSparseMatrix::Storage::Full)
    throw std::logic_error("amg: the matrix must store both triangles (its rows are read whole)");
  if (x.rows() != A.rows()) throw std::invalid_argument("amg: the positions and the matrix differ in node count");
  auto h = std::make_unique<Hierarchy>();
  h->nodes = A.rows();
  h->blocks = A.block_count();
  filter_.assign(A.rows(), fixed);
  h->levels.emplace_back();
  fill_level0(A, filter_, true, h->levels[0].A);

  std::vector<int> node_start(static_cast<std::size_t>(A.rows()) + 1);
  for (std::size_t i = 0; i < node_start.size(); ++i) node_start[i] = 3 * static_cast<int>(i);
  Eigen::MatrixXd B = rigid_motions(x, filter_);
  for (;;) {
    Level& fine = h->levels.back();
    set_inverse_diagonal(fine);
    amg::estimate_lambda_max(fine, kSetupPowerIterations);
    if (fine.A.rows() <= kCoarsestDofs || static_cast<int>(h->levels.size()) == kMaxLevels) break;
    Level coarse;
    std::vector<int> coarse_node_start;
    Eigen::MatrixXd coarse_B;
    if (!coarsen(fine, node_start, B, coarse, coarse_node_start, coarse_B) ||
        coarse.A.rows() > kMinShrink * static_cast<double>(fine.A.rows())) {
      fine.P = Csr();
      fine.R = Csr();
      break;
    }
    h->levels.push_back(std::move(coarse));
    node_start.swap(coarse_node_start);
    B.swap(coarse_B);
  }
  h->direct = false;
  if (h->levels.back().A.rows() <= kCoarsestDofs) factorize_coarsest(*h);
  h_ = std::move(h);
}

bool AmgPreconditioner::ready_for(const BlockSparseMatrix& A) const {
  return h_ && h_->nodes == A.rows() && h_->blocks == A.block_count();
}

void AmgPreconditioner::refresh(const BlockSparseMatrix& A, const NodeConstraints& fixed) {
  if (!ready_for(A)) throw std::logic_error("amg: refresh on a pattern the hierarchy was not built for");
  filter_.assign(A.rows(), fixed);
  Level& level0 = h_->levels[0];
  fill_level0(A, filter_, false, level0.A);
  set_inverse_diagonal(level0);
  amg::estimate_lambda_max(level0, kRefreshPowerIterations);
  if (h_->levels.size() == 1 && h_->direct) factorize_coarsest(*h_);  // one level only: its factor is K's
}

std::vector<Eigen::Index> AmgPreconditioner::level_dofs() const {
  std::vector<Eigen::Index> dofs;
  if (h_)
    for (const amg::Level& l : h_->levels) dofs.push_back(l.A.rows());
  return dofs;
}

}  // namespace invfem
