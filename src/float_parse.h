// ASCII numbers: the exact float of a decimal token, as strtof reads it in the "C" locale.
// parseDecimal is the inline fast path of the ASCII parser's whole-facet reader;
// parseFloat takes any token.
#pragma once

#include <cstddef>
#include <cstdint>

#include "bit_cast.h"
#include "stltopo/read.h"
#include "text_format.h"

namespace stltopo::detail {

// wraps around: the caller checks the count.
inline const char* digits(const char* q, const char* limit, uint64_t& m) {
  for (; q < limit && unsigned(*q - '0') < 10; ++q) m = m * 10 + unsigned(*q - '0');
  return q;
}

// The fast path of parseFloat, for the plain decimal at s: [sign] digits [. digits]
// [e [sign] digits] with at most 19 digits (leading zeros included) and a small exponent,
// e.g. "3.99992108", "-0.5", "1.234567e+01". Reads nothing at or past limit. Returns the
// end of the number (the caller checks that the token ends there), or nullptr when it
// cannot decide (the caller then takes the general path).
inline const char* parseDecimal(const char* s, const char* limit, float& out) {
  const char* q = s;
  bool neg = false;
  if (q < limit && (*q == '-' || *q == '+')) neg = *q++ == '-';
  uint64_t m = 0;
  const char* intAt = q;
  q = digits(q, limit, m);
  int nDigits = int(q - intAt), fracDigits = 0;
  if (q < limit && *q == '.') {
    const char* fracAt = ++q;
    q = digits(q, limit, m);
    fracDigits = int(q - fracAt);
    nDigits += fracDigits;
  }
  if (nDigits == 0 || nDigits > 19) return nullptr;
  int e = 0;
  if (q < limit && (*q | 0x20) == 'e') {
    ++q;
    bool eneg = false;
    if (q < limit && (*q == '-' || *q == '+')) eneg = *q++ == '-';
    const char* expAt = q;
    for (; q < limit && unsigned(*q - '0') < 10 && q - expAt < 4; ++q) e = e * 10 + (*q - '0');
    if (q == expAt) return nullptr;
    if (eneg) e = -e;
  }
  if (m == 0) {
    out = neg ? -0.0f : 0.0f;
    return q;
  }
  // m * 10^ex in double, with a multiplication (a division is much slower): m is exact,
  // 10^ex is rounded when ex < 0, and so is the product, so d is within 2 units in the last
  // place (ulp) of the exact value. The float nearest to d is then the float nearest to the
  // exact value unless d lies within those 2 ulp of a halfway point between two floats,
  // where the low 29 bits of d (those a float drops) read 0x10000000: there, and for the
  // rest (m >= 2^53, |ex| > 22), take the general path.
  static constexpr double kPow10[45] = {
      1e-22, 1e-21, 1e-20, 1e-19, 1e-18, 1e-17, 1e-16, 1e-15, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8,
      1e-7,  1e-6,  1e-5,  1e-4,  1e-3,  1e-2,  1e-1,  1e0,   1e1,   1e2,   1e3,   1e4,   1e5,   1e6,  1e7,
      1e8,   1e9,   1e10,  1e11,  1e12,  1e13,  1e14,  1e15,  1e16,  1e17,  1e18,  1e19,  1e20,  1e21, 1e22};
  int ex = e - fracDigits;
  if (m >= (1ull << 53) || ex < -22 || ex > 22) return nullptr;
  double d = double(m) * kPow10[ex + 22];
  uint64_t dropped = detail::bitCast<uint64_t>(d) & 0x1FFFFFFFull;
  if (dropped - (0x10000000ull - 4) <= 8) return nullptr;
  float f = float(d);
  out = neg ? -f : f;
  return q;
}

// Parses a whole token [s, s + len) as a float exactly as strtof does in the "C" locale;
// false when strtof would not read the whole token, or len > kMaxNumberChars.
bool parseFloat(const char* s, size_t len, float& out);

}  // namespace stltopo::detail
