#pragma once
// The one parallel element loop of invfem (every force's per-element pass uses it). body(e) runs
// for every e in [0, n), in TBB chunks of `grain` elements. The body must write only element e's
// own slots; sums over elements are taken afterwards, sequentially in element order (the scatter
// helpers of the kernels), so results are bit-identical whatever the thread count. A loop of at
// most one grain runs on the calling thread.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>

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

// body(begin, end) for the ranges [0, size), [size, 2 size), ... covering [0, n), at least
// `ranges_per_task` ranges a task: for loops whose body works on a run of rows at once (a SIMD
// kernel, an Eigen block).
template <class Body>
void parallel_for_ranges(std::size_t n, std::size_t size, const Body& body, std::size_t ranges_per_task = 1) {
  parallel_for_each((n + size - 1) / size, ranges_per_task,
                    [&](std::size_t c) { body(c * size, std::min(n, (c + 1) * size)); });
}

// compute(begin, end, slot) for the ranges [0, size), [size, 2 size), ... covering [0, n), in
// parallel, and consume(begin, end, slot) of each range after its compute, one range at a time, in
// range order (TBB's pipeline). At most `in_flight` ranges are between the two, and as they leave
// in order the ranges alive at once are consecutive: slot = (range index) mod in_flight is unique
// among them, so `in_flight` buffers of one range each hold every result between compute and
// consume. For an element pass and its serial scatter: the scatter sees the elements in order, so
// its sums have the serial loop's bits whatever the thread count; it reads each range's results
// from cache (a buffer of a few ranges, not one result per element from memory), beside the later
// ranges' computes.
template <class Compute, class Consume>
void parallel_ranges_in_order(std::size_t n, std::size_t size, std::size_t in_flight, const Compute& compute,
                              const Consume& consume) {
  const std::size_t count = (n + size - 1) / size;
  if (count <= 1) {  // one range: no pipeline
    if (n > 0) {
      compute(std::size_t{0}, n, std::size_t{0});
      consume(std::size_t{0}, n, std::size_t{0});
    }
    return;
  }
  std::size_t next = 0;
  tbb::parallel_pipeline(
      in_flight,
      tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                          [&](tbb::flow_control& fc) -> std::size_t {
                                            if (next == count) fc.stop();
                                            return next++;
                                          }) &
          tbb::make_filter<std::size_t, std::size_t>(tbb::filter_mode::parallel,
                                                     [&](std::size_t c) {
                                                       compute(c * size, std::min(n, (c + 1) * size), c % in_flight);
                                                       return c;
                                                     }) &
          tbb::make_filter<std::size_t, void>(tbb::filter_mode::serial_in_order, [&](std::size_t c) {
            consume(c * size, std::min(n, (c + 1) * size), c % in_flight);
          }));
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
