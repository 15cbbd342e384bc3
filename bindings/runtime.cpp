// What both wasm modules (stltopo-wasm and stltopo-full) register besides their own
// classes: the heap figures the JS layer and the heap-baseline tests read, and the test
// hooks that make allocation fail or the instance abort.
#include <emscripten/bind.h>
#include <emscripten/em_asm.h>
#include <emscripten/heap.h>
#include <malloc.h>

#include <cstddef>
#include <cstdlib>
#include <new>

namespace {

// The allocator's in-use bytes (emmalloc's mallinfo), for the heap-baseline tests.
double heapInUse() { return double(mallinfo().uordblks); }
double heapSize() { return double(emscripten_get_heap_size()); }
double heapMax() { return double(emscripten_get_heap_max()); }

// Test hook: occupy the heap so that at most about `leave` bytes stay allocatable,
// to prove that allocation failure becomes an out-of-memory status. Returns the
// number of bytes held. testRelease() gives them back.
void* gBallast[8192];
size_t gBallastSize[8192];
int gBallastCount = 0;
void testRelease() {
  for (int i = 0; i < gBallastCount; ++i) std::free(gBallast[i]);
  gBallastCount = 0;
}
double testFill(double leave) {
  testRelease();
  double held = 0;
  for (size_t size = size_t(1) << 28; size >= (size_t(1) << 16); size >>= 1) {
    while (gBallastCount < 8192) {
      void* p = std::malloc(size);
      if (!p) break;
      gBallast[gBallastCount] = p;
      gBallastSize[gBallastCount++] = size;
      held += double(size);
    }
  }
  // Free the smallest blocks until about `leave` bytes are available again.
  double freed = 0;
  while (gBallastCount > 0 && freed < leave) {
    --gBallastCount;
    std::free(gBallast[gBallastCount]);
    freed += double(gBallastSize[gBallastCount]);
    held -= double(gBallastSize[gBallastCount]);
  }
  return held;
}

// Test hook: a wasm abort (what a failed operator new would do), to prove that
// the JS layer drops the dead instance and the next load gets a fresh one.
void testAbort() { std::abort(); }

// operator new's failure (the core checks its own arrays; a repair plan's std::vector and
// std::string are not): the instance aborts, as it would, but says why, so that the JS layer
// (wasm.js wasmFailure, which reads the abort's reason) gives an out-of-memory error whatever
// the size that did not fit. Without it the abort had no reason, and one that failed far below
// the top of the heap (a 700 MB string) came out of the API as a raw RuntimeError.
void outOfMemory() {
  EM_ASM({ abort('out of memory: operator new failed'); });
  std::abort();
}
[[maybe_unused]] const bool kNewHandler = (std::set_new_handler(outOfMemory), true);

// Test hook: an operator new that fails (4 GB less 64 kB: more than a 4 GB heap that holds
// the module can give).
void* volatile gNewKept = nullptr;
double testNewFails() {
  volatile size_t n = ~size_t(0) - 65535;
  gNewKept = ::operator new(n);  // kept in a volatile: the call is not elided
  ::operator delete(gNewKept);
  gNewKept = nullptr;
  return 0;
}

}  // namespace

EMSCRIPTEN_BINDINGS(stltopo_runtime) {
  using emscripten::function;
  function("_heapInUse", &heapInUse);
  function("_heapSize", &heapSize);
  function("_heapMax", &heapMax);
  function("_testFill", &testFill);
  function("_testRelease", &testRelease);
  function("_testAbort", &testAbort);
  function("_testNewFails", &testNewFails);
}
