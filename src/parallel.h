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

// Runs fn(b, e) over consecutive ranges [b, e) that cover [begin, end) in order, for loops
// that run once over a whole mesh. In wasm the ranges have at most `chunk` items and each is
// a call of a function that is never inlined: V8 runs a function in the baseline code it
// compiled first (Liftoff) until the call returns, as it has no on-stack replacement for
// wasm, and compiles optimized code for the calls that come after the function got hot. A
// loop over a million items in one call would run unoptimized to its end (2-3x slower); in
// chunks, the first few run in the baseline code and the rest in the optimized code
// (bench/PROFILE.md, *Chunked loops*). Natively there is no such tiering, and the whole
// range is one call (inlined): calls per chunk made the topology up to 20% slower. Tests
// set a chunk size natively too (setChunkItemsForTesting), so that the chunked paths run.
// fn(b, e) must do for [b, e) exactly what the loop does there: the result is the loop's.
inline constexpr size_t kChunkItems = 16384;
// The native chunk size (0: none, one call); test-only, as setParallelGrainForTesting.
void setChunkItemsForTesting(size_t items);
size_t chunkItemsForTesting();
template <class F>
#if defined(__GNUC__)
__attribute__((noinline))
#endif
void chunkBody(F&& fn, size_t b, size_t e) {
  fn(b, e);
}
template <class F>
void inChunks(size_t begin, size_t end, size_t chunk, F&& fn) {
  // Two call sites: binaryen (Emscripten's optimizer after LLVM) inlines a function that
  // has a single caller, whatever its size and its noinline attribute.
  if (begin >= end) return;
  size_t e = end - begin > chunk ? begin + chunk : end;
  chunkBody(fn, begin, e);
  for (begin = e; begin < end; begin = e) {
    e = end - begin > chunk ? begin + chunk : end;
    chunkBody(fn, begin, e);
  }
}
template <class F>
void forChunks(size_t begin, size_t end, F&& fn, size_t chunk = kChunkItems) {
#if defined(__EMSCRIPTEN__)
  inChunks(begin, end, chunk, fn);
#else
  if (const size_t c = chunkItemsForTesting(); c > 0) {
    inChunks(begin, end, c, fn);
  } else if (begin < end) {
    (void)chunk;
    fn(begin, end);
  }
#endif
}

// forChunks when kChunked, else fn(begin, end) in one call: for code that has both versions
// as separate instantiations, so that a wasm module that calls only the one-call version
// holds no chunked code (the core module's download budget: src/topology.cpp, buildTopology).
template <bool kChunked, class F>
void forChunksIf(size_t begin, size_t end, F&& fn, size_t chunk = kChunkItems) {
  if constexpr (kChunked)
    forChunks(begin, end, fn, chunk);
  else if (begin < end)
    fn(begin, end);
}

// fn(i) for every i in [begin, end), in order; in wasm one out-of-line call each (see
// forChunks): for a loop whose iterations are big.
template <class F>
void forEachCall(size_t begin, size_t end, F&& fn) {
#if defined(__EMSCRIPTEN__)
  inChunks(begin, end, 1, [&](size_t i, size_t) { fn(i); });
#else
  for (size_t i = begin; i < end; ++i) fn(i);
#endif
}

}  // namespace stltopo::detail
