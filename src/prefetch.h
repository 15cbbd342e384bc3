// Starting a load early, so that the cache misses of a loop's next items overlap with its
// work on this one. Private (not installed).
#pragma once

#include <algorithm>
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

// The items a loop over [first, end) touches at item i, for items `lead` on: natively the one
// item i + lead (a prefetch does not hold up the loop), in wasm a whole group of kAhead items
// when i starts a group (counted from first) and none otherwise. In wasm a touch is a load,
// which the loop's later work waits on: a group's loads run back to back, so that their
// misses overlap instead of coming one item at a time.
//   for (auto [u, ue] = aheadOf(i, first, end, kAhead); u < ue; ++u) ... touch(... u ...);
struct AheadRange {
  uint32_t begin, end;
};
inline AheadRange aheadOf(uint32_t i, uint32_t first, uint32_t end, uint32_t lead) {
  const uint64_t b = uint64_t(i) + lead;
  if (b >= end) return {0, 0};
#if defined(__EMSCRIPTEN__)
  if ((i - first) % kAhead != 0) return {0, 0};
  return {uint32_t(b), uint32_t(std::min<uint64_t>(end, b + kAhead))};
#else
  (void)first;
  return {uint32_t(b), uint32_t(b + 1)};
#endif
}

// Keeps wasm's touch loads alive (their sum goes to an atomic no one reads); natively a
// prefetch has no value to keep, and this does nothing.
inline std::atomic<uint32_t> gTouchSink{0};
inline void keepAlive(uint32_t sink) {
#if defined(__EMSCRIPTEN__)
  gTouchSink.fetch_add(sink, std::memory_order_relaxed);
#else
  (void)sink;
#endif
}

}  // namespace stltopo::detail
