// Fork-join over a few threads, for the stages that split into independent parts with a
// deterministic merge (issue 24): every caller's result is the same for every thread count.
// Private (not installed).
//
// The single-threaded wasm modules have no threads (Emscripten without pthreads): there
// STLTOPO_THREADS is 0, threadCount() is always 1 and runParts() runs the parts one after
// another on the caller. The threaded ones (-pthread, bindings/CMakeLists.txt) have them; the
// bindings cap `threads` at Emscripten's preallocated worker pool (bindings/session.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

#if !defined(STLTOPO_THREADS)
#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
#define STLTOPO_THREADS 0
#else
#define STLTOPO_THREADS 1
#endif
#endif

namespace stltopo::detail {

// The number of threads a stage uses for the option value `requested`: 0 = the machine's
// hardware threads (1 when unknown), otherwise `requested`, capped at kMaxThreads. Always 1
// without thread support.
inline constexpr unsigned kMaxThreads = 64;
unsigned threadCount(unsigned requested);

// The smallest number of work items (records, triangles, vertices: what the stage counts)
// a part is given before a stage splits; 0 = each stage's own default. Test-only: the
// tests set 1 so that the parallel paths run on the small fixtures too. Not thread-safe
// against a read running at the same time.
void setParallelGrainForTesting(size_t items);
// How many times work was split into two or more parts (runParts), since the start.
uint64_t parallelSplitsForTesting();
// The grain a stage uses: the testing value when set, else `dflt`.
size_t parallelGrain(size_t dflt);

// How many parts (at most `threads`) `items` work items split into with at least `grain`
// items each; 1 when the stage should run its single-threaded path.
inline unsigned partsFor(unsigned threads, size_t items, size_t grain) {
#if !STLTOPO_THREADS
  (void)threads, (void)items, (void)grain;
  return 1;  // a constant: the compiler drops the threaded branches of the wasm build
#endif
  if (threads <= 1) return 1;
  size_t p = grain ? items / grain : items;
  if (p > threads) p = threads;
  return p >= 2 ? unsigned(p) : 1;
}

// Part i of n of [0, items): [begin, end), contiguous, in order, sizes differing by <= 1.
inline size_t partBegin(size_t items, unsigned n, unsigned i) {
  return items / n * i + (i < items % n ? i : items % n);
}

// Runs fn(i) for every i in [0, n): fn(0) on the calling thread, the others on threads of
// their own; returns when all have returned. When a thread cannot be started, its part runs
// on the caller after the others were started, so the parts must not wait for each other.
// fn must not throw.
using PartFn = void (*)(void* ctx, unsigned part);
void runPartsImpl(unsigned n, PartFn fn, void* ctx);
template <class F>
void runParts(unsigned n, F&& fn) {
  if (n <= 1) {
    if (n == 1) fn(0u);
    return;
  }
  runPartsImpl(
      n, [](void* ctx, unsigned part) { (*static_cast<F*>(ctx))(part); }, &fn);
}

}  // namespace stltopo::detail
