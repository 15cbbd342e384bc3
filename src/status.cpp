#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "stltopo/array.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "text_format.h"
#include "try_alloc.h"

#if defined(__linux__) && !defined(__EMSCRIPTEN__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace stltopo {

#if defined(__EMSCRIPTEN__)
float detail::strtofC(const char* s, char** end) { return std::strtof(s, end); }
double detail::strtodC(const char* s, char** end) { return std::strtod(s, end); }
#else
static locale_t cLocale() {
  static locale_t loc = newlocale(LC_ALL_MASK, "C", locale_t(0));
  return loc;
}
float detail::strtofC(const char* s, char** end) { return strtof_l(s, end, cLocale()); }
double detail::strtodC(const char* s, char** end) { return strtod_l(s, end, cLocale()); }
#endif

static void vappendf(std::string& out, const char* f, va_list ap) {
  char buf[512];
  va_list again;
  va_copy(again, ap);
  int n = std::vsnprintf(buf, sizeof buf, f, ap);
  if (n >= 0 && size_t(n) < sizeof buf) {
    out.append(buf, size_t(n));
  } else if (n >= 0) {
    std::string big(size_t(n) + 1, '\0');
    std::vsnprintf(big.data(), big.size(), f, again);
    out.append(big.data(), size_t(n));
  }
  va_end(again);
}

void detail::appendf(std::string& out, const char* f, ...) {
  va_list ap;
  va_start(ap, f);
  vappendf(out, f, ap);
  va_end(ap);
}

std::string detail::format(const char* f, ...) {
  char buf[512];
  va_list ap, again;
  va_start(ap, f);
  va_copy(again, ap);
  int n = std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  std::string out;
  if (n >= 0 && size_t(n) < sizeof buf) {
    assignOrCut(out, buf, size_t(n));
  } else if (n >= 0 && tryReserve(out, size_t(n))) {
    out.resize(size_t(n));  // within the capacity reserved
    std::vsnprintf(out.data(), size_t(n) + 1, f, again);
  } else {
    assignOrCut(out, buf, sizeof buf - 1);
  }
  va_end(again);
  return out;
}

Status Status::error(Code c, const std::string& msg, uint64_t offset, uint64_t line, uint32_t triangle) {
  Status s;
  s.code = c;
  const char* name = codeName(c);
  size_t nameBytes = std::strlen(name);
  if (detail::tryReserve(s.message, nameBytes + 2 + msg.size())) {
    s.message.append(name, nameBytes).append(": ", 2).append(msg);
  } else {
    detail::assignOrCut(s.message, name, nameBytes);
  }
  s.offset = offset;
  s.line = line;
  s.triangle = triangle;
  return s;
}

bool detail::canAllocate(size_t bytes) {
  void* p = std::malloc(bytes);
  if (!p) return false;
  // The block goes through a volatile so that the compiler cannot drop the malloc/free pair
  // as unused. A local one: threads that probe at once (info --jobs N) each free their own
  // block (a shared global let one thread free another's block twice).
  void* volatile sink = p;
  std::free(sink);
  return true;
}

bool detail::tryReserve(std::string& s, size_t n) {
  if (n <= s.capacity()) return true;
  // The string library grows to at least twice the old capacity: probe what it will take.
  size_t grown = std::max(n, 2 * s.capacity());
  if (n >= s.max_size() || !canAllocate(grown + 1)) return false;
  s.reserve(n);
  return true;
}

void detail::assignOrCut(std::string& s, const char* p, size_t n) {
  if (tryAssign(s, p, n)) return;
  s.assign(p, std::min(n, s.capacity()));  // what fits without allocating
}

bool detail::tryAssign(std::string& s, const char* p, size_t n) {
  if (!tryReserve(s, n)) return false;
  s.assign(p, n);
  return true;
}

Status detail::oom(const char* what) { return Status::error(Code::OutOfMemory, format("could not allocate %s", what)); }

namespace {
// Advice for the whole 2 MiB-aligned stretches of [p, p + bytes): only those can be huge pages.
void advisePages(void* p, size_t bytes, bool huge) {
#if defined(__linux__) && !defined(__EMSCRIPTEN__) && defined(MADV_HUGEPAGE)
  const uintptr_t size = uintptr_t(2) << 20;
  uintptr_t begin = (reinterpret_cast<uintptr_t>(p) + size - 1) & ~(size - 1);
  uintptr_t end = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(size - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
#else
  (void)p;
  (void)bytes;
  (void)huge;
#endif
}
}  // namespace

void detail::adviseHugePages(void* p, size_t bytes) { advisePages(p, bytes, true); }

void detail::adviseSmallPages(void* p, size_t bytes) { advisePages(p, bytes, false); }

namespace {
// Indexed by Code; the static_assert keeps it in step with the enum.
constexpr const char* kCodeNames[] = {
    "ok",
    "empty",
    "not-stl",
    "truncated",
    "unexpected-end",
    "ascii-syntax",
    "non-finite",
    "too-large",
    "out-of-memory",
    "invalid-argument",
    "aborted",
    "invalid",
    "trailing-bytes",
    "missing-endsolid",
    "name-truncated",
    "invalid-index",
    "write-failed",
    "wasm-load",
    "edit-refused",
};
static_assert(sizeof(kCodeNames) / sizeof(kCodeNames[0]) == size_t(kCodeCount), "one name per Code");
}  // namespace

const char* codeName(Code c) {
  int i = int(c);
  return i >= 0 && i < kCodeCount ? kCodeNames[i] : "unknown";
}

bool codeFromName(const char* name, Code& out) {
  for (int i = 0; i < kCodeCount; ++i)
    if (std::strcmp(name, kCodeNames[i]) == 0) {
      out = Code(i);
      return true;
    }
  return false;
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
