#include "invfem/core/integrate/term_assembly.hpp"

namespace invfem {

bool TermAssembly::pattern(const Force& f, ElementMatrices& out) const {
  return term_ == Term::Stiffness ? f.stiffness_pattern(out) : f.damping_pattern(out);
}

bool TermAssembly::matrices(const Force& f, ElementMatrices& out) const {
  return term_ == Term::Stiffness ? f.stiffness_matrices(out) : f.damping_matrices(out);
}

bool TermAssembly::range(const Force& f, std::size_t begin, std::size_t end, double* out) const {
  return term_ == Term::Stiffness ? f.stiffness_range(begin, end, out) : f.damping_range(begin, end, out);
}

void TermAssembly::learn(const std::vector<Force*>& forces) {
  sets_.assign(forces.size(), ElementMatrices{});
  given_.assign(forces.size(), 0);
  scatter_.assign(forces.size(), ElementScatter{});
  elements_ = 0;
  for (std::size_t k = 0; k < forces.size(); ++k) {
    given_[k] = pattern(*forces[k], sets_[k]) ? 1 : 0;
    if (given_[k]) elements_ += sets_[k].count();
  }
}

bool TermAssembly::all_given() const {
  for (char g : given_)
    if (!g) return false;
  return true;
}

void TermAssembly::append_sets(std::vector<const ElementMatrices*>& sets) const {
  for (std::size_t k = 0; k < sets_.size(); ++k)
    if (given_[k]) sets.push_back(&sets_[k]);
}

void TermAssembly::plan(const std::vector<Force*>& forces, const BlockSparseMatrix& A) {
  for (std::size_t k = 0; k < sets_.size(); ++k) {
    if (!given_[k]) continue;
    // An empty range asks whether the force forms its matrices by ranges.
    const bool ranges = sets_[k].form == ElementMatrices::Form::Upper && range(*forces[k], 0, 0, nullptr);
    scatter_[k] = ElementScatter(sets_[k], A, ranges ? ElementScatter::Plan::InOrder : ElementScatter::Plan::Gather);
    if (ranges) sets_[k] = ElementMatrices{};  // the plan holds where each block goes: the lists can go
  }
}

void TermAssembly::add_upper(const std::vector<Force*>& forces, double w, BlockSparseMatrix& A) {
  for (std::size_t k = 0; k < sets_.size(); ++k) {
    if (!given_[k]) continue;
    if (scatter_[k].plan() == ElementScatter::Plan::InOrder) {
      const Force& force = *forces[k];
      auto form = [this, &force](std::size_t begin, std::size_t end, double* values) {
        range(force, begin, end, values);
      };
      scatter_[k].add_upper(form, w, A);
      continue;
    }
    matrices(*forces[k], sets_[k]);
    scatter_[k].add_upper(sets_[k], w, A);
  }
}

}  // namespace invfem
