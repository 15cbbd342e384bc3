// printf-style text for the reports and the status messages, and the "C" locale the number
// parsers and printers use. Private (not installed).
#pragma once

#include <locale.h>

#include <cstdarg>
#include <string>

namespace stltopo::detail {

// strtof and strtod in the "C" locale: numbers never depend on the process locale. (musl, the
// wasm build's C library, reads numbers alike in every locale, and its strtof_l ignores the
// locale: there these are the plain functions, and no locale object is made, which keeps
// musl's locale loading out of the core module.)
float strtofC(const char* s, char** end);
double strtodC(const char* s, char** end);

// printf appended to a std::string, of any length (the report's text; may throw natively).
void appendf(std::string& out, const char* f, ...) __attribute__((format(printf, 2, 3)));
// printf into a new std::string, for status messages: never throws or aborts; when memory
// runs out the message is cut to what fits in the string itself.
std::string format(const char* f, ...) __attribute__((format(printf, 1, 2)));

}  // namespace stltopo::detail
