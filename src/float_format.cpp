// Shortest round-trip decimals (see float_format.h). The exact float path is in
// float_shortest.h, which the ASCII writer compiles too.
#include "float_format.h"

#include <locale.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "float_shortest.h"
#include "text_format.h"

namespace stltopo::detail {

// For p = 1, 2, ... print x correctly rounded to p digits (the C library's %e) and keep
// the first that the C library reads back as the same value.
std::string shortestByPrinting(double x, bool isFloat) {
  if (x == 0) return std::signbit(x) ? "-0" : "0";
  char buf[64];
  int maxp = isFloat ? 9 : 17;
  std::string digits;
  int exp10 = 0;
  bool neg = false;
  for (int p = 1; p <= maxp; ++p) {
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
    bool same = isFloat ? strtof_l(canon.c_str(), nullptr, cLocale()) == float(x)
                        : strtod_l(canon.c_str(), nullptr, cLocale()) == x;
    if (same) break;
  }
  while (digits.size() > 1 && digits.back() == '0') digits.pop_back();
  char out[400];
  return std::string(out, render(neg, digits.data(), int(digits.size()), exp10, out));
}

size_t formatShortest(float f, char* out) { return formatShortestHere(f, out); }

std::string shortest(double x, bool isFloat) {
  if (x == 0) return std::signbit(x) ? "-0" : "0";
  if (isFloat) {
    char buf[kMaxFloatChars];
    return std::string(buf, formatShortestHere(float(x), buf));
  }
  return shortestByPrinting(x, false);
}

}  // namespace stltopo::detail
