// Fork-join over std::thread (src/parallel.h). The only file of the core that starts threads.
#include "parallel.h"

#include "stltopo/read.h"

#include <atomic>
#include <new>

#if STLTOPO_THREADS
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#if defined(__EMSCRIPTEN__)
#include <pthread.h>
#endif
#endif

namespace stltopo::detail {

namespace {
std::atomic<size_t> gGrainForTesting{0};
std::atomic<uint64_t> gSplits{0};
std::atomic<size_t> gChunkForTesting{0};
}  // namespace

void setParallelGrainForTesting(size_t items) { gGrainForTesting.store(items, std::memory_order_relaxed); }

void setChunkItemsForTesting(size_t items) { gChunkForTesting.store(items, std::memory_order_relaxed); }
size_t chunkItemsForTesting() { return gChunkForTesting.load(std::memory_order_relaxed); }

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

#if STLTOPO_THREADS
namespace {

// Starts fn(arg) on a detached thread; false when none could be started (resources,
// memory; in the threaded wasm build also an exhausted worker pool: Emscripten's
// PTHREAD_POOL_SIZE_STRICT=2 makes that EAGAIN, and the library has no exceptions there).
template <class Fn>
bool startDetached(Fn* fn) {
#if defined(__EMSCRIPTEN__)
  pthread_t t;
  auto entry = [](void* p) -> void* {
    auto* f = static_cast<Fn*>(p);
    (*f)();
    delete f;
    return nullptr;
  };
  if (pthread_create(&t, nullptr, entry, fn) != 0) {
    delete fn;
    return false;
  }
  pthread_detach(t);
  return true;
#else
  try {
    std::thread([fn] {
      (*fn)();
      delete fn;
    }).detach();
  } catch (...) {
    delete fn;
    return false;
  }
  return true;
#endif
}

// Waits up to about kSpinMicros for ready() to hold, without sleeping; true when it did. A
// thread that sleeps on a condition variable is woken through the kernel, and on a virtual
// machine an idle virtual CPU's wake-up took 70-230 us here (a split of two empty parts after
// 0.7 ms of other work), against 1-15 us for one that is still spinning: the stages split
// dozens of times a load, with short one-thread stretches between the splits. Natively only.
#if !defined(__EMSCRIPTEN__)
constexpr int kSpinMicros = 1000;
template <class Ready>
bool spinFor(Ready ready) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(kSpinMicros);
  for (;;) {
    for (int i = 0; i < 64; ++i) {
      if (ready()) return true;
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
    if (std::chrono::steady_clock::now() >= until) return false;
  }
}
#endif

// The threads of the process's parts: started on first use, kept for the next split (a
// thread start and its stack's unmapping cost more than many a part), never ended (the
// pool is never destroyed, so no thread is joined at exit). One split at a time uses it;
// a split that finds it busy (another thread of the caller's) starts threads of its own.
// Natively, between splits and while the caller waits for the parts, threads spin up to 1 ms
// before they sleep (spinFor), unless the pool has more threads than the machine has cores.
struct Pool {
  std::mutex busy;  // held by the split that uses the pool
  std::mutex m;
  std::condition_variable wake, finished;
  PartFn fn = nullptr;
  void* ctx = nullptr;
  unsigned parts = 0, nWorkers = 0;
  std::atomic<unsigned> pending{0};
  std::atomic<uint64_t> generation{0};
  std::atomic<bool> spin{false};  // the pool's threads fit on the machine's cores (natively)

  void work(unsigned id) {  // worker `id` (1-based) runs part id of each split that has one
    uint64_t seen = 0;
    for (;;) {
#if !defined(__EMSCRIPTEN__)
      if (spin.load(std::memory_order_relaxed))
        spinFor([&] { return generation.load(std::memory_order_acquire) != seen; });
#endif
      std::unique_lock<std::mutex> lock(m);
      wake.wait(lock, [&] { return generation.load(std::memory_order_relaxed) != seen; });
      seen = generation.load(std::memory_order_relaxed);
      if (id >= parts) continue;
      PartFn f = fn;
      void* c = ctx;
      lock.unlock();
      f(c, id);
      lock.lock();
      if (pending.fetch_sub(1) == 1) finished.notify_one();
    }
  }

  // Runs parts [0, n); false when the pool is busy (nothing ran).
  bool run(unsigned n, PartFn f, void* c) {
    std::unique_lock<std::mutex> job(busy, std::try_to_lock);
    if (!job.owns_lock()) return false;
    while (nWorkers + 1 < n && nWorkers + 1 < kMaxThreads) {
      unsigned id = nWorkers + 1;
      Pool* self = this;
      auto* start = new (std::nothrow) auto([self, id] { self->work(id); });
      // no thread (resources, memory): the caller runs the parts without one
      if (!start || !startDetached(start)) break;
      ++nWorkers;
#if !defined(__EMSCRIPTEN__)
      // (Not in wasm: Emscripten 3.1.6 asks navigator.hardwareConcurrency for the cores,
      // which Node 20 lacks; its threads never spin.)
      const unsigned cores = std::thread::hardware_concurrency();
      spin.store(cores == 0 || nWorkers + 1 <= cores, std::memory_order_relaxed);
#endif
    }
    const unsigned withWorker = n - 1 < nWorkers ? n - 1 : nWorkers;
    {
      std::lock_guard<std::mutex> lock(m);
      fn = f;
      ctx = c;
      parts = withWorker + 1;
      pending.store(withWorker, std::memory_order_relaxed);
      generation.fetch_add(1, std::memory_order_release);
    }
    wake.notify_all();
    f(c, 0);
    for (unsigned i = withWorker + 1; i < n; ++i) f(c, i);
#if !defined(__EMSCRIPTEN__)
    if (spin.load(std::memory_order_relaxed)) spinFor([&] { return pending.load(std::memory_order_acquire) == 0; });
#endif
    std::unique_lock<std::mutex> lock(m);
    finished.wait(lock, [&] { return pending.load(std::memory_order_relaxed) == 0; });
    return true;
  }
};

}  // namespace
#endif

void runPartsImpl(unsigned n, PartFn fn, void* ctx) {
  gSplits.fetch_add(1, std::memory_order_relaxed);
#if STLTOPO_THREADS
  static Pool* pool = new (std::nothrow) Pool;
  if (pool && pool->run(n, fn, ctx)) return;
#if defined(__EMSCRIPTEN__)
  // The pool is busy (a split inside a part): a wasm thread needs a worker of Emscripten's
  // preallocated pool, which the pool's threads hold, so the parts run here, in order.
  for (unsigned i = 0; i < n; ++i) fn(ctx, i);
#else
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
    if (i < kMaxThreads && started[i])
      threads[i].join();
    else
      fn(ctx, i);
  }
#endif
#else
  for (unsigned i = 0; i < n; ++i) fn(ctx, i);
#endif
}

}  // namespace stltopo::detail

namespace stltopo {
void setParallelGrainForTesting(size_t items) { detail::setParallelGrainForTesting(items); }
void setChunkItemsForTesting(size_t items) { detail::setChunkItemsForTesting(items); }
uint64_t parallelSplitsForTesting() { return detail::parallelSplitsForTesting(); }
}  // namespace stltopo
