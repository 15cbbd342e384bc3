// Test helpers: generate meshes and write them as binary or ASCII STL bytes.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "stltopo/stltopo.h"

namespace gen {

struct Soup {
  std::vector<std::array<float, 3>> v;     // vertices
  std::vector<std::array<uint32_t, 3>> f;  // faces (indices into v)
  std::vector<uint16_t> attr;              // optional per face
};

inline std::array<float, 3> normalOf(const Soup& s, size_t t) {
  auto& a = s.v[s.f[t][0]];
  auto& b = s.v[s.f[t][1]];
  auto& c = s.v[s.f[t][2]];
  double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  double wx = c[0] - a[0], wy = c[1] - a[1], wz = c[2] - a[2];
  double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
  double l = std::sqrt(nx * nx + ny * ny + nz * nz);
  if (l == 0) return {0, 0, 0};
  return {float(nx / l), float(ny / l), float(nz / l)};
}

inline std::string binary(const Soup& s, const std::string& header = "stltopo test") {
  std::string out(84, '\0');
  std::memcpy(&out[0], header.data(), std::min<size_t>(80, header.size()));
  uint32_t n = uint32_t(s.f.size());
  std::memcpy(&out[80], &n, 4);
  for (size_t t = 0; t < s.f.size(); ++t) {
    char rec[50];
    auto nn = normalOf(s, t);
    std::memcpy(rec, nn.data(), 12);
    for (int c = 0; c < 3; ++c) std::memcpy(rec + 12 + 12 * c, s.v[s.f[t][c]].data(), 12);
    uint16_t a = t < s.attr.size() ? s.attr[t] : 0;
    std::memcpy(rec + 48, &a, 2);
    out.append(rec, 50);
  }
  return out;
}

// Floats printed with %.9g read back exactly.
inline std::string ascii(const Soup& s, const std::string& name = "test") {
  std::string out = "solid " + name + "\n";
  char buf[256];
  for (size_t t = 0; t < s.f.size(); ++t) {
    auto nn = normalOf(s, t);
    std::snprintf(buf, sizeof buf, "  facet normal %.9g %.9g %.9g\n    outer loop\n", nn[0], nn[1], nn[2]);
    out += buf;
    for (int c = 0; c < 3; ++c) {
      auto& p = s.v[s.f[t][c]];
      std::snprintf(buf, sizeof buf, "      vertex %.9g %.9g %.9g\n", p[0], p[1], p[2]);
      out += buf;
    }
    out += "    endloop\n  endfacet\n";
  }
  out += "endsolid " + name + "\n";
  return out;
}

inline void append(Soup& dst, const Soup& src) {
  uint32_t base = uint32_t(dst.v.size());
  dst.v.insert(dst.v.end(), src.v.begin(), src.v.end());
  for (auto f : src.f) dst.f.push_back({f[0] + base, f[1] + base, f[2] + base});
}

// Axis-aligned cube [o, o+s]^3, outward winding, 12 triangles (2 per side).
inline Soup cube(float ox = 0, float oy = 0, float oz = 0, float s = 1) {
  Soup m;
  for (int i = 0; i < 8; ++i) m.v.push_back({ox + s * (i & 1), oy + s * ((i >> 1) & 1), oz + s * ((i >> 2) & 1)});
  // quads as (a,b,c,d) counter-clockwise seen from outside
  const uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& f : q) {
    m.f.push_back({f[0], f[1], f[2]});
    m.f.push_back({f[0], f[2], f[3]});
  }
  return m;
}

// Torus grid: n x m quads, 2 triangles each; `skip` quads (i*m + j) are left out (holes).
inline Soup torus(int n, int m, const std::vector<int>& skip = {}, float R = 3, float r = 1) {
  Soup s;
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      double u = 2 * pi * i / n, v = 2 * pi * j / m;
      s.v.push_back({float((R + r * std::cos(v)) * std::cos(u)), float((R + r * std::cos(v)) * std::sin(u)),
                     float(r * std::sin(v))});
    }
  auto id = [&](int i, int j) { return uint32_t(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      bool skipped = false;
      for (int k : skip) skipped |= k == i * m + j;
      if (skipped) continue;
      uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      s.f.push_back({a, b, c});
      s.f.push_back({a, c, d});
    }
  return s;
}

// A file that is a triangle soup for its first `soup` triangles (3 new vertices each, random
// points in [-50, 50]^3), then a 60 x 100 torus (12,000 triangles that weld), then `again`
// triangles on the soup's points: the reader's weld table, sized for a soup by then
// (Builder::growTable), has to weld the rest as the doubling one would.
inline Soup soupThenWelded(uint32_t soup = 6000, uint32_t again = 3000, unsigned seed = 5) {
  Soup s;
  uint64_t x = seed * 0x9E3779B97F4A7C15ull + 1;
  auto next = [&x] {  // splitmix64: the same points on every standard library
    uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  };
  auto coord = [&] { return float(int64_t(next() % 2000001) - 1000000) / 20000.0f; };
  for (uint32_t i = 0; i < 3 * soup; ++i) s.v.push_back({coord(), coord(), coord()});
  for (uint32_t i = 0; i < soup; ++i) s.f.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  append(s, torus(60, 100));
  for (uint32_t i = 0; i < again; ++i)
    s.f.push_back({uint32_t(next() % (3 * soup)), uint32_t(next() % (3 * soup)), uint32_t(next() % (3 * soup))});
  return s;
}

inline std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Whether a loop over every fixture that runs whole pipelines many times skips this file:
// only when STLTOPO_TEST_FIXTURE_BYTES_MAX is set and the file is larger. scripts/test-sanitize.sh
// sets it for the ASan+UBSan run, where the four largest fixtures (3-4 MB: 64% of the fixtures'
// triangles, no code path the smaller ones lack) took most of those loops' time; the Release
// run (scripts/test-native.sh) and the wasm run check every file.
inline bool skipLargeFixture(const std::string& path) {
  static const uint64_t limit = [] {
    const char* e = std::getenv("STLTOPO_TEST_FIXTURE_BYTES_MAX");
    return e ? std::strtoull(e, nullptr, 10) : 0;
  }();
  std::error_code ec;
  return limit > 0 && std::filesystem::file_size(path, ec) > limit;
}

#ifdef STLTOPO_FIXTURES  // the test suites (not the fuzz targets)
// Which files of tests/fixtures a loop over the fixtures reads: flags, or-ed.
enum FixtureSet : unsigned {
  kEveryFixture = 0,
  kWithoutRegress = 1,  // without regress/: the fuzz regressions, which have a test of their own
  kWithoutLarge = 2,    // without the files skipLargeFixture skips (in the sanitizer run)
};

// A fixture file's name: its path relative to tests/fixtures, with '/' separators.
inline std::string fixtureName(const std::string& path) {
  return std::filesystem::relative(path, STLTOPO_FIXTURES).generic_string();
}

// The fixture files (under STLTOPO_FIXTURES, tests/fixtures), as paths in sorted order: every
// regular file but the .md notes, less what `set` leaves out. The one list every test that loops
// over the fixtures reads.
inline std::vector<std::string> fixtureFiles(unsigned set = kEveryFixture) {
  namespace fs = std::filesystem;
  const fs::path root(STLTOPO_FIXTURES);
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file() || e.path().extension() == ".md") continue;
    const std::string path = e.path().string();
    if ((set & kWithoutRegress) && fixtureName(path).rfind("regress/", 0) == 0) continue;
    if ((set & kWithoutLarge) && skipLargeFixture(path)) continue;
    out.push_back(path);
  }
  std::sort(out.begin(), out.end());
  return out;
}

inline std::string fixturePath(const std::string& name) { return std::string(STLTOPO_FIXTURES) + "/" + name; }
#endif

inline stltopo::Status read(const std::string& bytes, stltopo::Mesh& m, const stltopo::ReadOptions& o = {}) {
  return stltopo::readStl(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), m, o);
}

inline stltopo::Status readChunked(const std::string& bytes, size_t chunk, stltopo::Mesh& m,
                                   const stltopo::ReadOptions& o = {}) {
  stltopo::Reader r(o);
  for (size_t i = 0; i < bytes.size(); i += chunk) {
    auto s = r.feed(reinterpret_cast<const uint8_t*>(bytes.data()) + i, std::min(chunk, bytes.size() - i));
    if (!s.ok()) return s;
  }
  return r.finish(m);
}

// Element-wise equality of two arrays (bit for bit).
template <class T>
inline bool sameArray(const stltopo::Array<T>& a, const stltopo::Array<T>& b) {
  return a.size() == b.size() && (a.size() == 0 || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Builds the topology of m again with TopologyOptions::prevAndFace = false and returns
// the first difference from `full` (built with the same tolerance and prevAndFace = true),
// or "" when the lean topology equals it in everything but the empty prev and face.
inline std::string leanTopologyDifference(const stltopo::Mesh& m, const stltopo::Topology& full, double tolerance = 0) {
  stltopo::TopologyOptions o;
  o.tolerance = tolerance;
  o.prevAndFace = false;
  stltopo::Topology lean;
  stltopo::Status s = stltopo::buildTopology(m, lean, o);
  if (!s.ok()) return "buildTopology: " + s.message;
  if (!lean.prev.empty() || !lean.face.empty()) return "prev or face was built";
#define STLTOPO_SAME(f) \
  if (!sameArray(lean.f, full.f)) return #f;
  STLTOPO_SAME(next)
  STLTOPO_SAME(vert) STLTOPO_SAME(pairKind) STLTOPO_SAME(triangleHalfedge) STLTOPO_SAME(vertexHalfedge)
      STLTOPO_SAME(vertexWeld) STLTOPO_SAME(loopHalfedge) STLTOPO_SAME(loopOffsets) STLTOPO_SAME(loopHalfedges)
          STLTOPO_SAME(loopIsSeam) STLTOPO_SAME(loopPerimeter) STLTOPO_SAME(triangleDegenerate)
              STLTOPO_SAME(vertexNonManifold)
#undef STLTOPO_SAME
                  if (stltopo::infoJson("f", m, &lean) != stltopo::infoJson("f", m, &full)) return "infoJson";
  if (lean.nHalfedges() > 0 && stltopo::validate(m, lean).code != stltopo::Code::Invalid)
    return "validate() accepted a topology without prev and face";
  return "";
}

// Whether two meshes have the same arrays, byte for byte (positions, triangles, attribute
// words, colours, normals).
inline bool sameMesh(const stltopo::Mesh& a, const stltopo::Mesh& b) {
  return sameArray(a.positions, b.positions) && sameArray(a.triangles, b.triangles) &&
         sameArray(a.attributes, b.attributes) && sameArray(a.colors, b.colors) &&
         sameArray(a.colorValid, b.colorValid) && sameArray(a.normals, b.normals);
}

}  // namespace gen
