// Internal helpers shared by the core's translation units. Not installed.
#pragma once

#include <locale.h>

#include <cstdarg>
#include <cstdint>
#include <string>

#include "stltopo.h"

namespace stltopo::detail {

// std::bit_cast without <bit>: Emscripten 3.1.6's libc++ lacks it; the builtin is in
// both GCC and Clang.
template <class To, class From>
constexpr To bitCast(const From& from) noexcept {
  static_assert(sizeof(To) == sizeof(From));
  return __builtin_bit_cast(To, from);
}

// The "C" locale, for strtof_l/strtod_l: numbers never depend on the process locale.
locale_t cLocale();

// printf into a std::string, of any length.
void appendf(std::string& out, const char* f, ...) __attribute__((format(printf, 2, 3)));
std::string format(const char* f, ...) __attribute__((format(printf, 1, 2)));

// A status whose message starts with the code's name: "truncated: ...".
Status makeStatus(Code c, const std::string& msg, uint64_t offset = kNoOffset, uint64_t line = 0,
                  uint32_t triangle = kInvalid);

}  // namespace stltopo::detail
