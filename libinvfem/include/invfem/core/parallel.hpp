#pragma once
// The one parallel element loop of invfem (every force's per-element pass uses it). body(e) runs
// for every e in [0, n), in TBB chunks of `grain` elements. The body must write only element e's
// own slots; sums over elements are taken afterwards, sequentially in element order (the scatter
// helpers of the kernels), so results are bit-identical whatever the thread count. A loop of at
// most one grain runs on the calling thread.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace invfem {

template <class Body> void parallel_for_each(std::size_t n, std::size_t grain, const Body& body) {
  if (n <= grain) {  // one chunk: run it here rather than wake the workers for it
    for (std::size_t e = 0; e < n; ++e) body(e);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t e = r.begin(); e != r.end(); ++e) body(e);
  });
}

// body(begin, end) for the ranges [0, size), [size, 2 size), ... covering [0, n), one range a task:
// for loops whose body works on a run of rows at once (a SIMD kernel, an Eigen block).
template <class Body> void parallel_for_ranges(std::size_t n, std::size_t size, const Body& body) {
  parallel_for_each((n + size - 1) / size, 1, [&](std::size_t c) { body(c * size, std::min(n, (c + 1) * size)); });
}

// The sum of term(i) over i in [0, n): the terms formed in parallel into `terms` (the caller's
// buffer, reused from call to call: no allocation once it has grown), then added in index order,
// so the bits do not depend on the thread count. For energies whose terms cost more than the add.
template <class Term>
double parallel_ordered_sum(std::size_t n, std::size_t grain, std::vector<double>& terms, const Term& term) {
  terms.resize(n);
  parallel_for_each(n, grain, [&](std::size_t i) { terms[i] = term(i); });
  double sum = 0;
  for (const double t : terms) sum += t;
  return sum;
}

}  // namespace invfem
