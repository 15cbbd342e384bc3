// printf-style text for the reports and the status messages, and the "C" locale the number
// parsers and printers use. Private (not installed).
#pragma once

#include <locale.h>

#include <cstdarg>
#include <string>

namespace stltopo::detail {

// The "C" locale, for strtof_l/strtod_l: numbers never depend on the process locale.
locale_t cLocale();

// printf appended to a std::string, of any length (the report's text; may throw natively).
void appendf(std::string& out, const char* f, ...) __attribute__((format(printf, 2, 3)));
// printf into a new std::string, for status messages: never throws or aborts; when memory
// runs out the message is cut to what fits in the string itself.
std::string format(const char* f, ...) __attribute__((format(printf, 1, 2)));

}  // namespace stltopo::detail
