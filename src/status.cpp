#include "stltopo.h"

#if defined(__linux__) && !defined(__EMSCRIPTEN__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace stltopo {

void detail::adviseHugePages(void* p, size_t bytes) {
#if defined(__linux__) && !defined(__EMSCRIPTEN__) && defined(MADV_HUGEPAGE)
  // Only whole 2 MiB-aligned stretches can become huge pages; advise those.
  const uintptr_t huge = uintptr_t(2) << 20;
  uintptr_t begin = (reinterpret_cast<uintptr_t>(p) + huge - 1) & ~(huge - 1);
  uintptr_t end = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(huge - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

const char* codeName(Code c) {
  switch (c) {
    case Code::Ok: return "ok";
    case Code::Empty: return "empty";
    case Code::NotStl: return "not-stl";
    case Code::Truncated: return "truncated";
    case Code::UnexpectedEnd: return "unexpected-end";
    case Code::AsciiSyntax: return "ascii-syntax";
    case Code::NonFinite: return "non-finite";
    case Code::TooLarge: return "too-large";
    case Code::OutOfMemory: return "out-of-memory";
    case Code::InvalidArgument: return "invalid-argument";
    case Code::Aborted: return "aborted";
    case Code::Invalid: return "invalid";
    case Code::TrailingBytes: return "trailing-bytes";
    case Code::MissingEndsolid: return "missing-endsolid";
    case Code::NameTruncated: return "name-truncated";
  }
  return "unknown";
}

const char* formatName(Format f) {
  switch (f) {
    case Format::Binary: return "binary";
    case Format::Ascii: return "ascii";
    default: return "unknown";
  }
}

const char* colorConventionName(ColorConvention c) {
  switch (c) {
    case ColorConvention::VisCam: return "viscam";
    case ColorConvention::Magics: return "magics";
    default: return "none";
  }
}

}  // namespace stltopo
