// Fork-join over std::thread (src/parallel.h). The only file of the core that starts threads.
#include "parallel.h"

#include "stltopo/read.h"

#include <atomic>

#if STLTOPO_THREADS
#include <thread>
#endif

namespace stltopo::detail {

namespace {
std::atomic<size_t> gGrainForTesting{0};
std::atomic<uint64_t> gSplits{0};
}  // namespace

void setParallelGrainForTesting(size_t items) { gGrainForTesting.store(items, std::memory_order_relaxed); }

size_t parallelGrain(size_t dflt) {
  size_t g = gGrainForTesting.load(std::memory_order_relaxed);
  return g ? g : dflt;
}

unsigned threadCount(unsigned requested) {
#if STLTOPO_THREADS
  unsigned n = requested;
  if (n == 0) {
    n = std::thread::hardware_concurrency();
    if (n == 0) n = 1;
  }
  return n < kMaxThreads ? n : kMaxThreads;
#else
  (void)requested;
  return 1;
#endif
}

uint64_t parallelSplitsForTesting() { return gSplits.load(std::memory_order_relaxed); }

void runPartsImpl(unsigned n, PartFn fn, void* ctx) {
  gSplits.fetch_add(1, std::memory_order_relaxed);
#if STLTOPO_THREADS
  std::thread threads[kMaxThreads];
  bool started[kMaxThreads] = {};
  for (unsigned i = 1; i < n && i < kMaxThreads; ++i) {
    try {
      threads[i] = std::thread(fn, ctx, i);
      started[i] = true;
    } catch (...) {  // no thread (resources, memory): the part runs on the caller below
    }
  }
  fn(ctx, 0);
  for (unsigned i = 1; i < n; ++i) {
    if (i < kMaxThreads && started[i]) threads[i].join();
    else fn(ctx, i);
  }
#else
  for (unsigned i = 0; i < n; ++i) fn(ctx, i);
#endif
}

}  // namespace stltopo::detail

namespace stltopo {
void setParallelGrainForTesting(size_t items) { detail::setParallelGrainForTesting(items); }
uint64_t parallelSplitsForTesting() { return detail::parallelSplitsForTesting(); }
}  // namespace stltopo
