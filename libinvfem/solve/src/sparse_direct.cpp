#include "invfem/core/solve/sparse_direct.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <dlfcn.h>

#include <mutex>
#include <stdexcept>

namespace invfem {

namespace {

// CHOLMOD's supernodal factorization runs serially: its OpenMP loops (their thread count fixed
// when CHOLMOD was built) and OpenBLAS's own threads busy-wait against the TBB workers that
// assemble the forces on the same cores, which made the factorization slower, not faster, on 2
// cores. max-active-levels 0 makes every OpenMP region of the process run on one thread (invfem
// has no other); both calls are looked up at run time, so another BLAS or an OpenMP-free CHOLMOD
// is simply left as it is.
void run_cholmod_serially() {
  static std::once_flag once;
  std::call_once(once, [] {
    using SetInt = void (*)(int);
    if (auto set = reinterpret_cast<SetInt>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
    if (auto set = reinterpret_cast<SetInt>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))) set(0);
  });
}

}  // namespace

struct FilteredDirectSolver::Factorization {
  Eigen::SparseMatrix<double> K;  // 3n x 3n, lower triangle of K only
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
};

FilteredDirectSolver::FilteredDirectSolver() = default;
FilteredDirectSolver::~FilteredDirectSolver() = default;
FilteredDirectSolver::FilteredDirectSolver(FilteredDirectSolver&&) noexcept = default;
FilteredDirectSolver& FilteredDirectSolver::operator=(FilteredDirectSolver&&) noexcept = default;

void FilteredDirectSolver::analyze(const BlockSparseMatrix& A) {
  if (A.storage() != BlockSparseMatrix::Storage::Full)
    throw std::logic_error("direct solver: the matrix must store both triangles (its rows are read whole)");
  const Eigen::Index n = A.rows();
  const std::vector<int>& row_start = A.row_start();
  const std::vector<int>& col = A.columns();
  nodes_ = n;
  blocks_ = A.block_count();
  factorized_ = false;

  // Column 3 j + c of K's lower triangle holds, block by block along block row j of A from its
  // diagonal block on (columns i >= j, ascending), rows 3 i + r with 3 i + r >= 3 j + c. Each block
  // row starts at its diagonal block: columns are ascending and the diagonal is always present.
  const Eigen::Index N = 3 * n;
  std::vector<int> outer(static_cast<std::size_t>(N) + 1, 0);
  for (Eigen::Index j = 0; j < n; ++j) {
    int upper_blocks = 0;
    for (int k = row_start[static_cast<std::size_t>(j)]; k < row_start[static_cast<std::size_t>(j) + 1]; ++k)
      if (col[static_cast<std::size_t>(k)] >= j) ++upper_blocks;
    for (int c = 0; c < 3; ++c)  // the diagonal block contributes 3 - c entries, the others 3
      outer[static_cast<std::size_t>(3 * j + c) + 1] = 3 * upper_blocks - c;
  }
  for (std::size_t s = 0; s < static_cast<std::size_t>(N); ++s) outer[s + 1] += outer[s];
  const std::size_t nnz = static_cast<std::size_t>(outer.back());

  f_ = std::make_unique<Factorization>();
  Eigen::SparseMatrix<double>& K = f_->K;
  K.resize(N, N);
  K.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  source_.resize(nnz);
  block_row_.resize(blocks_);
  std::size_t p = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const int begin = row_start[static_cast<std::size_t>(j)], end = row_start[static_cast<std::size_t>(j) + 1];
    for (int k = begin; k < end; ++k) block_row_[static_cast<std::size_t>(k)] = static_cast<int>(j);
    for (int c = 0; c < 3; ++c) {
      for (int k = begin; k < end; ++k) {
        const int i = col[static_cast<std::size_t>(k)];
        if (i < j) continue;
        for (int r = (i == j ? c : 0); r < 3; ++r, ++p) {
          K.innerIndexPtr()[p] = 3 * i + r;
          source_[p] = 9 * k + 3 * r + c;  // A_ji(c, r), column-major
        }
      }
    }
  }
  if (p != nnz) throw std::logic_error("sparse direct: the pattern of A is not symmetric with its diagonal");
  std::copy(outer.begin(), outer.end(), K.outerIndexPtr());
  std::fill(K.valuePtr(), K.valuePtr() + nnz, 0.0);

  filtered_.assign(blocks_, Mat3::Zero());
  rhs_.resize(N);
  sol_.resize(N);
  run_cholmod_serially();
  cholmod_common& cm = f_->llt.cholmod();
  cm.print = 0;  // its warnings (a matrix not definite) are read from the status instead
  f_->llt.analyzePattern(K);  // CHOLMOD's default: AMD, and METIS where AMD fills in much
  if (cm.status < CHOLMOD_OK) throw std::runtime_error("sparse direct: CHOLMOD's analysis of K failed (out of memory?)");
}

bool FilteredDirectSolver::analyzed_for(const BlockSparseMatrix& A) const {
  return f_ && nodes_ == A.rows() && blocks_ == A.block_count();
}

bool FilteredDirectSolver::factorize(const BlockSparseMatrix& A, const NodeConstraints& fixed) {
  if (!analyzed_for(A)) throw std::logic_error("sparse direct: factorize on a pattern that was not analyzed");
  factorized_ = false;
  filter_.assign(nodes_, fixed);
  // Filtered blocks S_j A_ji S_i (plus I - S_j on the diagonal), then K's lower triangle gathered
  // from them.
  const std::vector<Mat3>& blocks = A.blocks();
  const std::vector<int>& col = A.columns();
  for (std::size_t k = 0; k < blocks_; ++k) {
    const int j = block_row_[k], i = col[k];
    if (i < j) continue;
    filtered_[k] = filter_.filtered(j, i, blocks[k]);
  }
  const double* f = filtered_.front().data();
  double* value = f_->K.valuePtr();
  const std::size_t nnz = source_.size();
  for (std::size_t p = 0; p < nnz; ++p) value[p] = f[source_[p]];

  // A matrix not definite stops LL^T at its first nonpositive pivot (info() NumericalIssue, CHOLMOD's
  // status CHOLMOD_NOT_POSDEF); the analysis stays valid for the next factorize().
  f_->llt.factorize(f_->K);
  if (f_->llt.cholmod().status < CHOLMOD_OK) throw std::runtime_error("sparse direct: CHOLMOD's factorization failed (out of memory?)");
  if (f_->llt.info() != Eigen::Success) return false;
  factorized_ = true;
  return true;
}

void FilteredDirectSolver::solve(const Points& r, Points& d) {
  if (!factorized_) throw std::logic_error("sparse direct: solve before a successful factorize");
  const Eigen::Index n = nodes_;
  for (Eigen::Index i = 0; i < n; ++i) {
    Vec3 ri = r.row(i).transpose();
    if (filter_.constrained(i)) ri = filter_.S(i) * ri;
    rhs_.segment<3>(3 * i) = ri;
  }
  sol_ = f_->llt.solve(rhs_);
  d.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    Vec3 di = sol_.segment<3>(3 * i);
    // d = S d in exact arithmetic; the filter removes the rounding left in constrained components.
    if (filter_.constrained(i)) di = filter_.S(i) * di;
    d.row(i) = di.transpose();
  }
}

}  // namespace invfem
