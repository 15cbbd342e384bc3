// parseFloat: parseDecimal, then the exact float and double fast paths, then strtof_l.
#include <cstdlib>
#include <cstring>

#include "float_parse.h"

namespace stltopo::detail {

bool parseFloat(const char* s, size_t len, float& out) {
  if (len > kMaxNumberChars) return false;  // also for the fast path: any chunking agrees
  {
    float f = 0;
    if (parseDecimal(s, s + len, f) == s + len) {
      out = f;
      return true;
    }
  }
  // What parseDecimal leaves (more digits, larger exponents, near ties, other syntax):
  // [sign] digits [. digits] [e [sign] digits] with trailing zeros of the mantissa moved
  // into the exponent, through the exact float and double fast paths, then strtof.
  {
    size_t i = 0;
    bool neg = false;
    if (i < len && (s[i] == '-' || s[i] == '+')) neg = s[i++] == '-';
    uint64_t m = 0;
    int digits = 0, fracDigits = 0;
    bool overflow = false;
    while (i < len && unsigned(s[i] - '0') < 10) {
      if (m < 100000000000000000ull)
        m = m * 10 + unsigned(s[i] - '0');
      else
        overflow = true;
      ++digits;
      ++i;
    }
    if (i < len && s[i] == '.') {
      ++i;
      while (i < len && unsigned(s[i] - '0') < 10) {
        if (m < 100000000000000000ull)
          m = m * 10 + unsigned(s[i] - '0');
        else
          overflow = true;
        ++digits;
        ++fracDigits;
        ++i;
      }
    }
    int e = 0;
    bool ok = digits > 0;
    if (ok && i < len && (s[i] == 'e' || s[i] == 'E')) {
      ++i;
      bool eneg = false;
      if (i < len && (s[i] == '-' || s[i] == '+')) eneg = s[i++] == '-';
      int ed = 0;
      while (i < len && unsigned(s[i] - '0') < 10) {
        if (e < 10000) e = e * 10 + (s[i] - '0');
        ++ed;
        ++i;
      }
      if (ed == 0) ok = false;
      if (eneg) e = -e;
    }
    if (ok && i == len && !overflow) {
      int ex = e - fracDigits;
      // Strip trailing zeros of the mantissa into the exponent.
      while (m != 0 && m % 10 == 0 && ex < 0) {
        m /= 10;
        ++ex;
      }
      if (m == 0) {
        out = neg ? -0.0f : 0.0f;
        return true;
      }
      static const float kPow10[] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f, 1e6f, 1e7f, 1e8f, 1e9f, 1e10f};
      if (m <= (1u << 24) && ex >= -10 && ex <= 10) {
        float f = float(m);
        f = ex < 0 ? f / kPow10[-ex] : f * kPow10[ex];
        out = neg ? -f : f;
        return true;
      }
      // Clinger's fast path, as in parseDecimal.
      static const double kPow10d[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                       1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
      if (m < (1ull << 53) && ex >= -22 && ex <= 22) {
        double d = ex < 0 ? double(m) / kPow10d[-ex] : double(m) * kPow10d[ex];
        if ((detail::bitCast<uint64_t>(d) & 0x1FFFFFFFull) != 0x10000000ull) {
          float f = float(d);
          out = neg ? -f : f;
          return true;
        }
      }
    }
  }
  // General path: the C library's strtof in the "C" locale.
  char buf[kMaxNumberChars + 1];
  std::memcpy(buf, s, len);
  buf[len] = 0;
  char* end = nullptr;
  float f = strtofC(buf, &end);
  if (end != buf + len || len == 0) return false;
  out = f;
  return true;
}

}  // namespace stltopo::detail
