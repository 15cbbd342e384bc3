// Allocation that never throws or aborts: the probes and helpers every container whose size
// the input controls grows through, and the one out-of-memory status. Private (not installed).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "stltopo/status.h"

// Allocation failures of the std containers (names, lists whose size the input controls) are
// caught where exceptions exist: `STLTOPO_TRY { ... } STLTOPO_CATCH { return oom(...); }`.
// The wasm build has none; an allocation failure there aborts, as for the rest of the std
// containers of the core.
#if defined(__cpp_exceptions)
#define STLTOPO_TRY try
#define STLTOPO_CATCH catch (...)
#else
#define STLTOPO_TRY if (true)
#define STLTOPO_CATCH else
#endif

namespace stltopo::detail {

// Whether malloc can give `bytes` now (the block is freed again). The standard containers
// throw (natively) or abort (wasm, built without exceptions) when an allocation fails, so
// every one whose size the input controls grows only after this probe said yes; the probe
// and the container's own allocation follow each other with nothing in between, so the
// container gets the block the probe just freed.
bool canAllocate(size_t bytes);

// Appends `v` to `vec` without a throw or abort: when `vec` is full, its grown buffer is
// probed first. False (and `vec` unchanged) when the probe fails.
template <class T>
bool tryPushBack(std::vector<T>& vec, T&& v) {
  if (vec.size() == vec.capacity()) {
    size_t cap = vec.capacity() < 4 ? 4 : vec.capacity() * 2;
    if (cap > vec.max_size() || !canAllocate(cap * sizeof(T))) return false;
    vec.reserve(cap);
  }
  vec.push_back(std::move(v));
  return true;
}

// A T in malloc'ed memory (placement new; T's constructor must not allocate): null when
// malloc fails. Never a throw, also where operator new would throw or abort.
template <class T, class... Args>
T* tryNew(Args&&... args) {
  void* p = std::malloc(sizeof(T));
  return p ? new (p) T(std::forward<Args>(args)...) : nullptr;
}
// Destroys and frees a tryNew() object; null is allowed.
template <class T>
void tryDelete(T* p) {
  if (!p) return;
  p->~T();
  std::free(p);
}

// s = [p, p + n) without a throw or abort (probed as tryPushBack). False: `s` unchanged.
bool tryAssign(std::string& s, const char* p, size_t n);
// s = [p, p + n) or, when the probe fails, as much of it as fits in s without allocating:
// for messages, which would rather be cut than throw.
void assignOrCut(std::string& s, const char* p, size_t n);
// Reserves `n` bytes in `s` (probed). After it, appends up to n bytes never allocate.
bool tryReserve(std::string& s, size_t n);

// The out-of-memory status of every stage: "out-of-memory: could not allocate <what>".
// Never throws (the message is cut when even it cannot be allocated).
Status oom(const char* what);

// The opposite of adviseHugePages (stltopo/array.h), for an array that huge pages do not help:
// Linux native builds ask for small pages over the array's whole 2 MiB-aligned stretches; a
// no-op elsewhere. For arrays written once in order and then read, which a call allocates
// and frees: the intersection pass's hierarchy. There huge pages gave no warm gain and made a
// process's first pass bimodal (bench/PROFILE.md, *Stop 42*).
void adviseSmallPages(void* p, size_t bytes);

}  // namespace stltopo::detail
