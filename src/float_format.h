// Shortest round-trip decimals for the JSON report and the ASCII STL writer. Not installed.
#pragma once

#include <cstddef>
#include <string>

namespace stltopo::detail {

// The shortest decimal that reads back as the same value (a float32 or a double), rendered
// like JavaScript's Number#toString: fixed notation for decimal exponents in [-7, 21), else
// d.ddde+N / d.ddde-N; "-0" for negative zero. The digits are those of the first precision
// p = 1, 2, ... whose correctly rounded p-digit decimal reads back.

// Room the two formatShortest() need: "-100000000000000000000" (21 digits) is a float's
// longest, "-0.00000012345678901234567" (26 characters) a double's.
inline constexpr size_t kMaxFloatChars = 24;
inline constexpr size_t kMaxDoubleChars = 32;

// Writes f's shortest decimal to out (at least kMaxFloatChars bytes, no terminator) and
// returns its length. Without allocation, and fast: exact integer arithmetic for nearly all
// floats, printing for the rest. NaN and infinities are written "nan", "-nan", "inf" and
// "-inf" (what strtof reads back as the same class; a NaN's payload is not kept).
size_t formatShortest(float f, char* out);
// The same for a finite double x (out at least kMaxDoubleChars bytes): exact integer
// arithmetic for nearly every double, else 1 to 3 printings.
size_t formatShortest(double x, char* out);
// formatShortest(x, ...) as a string.
std::string shortestDouble(double x);
// The same text through printf and strtof (isFloat) or strtod alone, trying p = 1, 2, ...:
// the definition, and the reference for tests. x must be finite.
std::string shortestByPrinting(double x, bool isFloat);

}  // namespace stltopo::detail
