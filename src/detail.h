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

// Shortest decimal that reads back as the same value (float32 or double), rendered
// like JavaScript's Number#toString: fixed notation for exponents in [-7, 21).
std::string shortest(double x, bool isFloat);

// A JSON writer for the reports: s holds the text, `first` whether the next key or
// element is the first of its object or array.
struct Json {
  std::string s;
  bool first = true;
  void open(char c) { s += c; first = true; }
  void close(char c) { s += c; first = false; }
  void key(const char* k) {
    if (!first) s += ',';
    first = false;
    s += '"';
    s += k;
    s += "\":";
  }
  void sep() {
    if (!first) s += ',';
    first = false;
  }
  void u(uint64_t v) { s += std::to_string(v); }
  void i(int64_t v) { s += std::to_string(v); }
  void str(const std::string& v) { s += jsonString(v); }
  void b(bool v) { s += v ? "true" : "false"; }
  void null() { s += "null"; first = false; }
  // A float32 coordinate (-0 printed as 0) or a float64 figure, in shortest form.
  void f32(float v) { s += shortest(v + 0.0f, true); }
  void f64(double v) { s += shortest(v, false); }
};

}  // namespace stltopo::detail
