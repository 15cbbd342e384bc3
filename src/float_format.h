// Shortest round-trip decimals for the JSON report and the ASCII STL writer. Not installed.
#pragma once

#include <cstddef>
#include <string>

namespace stltopo::detail {

// The shortest decimal that reads back as the same value (float32 when isFloat, else
// double), rendered like JavaScript's Number#toString: fixed notation for decimal
// exponents in [-7, 21), else d.ddde+N / d.ddde-N; "-0" for negative zero. The digits are
// those of the first precision p = 1, 2, ... whose correctly rounded p-digit decimal reads
// back. x must be finite.
std::string shortest(double x, bool isFloat);
// The same as shortest(), always through printf and strtof (the reference for tests).
std::string shortestByPrinting(double x, bool isFloat);
// shortest(x, false): the same digits as shortestByPrinting(x, false), by exact integer
// arithmetic for nearly every double, else in 1 to 3 printings.
std::string shortestDouble(double x);

// Room formatShortest() needs: "-100000000000000000000" (21 digits) is the longest.
inline constexpr size_t kMaxFloatChars = 24;

// Writes the same text as shortest(f, true) to out (at least kMaxFloatChars bytes, no
// terminator) and returns its length. Without allocation, and fast: exact integer
// arithmetic for nearly all floats, shortest() for the rest. NaN and infinities, which
// shortest() does not take, are written "nan", "-nan", "inf" and "-inf" (what strtof
// reads back as the same class; a NaN's payload is not kept).
size_t formatShortest(float f, char* out);

}  // namespace stltopo::detail
