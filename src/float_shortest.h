// The exact path of the shortest decimals (float_format.h), for the two files that compile
// it: float_format.cpp (the two formatShortest() and shortestDouble(): the report's numbers,
// compiled for size in the wasm build, where the core module has no writer) and write_stl.cpp
// (the ASCII writer's hot loop, compiled for speed). Everything here has internal linkage,
// so that each of them keeps its own copy, built with its own flags: one shared copy at -Oz
// made ASCII writing 27-40% slower, and at -O3 it cost the core module 1.7 kB gzipped.
// Not installed; include nowhere else.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "bit_cast.h"
#include "float_format.h"

namespace stltopo::detail {
namespace {

// digits[0, n) (no trailing zeros unless n == 1) times 10^exp10 (the exponent of the
// first digit), rendered like Number#toString. Returns the length written.
size_t render(bool neg, const char* digits, int n, int exp10, char* out) {
  char* o = out;
  if (neg) *o++ = '-';
  if (exp10 >= 21 || exp10 < -7) {
    *o++ = digits[0];
    if (n > 1) {
      *o++ = '.';
      std::memcpy(o, digits + 1, size_t(n - 1));
      o += n - 1;
    }
    *o++ = 'e';
    *o++ = exp10 < 0 ? '-' : '+';
    int a = exp10 < 0 ? -exp10 : exp10;
    if (a >= 100) *o++ = char('0' + a / 100);
    if (a >= 10) *o++ = char('0' + a / 10 % 10);
    *o++ = char('0' + a % 10);
  } else if (exp10 < 0) {
    *o++ = '0';
    *o++ = '.';
    for (int i = 0; i < -exp10 - 1; ++i) *o++ = '0';
    std::memcpy(o, digits, size_t(n));
    o += n;
  } else if (exp10 + 1 >= n) {
    std::memcpy(o, digits, size_t(n));
    o += n;
    for (int i = 0; i < exp10 + 1 - n; ++i) *o++ = '0';
  } else {
    std::memcpy(o, digits, size_t(exp10 + 1));
    o += exp10 + 1;
    *o++ = '.';
    std::memcpy(o, digits + exp10 + 1, size_t(n - exp10 - 1));
    o += n - exp10 - 1;
  }
  return size_t(o - out);
}

// ---------------------------------------------------------------------------
// The exact path, for float32 (9 digits at most, kDigits = 9) and for doubles (17). A
// positive value is v = m * 2^e (m < 2^24 for a float, 2^53 for a double). For a precision p
// the candidate is C = round(v / 10^k), k = E10 - (p - 1), E10 the decimal exponent of
// v. With N = m * H, H = 5^max(-k,0) * 2^max(e-k,0) and D = 5^max(k,0) * 2^max(k-e,0),
// v / 10^k = N / D exactly, and half the gap to the next value above is H / 2 in the same
// units (H / 4 below a power of two, where the value below is closer). C * 10^k reads
// back as v exactly when |C * D - N| is less than that half gap.
using U128 = unsigned __int128;

struct Pow5 {
  U128 p[56];    // 5^i
  int bits[56];  // bit length of 5^i
  constexpr Pow5() : p(), bits() {
    U128 x = 1;
    for (int i = 0; i < 56; ++i) {
      p[i] = x;
      int b = 0;
      for (U128 y = x; y; y >>= 1) ++b;
      bits[i] = b;
      x *= 5;
    }
  }
};
constexpr Pow5 kPow5;

struct Exact {
  uint64_t m;
  int e;
  bool narrowBelow;  // the value below is half as far as the value above

  // Sets N, D, H for v / 10^k in the integer type U; false when they do not fit it (with
  // room for 4 * 10^(kDigits - 1) * D, the largest product of the candidates: 2^28.6 for a
  // float, 2^55.2 for a double).
  template <class U, int kDigits>
  bool scale(int k, U& N, U& D, U& H) const {
    constexpr int kBits = int(sizeof(U) * 8);
    constexpr int kMantBits = kDigits == 9 ? 24 : 53, kRoom = kDigits == 9 ? 30 : 57;
    int a = k < 0 ? -k : 0, b = e > k ? e - k : 0, c = k > 0 ? k : 0, d = k > e ? k - e : 0;
    if (a > 55 || c > 55) return false;
    if (kMantBits + kPow5.bits[a] + b > kBits - 2 || kPow5.bits[c] + d > kBits - kRoom) return false;
    H = U(kPow5.p[a]) << b;
    N = H * m;
    D = U(kPow5.p[c]) << d;
    return true;
  }
};

enum class Found : uint8_t { Yes, Unsure, NoRoom };

struct Pow10 {
  uint64_t p[19];  // 10^i
  constexpr Pow10() : p() {
    uint64_t x = 1;
    for (int i = 0; i < 19; ++i, x *= 10) p[i] = x;
  }
};
constexpr Pow10 kPow10;

// The shortest digits of x (at most kDigits of them) in the integer type U (64 bits for a
// float's usual magnitudes, else 128): E10 is floor(log10 v) or one less.
template <class U, int kDigits>
Found digitsIn(const Exact& x, int E10, uint64_t& digits, int& p, int& exp10) {
  // v / 10^(E10 - kDigits + 1) = qn + rn / D: qn has kDigits digits when E10 is right, one
  // more when it is one low.
  U N, D, H, rn = 0;
  uint64_t qn = 0;
  for (int pass = 0; pass < 2; ++pass) {
    int k = E10 - (kDigits - 1);
    if (!x.template scale<U, kDigits>(k, N, D, H)) return Found::NoRoom;
    U q;
    if (k <= 0) {  // D is a power of two
      int d = k > x.e ? k - x.e : 0;
      q = N >> d;
      rn = N & ((U(1) << d) - 1);
    } else {
      q = N / D;
      rn = N - q * D;
    }
    qn = uint64_t(q);
    if (qn < kPow10.p[kDigits]) break;
    ++E10;
  }
  // The p-digit candidate, p = kDigits - j: v / 10^(E10 - p + 1) = (qn + rn / D) / 10^j,
  // so its quotient is qn / 10^j and its remainder, in units of 1 / D, is
  // rem = (qn % 10^j) * D + rn out of 10^j * D. Half the gap to the value above is H / 2
  // in the same units, H / 4 to the value below when narrowBelow.
  enum Fit { Inside, Outside, Unsure };
  auto candidate = [&](int j, uint64_t& c) {
    uint64_t P = kPow10.p[j], qp = qn / P;
    U rem = U(qn % P) * D + rn, whole = U(P) * D;
    // Round half to even, as printf does with an exact tie.
    bool below = 2 * rem < whole || (2 * rem == whole && (qp & 1) == 0);
    c = below ? qp : qp + 1;
    U err = below ? rem : whole - rem;
    U twice = U(below && x.narrowBelow ? 4 : 2) * err;
    return twice < H ? Inside : twice > H ? Outside : Unsure;
  };
  uint64_t cn;
  if (candidate(0, cn) != Inside) return Found::Unsure;
  digits = cn;
  p = kDigits;
  if (x.narrowBelow) {
    // The gap differs on the two sides, so a longer candidate can fail where a shorter
    // one passed: take the first that fits, as the search by printing does.
    for (int q = 1; q < kDigits; ++q) {
      uint64_t c;
      Fit fit = candidate(kDigits - q, c);
      if (fit == Unsure) return Found::Unsure;
      if (fit == Inside) {
        digits = c;
        p = q;
        break;
      }
    }
  } else {
    // A candidate of p + 1 digits is never farther from v than the one of p digits, so
    // "fits" is monotone in p: shorten while it fits.
    for (int j = 1; j < kDigits; ++j) {
      uint64_t c;
      Fit fit = candidate(j, c);
      if (fit == Unsure) return Found::Unsure;
      if (fit == Outside) break;
      digits = c;
      p = kDigits - j;
    }
  }
  exp10 = E10;
  return Found::Yes;
}

// digits (p of them, or 10^p when the rounding carried) times 10^exp10, rendered like
// Number#toString into out (at least 26 bytes). Returns the length written.
size_t renderDigits(bool neg, uint64_t digits, int p, int exp10, char* out) {
  char d[24];
  int n = p;
  if (digits == kPow10.p[p]) {  // rounding carried to 10^p
    digits = 1;
    n = 1;
    ++exp10;
  }
  for (int i = n - 1; i >= 0; --i) {
    d[i] = char('0' + digits % 10);
    digits /= 10;
  }
  while (n > 1 && d[n - 1] == '0') --n;
  return render(neg, d, n, exp10, out);
}

// The digits and decimal exponent formatShortest() gives for the positive finite float f, or
// false when the integer arithmetic cannot decide (a candidate exactly on the boundary of
// the interval that reads back as f, or sizes out of range).
bool exactDigits(float f, uint64_t& digits, int& p, int& exp10) {
  uint32_t bits = bitCast<uint32_t>(f);
  uint32_t mant = bits & 0x7fffffu, ex = bits >> 23;
  Exact x;
  x.m = ex == 0 ? mant : mant | 0x800000u;
  x.e = ex == 0 ? -149 : int(ex) - 150;
  x.narrowBelow = mant == 0 && ex > 1;
  int b2 = x.e + (63 - __builtin_clzll(x.m));  // floor(log2 v)
  int E10 = int((int64_t(b2) * 78913) >> 18);  // floor(log10 v) or one less
  Found r = digitsIn<uint64_t, 9>(x, E10, digits, p, exp10);
  if (r == Found::NoRoom) r = digitsIn<U128, 9>(x, E10, digits, p, exp10);
  return r == Found::Yes;
}

// formatShortest(), in this file's copy.
size_t formatShortestHere(float f, char* out) {
  if (std::isnan(f)) {
    const char* s = std::signbit(f) ? "-nan" : "nan";
    std::memcpy(out, s, std::strlen(s));
    return std::strlen(s);
  }
  bool neg = std::signbit(f);
  if (std::isinf(f)) {
    std::memcpy(out, neg ? "-inf" : "inf", neg ? 4 : 3);
    return neg ? 4 : 3;
  }
  if (f == 0) {
    std::memcpy(out, neg ? "-0" : "0", neg ? 2 : 1);
    return neg ? 2 : 1;
  }
  uint64_t digits;
  int p, exp10;
  if (!exactDigits(neg ? -f : f, digits, p, exp10)) {
    std::string s = shortestByPrinting(double(f), true);
    std::memcpy(out, s.data(), s.size());
    return s.size();
  }
  return renderDigits(neg, digits, p, exp10, out);
}

}  // namespace
}  // namespace stltopo::detail
