// Shortest round-trip decimals (see float_format.h). The exact integer path is in
// float_shortest.h, whose float half the ASCII writer compiles too.
#include "float_format.h"

#include <locale.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "float_shortest.h"
#include "text_format.h"

namespace stltopo::detail {

namespace {

// x printed correctly rounded to p significant digits (the C library's %e): its digits,
// exponent and sign, and whether the C library reads them back as x (as float(x) when
// isFloat).
bool printedRoundTrips(double x, bool isFloat, int p, std::string& digits, int& exp10, bool& neg) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*e", p - 1, x);
  // Collect the mantissa digits and the exponent without trusting the locale's point.
  digits.clear();
  const char* s = buf;
  neg = *s == '-';
  if (neg) ++s;
  while (*s && *s != 'e') {
    if (*s >= '0' && *s <= '9') digits += *s;
    ++s;
  }
  exp10 = *s == 'e' ? std::atoi(s + 1) : 0;
  std::string canon;
  if (neg) canon += '-';
  canon += digits[0];
  if (digits.size() > 1) {
    canon += '.';
    canon.append(digits, 1, std::string::npos);
  }
  canon += 'e';
  canon += std::to_string(exp10);
  return isFloat ? strtofC(canon.c_str(), nullptr) == float(x) : strtodC(canon.c_str(), nullptr) == x;
}

std::string rendered(bool neg, std::string& digits, int exp10) {
  while (digits.size() > 1 && digits.back() == '0') digits.pop_back();
  char out[400];
  return std::string(out, render(neg, digits.data(), int(digits.size()), exp10, out));
}

// shortestByPrinting; with from15, shortestDouble (isFloat false).
std::string shortestFrom(double x, bool isFloat, bool from15) {
  if (x == 0) return std::signbit(x) ? "-0" : "0";
  const int maxp = isFloat ? 9 : 17;
  std::string digits;
  int exp10 = 0;
  bool neg = false;
  int p = 1;
  if (from15 && std::fabs(x) >= DBL_MIN && std::isfinite(x)) {
    if (printedRoundTrips(x, false, 15, digits, exp10, neg)) return rendered(neg, digits, exp10);
    p = 16;
  }
  for (; p <= maxp; ++p)
    if (printedRoundTrips(x, isFloat, p, digits, exp10, neg)) break;
  return rendered(neg, digits, exp10);
}

// The digits and decimal exponent shortestByPrinting() gives for the positive finite double
// v, by exact 128-bit arithmetic (float_shortest.h), or false when it cannot decide: a
// candidate exactly on the boundary of the interval that reads back as v, or a magnitude
// whose scaled numbers do not fit 128 bits (below about 1e-14, above about 1e46).
bool exactDigits(double v, uint64_t& digits, int& p, int& exp10) {
  const uint64_t bits = bitCast<uint64_t>(v), mant = bits & ((uint64_t(1) << 52) - 1), ex = bits >> 52;
  Exact x;
  x.m = ex == 0 ? mant : mant | (uint64_t(1) << 52);
  x.e = ex == 0 ? -1074 : int(ex) - 1075;
  x.narrowBelow = mant == 0 && ex > 1;
  const int b2 = x.e + (63 - __builtin_clzll(x.m));  // floor(log2 v)
  const int E10 = int((int64_t(b2) * 78913) >> 18);  // floor(log10 v) or one less
  return digitsIn<U128, 17>(x, E10, digits, p, exp10) == Found::Yes;
}

}  // namespace

// For p = 1, 2, ... print x correctly rounded to p digits (the C library's %e) and keep
// the first that the C library reads back as the same value.
std::string shortestByPrinting(double x, bool isFloat) { return shortestFrom(x, isFloat, false); }

// The digits of shortestByPrinting(x, false). Exact integer arithmetic decides nearly
// every double of a report (a report of 1M shells spent 40% of its time printing and reading
// doubles natively, more in wasm, where musl does both in 128-bit long double:
// bench/PROFILE.md, *Stop 68*). The rest take 1 to 3 printings: for a normal double x, if
// the p-digit rounding r_p of x reads back as x for some p <= 15,
// then r_p is within half an ulp of x (a relative 2^-53 < 1.2e-16), and every other 15-digit
// decimal is at least a 15-digit step away (a relative 1e-15 or more) less that: so r_p,
// padded with zeros, is the 15-digit rounding r_15. Hence: when r_15 reads back as x, the
// shortest p is r_15's digits without its trailing zeros (a shorter p would have left more
// zeros), and those digits are r_p; when it does not, no p <= 15 does, and the search starts
// at 16. Subnormal doubles, whose ulp is relatively larger, take the search from 1.
size_t formatShortest(double x, char* out) {
  uint64_t digits;
  int p, exp10;
  if (x != 0 && std::isfinite(x) && exactDigits(std::fabs(x), digits, p, exp10))
    return renderDigits(std::signbit(x), digits, p, exp10, out);
  const std::string s = shortestFrom(x, false, true);
  std::memcpy(out, s.data(), s.size());
  return s.size();
}

std::string shortestDouble(double x) {
  char out[kMaxDoubleChars];
  return std::string(out, formatShortest(x, out));
}

size_t formatShortest(float f, char* out) { return formatShortestHere(f, out); }

}  // namespace stltopo::detail
