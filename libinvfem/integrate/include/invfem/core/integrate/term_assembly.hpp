#pragma once
// One term of the forces' linearization at their current state, the stiffness K
// (Force::stiffness_matrices) or the damping C (Force::damping_matrices), added into a block-sparse
// matrix (3x3 BSR, block_sparse.hpp): per force its element set and the set's one scatter
// (ElementScatter). A force that forms its matrices by ranges in the Upper form
// (Force::stiffness_range, damping_range: tet solids without a fiber) has them added in element
// order as each range is formed (the in-order plan); its set holds node lists only
// (Force::stiffness_pattern, damping_pattern), so its 720 bytes a tet of element matrices are never
// held, not even once to learn the pattern. The others form their whole set, which is gathered.
// The implicit step assembles K and C with it (implicit_step_potential.cpp, implicit_step.cpp),
// the ITF04 step C (newmark_step.cpp).
#include <vector>

#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/math/element_matrices.hpp"
#include "invfem/core/integrate/force.hpp"

namespace invfem {

class TermAssembly {
 public:
  enum class Term { Stiffness, Damping };
  explicit TermAssembly(Term term = Term::Stiffness) : term_(term) {}

  // Learns every force's element set of the term (node lists and form, no values). given(k): force
  // k gives its matrices (its *_pattern returned true).
  void learn(const std::vector<Force*>& forces);
  std::size_t forces() const { return sets_.size(); }
  bool given(std::size_t k) const { return given_[k] != 0; }
  bool all_given() const;
  // The given forces' elements in all.
  Eigen::Index elements() const { return elements_; }
  // The given forces' sets, appended: what a pattern holding the term needs (BlockSparseMatrix(n, sets)).
  // Only before plan(), which drops the lists of the sets formed by ranges.
  void append_sets(std::vector<const ElementMatrices*>& sets) const;
  // Plans each given set's scatter into the pattern of A, which must hold the sets. Throws
  // std::logic_error when it does not (ElementScatter).
  void plan(const std::vector<Force*>& forces, const BlockSparseMatrix& A);
  // A's diagonal and upper triangle += w times the term of the given forces at their current state
  // (in force order; complete the lower triangle with A.mirror_lower() after the last term). A has
  // the pattern plan() saw; forces are the ones learn() saw.
  void add_upper(const std::vector<Force*>& forces, double w, BlockSparseMatrix& A);

 private:
  bool pattern(const Force& f, ElementMatrices& out) const;
  bool matrices(const Force& f, ElementMatrices& out) const;
  bool range(const Force& f, std::size_t begin, std::size_t end, double* out) const;

  Term term_;
  std::vector<char> given_;               // per force
  std::vector<ElementMatrices> sets_;     // per force (empty when not given)
  std::vector<ElementScatter> scatter_;   // per force (unused when not given)
  Eigen::Index elements_ = 0;
};

}  // namespace invfem
