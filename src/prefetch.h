// Starting a load early, so that the cache misses of a loop's next items overlap with its
// work on this one. Private (not installed).
#pragma once

#include <atomic>
#include <cstdint>

namespace stltopo::detail {

// Starts loading the cache line at p: a prefetch natively. wasm has no prefetch instruction,
// so there p is loaded and folded into `sink`, which the caller hands to keepAlive at the
// end so that the loads are not dropped.
inline void touch(const void* p, uint32_t& sink) {
#if defined(__EMSCRIPTEN__)
  sink += *static_cast<const uint8_t*>(p);
#else
  (void)sink;
  __builtin_prefetch(p);
#endif
}

// How many items ahead the loops that use touch() start loading: enough for the misses to
// overlap, few enough that the lines are still cached when the item comes.
constexpr uint32_t kAhead = 8;

inline std::atomic<uint32_t> gTouchSink{0};
inline void keepAlive(uint32_t sink) { gTouchSink.fetch_add(sink, std::memory_order_relaxed); }

}  // namespace stltopo::detail
