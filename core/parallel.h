// parallel.h — one parallel loop for host work outside Embree.
//
// parallel_for_each_index(n, fn) runs fn(i) for i in [0, n) on TBB's workers
// (which the threads setting limits); parallel_both(a, b) runs a() and b()
// there, perhaps at once, and returns when both have. In a ThreadSanitizer build it runs serially on the
// calling thread: TBB's task hand-offs synchronise inside uninstrumented libtbb
// and would be reported as races (scripts/sanitize says what that leaves
// unchecked).
#pragma once

#include <cstddef>

#include "core/sanitizers.h"

#ifndef PMC_UNDER_TSAN
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#endif

namespace pmc {

template <typename Fn>
void parallel_for_each_index(size_t n, const Fn& fn) {
#ifdef PMC_UNDER_TSAN
  for (size_t i = 0; i < n; ++i) fn(i);
#else
  tbb::parallel_for(size_t(0), n, [&](size_t i) { fn(i); });
#endif
}

template <typename A, typename B>
void parallel_both(const A& a, const B& b) {
#ifdef PMC_UNDER_TSAN
  a();
  b();
#else
  tbb::parallel_invoke(a, b);
#endif
}

}  // namespace pmc
