// std::bit_cast without <bit>: Emscripten 3.1.6's libc++ lacks it; the builtin is in both
// GCC and Clang. Private (not installed).
#pragma once

namespace stltopo::detail {

template <class To, class From>
constexpr To bitCast(const From& from) noexcept {
  static_assert(sizeof(To) == sizeof(From));
  return __builtin_bit_cast(To, from);
}

}  // namespace stltopo::detail
