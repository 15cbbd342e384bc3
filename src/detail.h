// Internal helpers shared by the core's translation units. Not installed.
#pragma once

#include <locale.h>

#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "float_format.h"
#include "stltopo/stltopo.h"

namespace stltopo::detail {

// std::bit_cast without <bit>: Emscripten 3.1.6's libc++ lacks it; the builtin is in
// both GCC and Clang.
template <class To, class From>
constexpr To bitCast(const From& from) noexcept {
  static_assert(sizeof(To) == sizeof(From));
  return __builtin_bit_cast(To, from);
}

// The "C" locale, for strtof_l/strtod_l: numbers never depend on the process locale.
locale_t cLocale();

// printf appended to a std::string, of any length (the report's text; may throw natively).
void appendf(std::string& out, const char* f, ...) __attribute__((format(printf, 2, 3)));
// printf into a new std::string, for status messages: never throws or aborts; when memory
// runs out the message is cut to what fits in the string itself.
std::string format(const char* f, ...) __attribute__((format(printf, 1, 2)));

// Whether malloc can give `bytes` now (the block is freed again). The standard containers
// throw (natively) or abort (wasm, built without exceptions) when an allocation fails, so
// every one whose size the input controls grows only after this probe said yes; the probe
// and the container's own allocation follow each other with nothing in between, so the
// container gets the block the probe just freed.
bool canAllocate(size_t bytes);

// Appends `v` to `vec` without a throw or abort: when `vec` is full, its grown buffer is
// probed first. False (and `vec` unchanged) when the probe fails.
template <class T>
bool tryPushBack(std::vector<T>& vec, T&& v) {
  if (vec.size() == vec.capacity()) {
    size_t cap = vec.capacity() < 4 ? 4 : vec.capacity() * 2;
    if (cap > vec.max_size() || !canAllocate(cap * sizeof(T))) return false;
    vec.reserve(cap);
  }
  vec.push_back(std::move(v));
  return true;
}

// A T in malloc'ed memory (placement new; T's constructor must not allocate): null when
// malloc fails. Never a throw, also where operator new would throw or abort.
template <class T, class... Args>
T* tryNew(Args&&... args) {
  void* p = std::malloc(sizeof(T));
  return p ? new (p) T(std::forward<Args>(args)...) : nullptr;
}
// Destroys and frees a tryNew() object; null is allowed.
template <class T>
void tryDelete(T* p) {
  if (!p) return;
  p->~T();
  std::free(p);
}

// s = [p, p + n) without a throw or abort (probed as tryPushBack). False: `s` unchanged.
bool tryAssign(std::string& s, const char* p, size_t n);
// s = [p, p + n) or, when the probe fails, as much of it as fits in s without allocating:
// for messages, which would rather be cut than throw.
void assignOrCut(std::string& s, const char* p, size_t n);
// Reserves `n` bytes in `s` (probed). After it, appends up to n bytes never allocate.
bool tryReserve(std::string& s, size_t n);

// One triangle's figures, the formulas of Mesh::area, Mesh::volume and
// Mesh::normalMismatches, in float64 from float32 corners: the cross product
// n = (b - a) x (c - a), the area |n| / 2, and the signed volume of the tetrahedron
// (origin, a, b, c). Every figure of the library goes through here, so that they agree to
// the bit.
struct TriangleFigures {
  double nx, ny, nz, area, volume;
};
inline TriangleFigures triangleFigures(const float* a, const float* b, const float* c) {
  double ax = a[0], ay = a[1], az = a[2], bx = b[0], by = b[1], bz = b[2], cx = c[0], cy = c[1], cz = c[2];
  double ux = bx - ax, uy = by - ay, uz = bz - az, wx = cx - ax, wy = cy - ay, wz = cz - az;
  TriangleFigures f;
  f.nx = uy * wz - uz * wy;
  f.ny = uz * wx - ux * wz;
  f.nz = ux * wy - uy * wx;
  f.area = 0.5 * std::sqrt(f.nx * f.nx + f.ny * f.ny + f.nz * f.nz);
  f.volume = (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0;
  return f;
}
// Whether a stored normal n points against the winding (Mesh::normalMismatches).
inline bool normalMismatch(const float* n, const TriangleFigures& f) {
  return (n[0] != 0.0f || n[1] != 0.0f || n[2] != 0.0f) && double(n[0]) * f.nx + double(n[1]) * f.ny + double(n[2]) * f.nz < 0;
}

// A JSON writer for the reports: s holds the text, `first` whether the next key or
// element is the first of its object or array.
struct Json {
  std::string s;
  bool first = true;
  void open(char c) { s += c; first = true; }
  void close(char c) { s += c; first = false; }
  void key(const char* k) {
    if (!first) s += ',';
    first = false;
    s += '"';
    s += k;
    s += "\":";
  }
  void sep() {
    if (!first) s += ',';
    first = false;
  }
  void u(uint64_t v) { s += std::to_string(v); }
  void i(int64_t v) { s += std::to_string(v); }
  void str(const std::string& v) { s += jsonString(v); }
  void b(bool v) { s += v ? "true" : "false"; }
  void null() { s += "null"; first = false; }
  // A float32 coordinate (-0 printed as 0) or a float64 figure, in shortest form.
  void f32(float v) { s += shortest(v + 0.0f, true); }
  void f64(double v) { s += shortest(v, false); }
  // [x,y,z] of float32 coordinates, and {"min":[..],"max":[..]}.
  void point(const float* p) {
    s += '[';
    for (int k = 0; k < 3; ++k) {
      if (k) s += ',';
      f32(p[k]);
    }
    s += ']';
  }
  void bbox(const float* lo, const float* hi) {
    open('{');
    key("min"); point(lo);
    key("max"); point(hi);
    close('}');
  }
};

// The report's "shellList" and "defects" keys with their values (shells_report.cpp).
// With `nesting` (of these shells), each shell also gets its intersection and nesting keys.
void writeShellList(Json& j, const Array<Shell>& shells, const ShellNesting* nesting = nullptr);
// `checks` null: computed here; `intersections` null: "selfIntersections" is null.
void writeDefects(Json& j, const Mesh& mesh, const Topology& topo, const Defects& defects, uint32_t maxPerKind,
                  const TriangleChecks* checks = nullptr, const Intersections* intersections = nullptr);
// How infoJson/infoText write the ReportExtras (shells_report.cpp), handed to the report
// (report.cpp) so that the plain report does not depend on them.
struct ExtrasWriter {
  const ReportExtras& extras;
  void (*json)(Json& j, const Mesh& mesh, const Topology& topo, const ReportExtras& extras);
  void (*text)(std::string& out, const Mesh& mesh, const Topology& topo, const ReportExtras& extras);
  // The intersection keys / line, when extras.intersections is given.
  void (*geometryJson)(Json& j, const ReportExtras& extras);
  void (*geometryText)(std::string& out, const ReportExtras& extras);
};
std::string infoJsonWith(const std::string& file, const Mesh& mesh, const Topology* topo, const ExtrasWriter* extras);
std::string infoTextWith(const std::string& file, const Mesh& mesh, const Topology* topo, const ExtrasWriter* extras);

}  // namespace stltopo::detail
