// Reading: detection, ASCII grammar, streaming, welding, colours, errors.
#include <gtest/gtest.h>

#include <locale.h>
#include <cmath>
#include <cstdlib>
#include <map>
#include <random>

#include "predicates.h"  // private (src/): the normal mismatch's exact sign, checked below
#include "stl_gen.h"
#include "triangle_figures.h"  // private (src/): and its filter

using namespace stltopo;

namespace {

void expectSameMesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  EXPECT_EQ(0, std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(float)));
  EXPECT_EQ(0, std::memcmp(a.triangles.data(), b.triangles.data(), a.triangles.size() * sizeof(uint32_t)));
}

void expectIdentical(const Mesh& a, const Mesh& b) {
  expectSameMesh(a, b);
  EXPECT_EQ(a.format, b.format);
  ASSERT_EQ(a.solids.size(), b.solids.size());
  for (size_t i = 0; i < a.solids.size(); ++i) {
    EXPECT_EQ(a.solids[i].name, b.solids[i].name);
    EXPECT_EQ(a.solids[i].triangleCount, b.solids[i].triangleCount);
  }
  ASSERT_EQ(a.warnings.size(), b.warnings.size());
  for (size_t i = 0; i < a.warnings.size(); ++i) EXPECT_EQ(a.warnings[i].message, b.warnings[i].message);
  EXPECT_EQ(a.attributes.size(), b.attributes.size());
  EXPECT_EQ(a.colorConvention, b.colorConvention);
  EXPECT_EQ(a.normalMismatches, b.normalMismatches);
  EXPECT_DOUBLE_EQ(a.volume, b.volume);
}

Status readErr(const std::string& bytes, const ReadOptions& o = {}) {
  Mesh m;
  return gen::read(bytes, m, o);
}

// The normal test before it was exact: the dot product in double with the figures' cross
// product, for the tests to show what it got wrong.
bool mismatchInDouble(const float* n, const float* a, const float* b, const float* c) {
  const detail::TriangleFigures f = detail::triangleFigures(a, b, c);
  return n[0] * f.nx + n[1] * f.ny + n[2] * f.nz < 0;
}

std::string facet(const char* v1, const char* v2, const char* v3) {
  return std::string("facet normal 0 0 1\n outer loop\n  vertex ") + v1 + "\n  vertex " + v2 + "\n  vertex " + v3 +
         "\n endloop\nendfacet\n";
}

}  // namespace

TEST(ReadStl, BinaryAndAsciiOfTheSameMeshGiveIdenticalArrays) {
  gen::Soup s = gen::torus(12, 8);
  Mesh a, b;
  ASSERT_TRUE(gen::read(gen::binary(s), a).ok());
  ASSERT_TRUE(gen::read(gen::ascii(s), b).ok());
  EXPECT_EQ(a.format, Format::Binary);
  EXPECT_EQ(b.format, Format::Ascii);
  EXPECT_EQ(a.nTriangles(), 192u);
  EXPECT_EQ(a.nVertices(), 96u);
  expectSameMesh(a, b);
}

TEST(ReadStl, ChunkedReadingEqualsWholeBuffer) {
  gen::Soup s = gen::torus(10, 6, {3, 17});
  s.attr.assign(s.f.size(), 0x8000 | 0x1234);
  std::string cat = gen::binary(s, "first part") + gen::binary(gen::cube(5, 5, 5), "second part") + "\n";
  std::string asc = gen::ascii(s, "one") + "\r\n" + gen::ascii(gen::cube(), "two");
  std::string crOnly = asc;
  for (char& c : crOnly)
    if (c == '\n') c = '\r';
  for (const std::string* bytes : {&cat, &asc, &crOnly}) {
    Mesh whole;
    ASSERT_TRUE(gen::read(*bytes, whole).ok());
    for (size_t chunk : {1, 7, 50, 4096}) {
      Mesh m;
      ASSERT_TRUE(gen::readChunked(*bytes, chunk, m).ok()) << chunk;
      expectIdentical(whole, m);
    }
  }
}

TEST(ReadStl, ChunkedReadingOfEveryFixtureEqualsWholeBuffer) {
  const char* files[] = {"wolph_numpy-stl/tests/stl_binary/HalfDonut.stl",
                         "wolph_numpy-stl/tests/stl_ascii/HalfDonut.stl",
                         "mikedh_trimesh/models/multibody.stl",
                         "wolph_numpy-stl/tests/stl_tests/dos.stl",
                         "mikedh_trimesh/models/20mm-xyz-cube.stl",
                         "Pix4D_OpenMesh/src/Unittests/TestFiles/cube1.stl"};
  for (const char* f : files) {
    std::string bytes = gen::readFile(gen::fixturePath(f));
    ASSERT_FALSE(bytes.empty()) << f;
    Mesh whole;
    ASSERT_TRUE(gen::read(bytes, whole).ok()) << f;
    for (size_t chunk : {7, 50, 4096}) {
      Mesh m;
      ASSERT_TRUE(gen::readChunked(bytes, chunk, m).ok()) << f << " " << chunk;
      expectIdentical(whole, m);
    }
  }
}

TEST(ReadStl, SolidHeaderWithExactBinarySizeIsBinary) {
  gen::Soup s = gen::cube();
  std::string b = gen::binary(s, "solid looks like ascii");
  Mesh m;
  ASSERT_TRUE(gen::read(b, m).ok());
  EXPECT_EQ(m.format, Format::Binary);
  EXPECT_EQ(m.solids[0].name, "solid looks like ascii");
  Mesh c;
  ASSERT_TRUE(gen::readChunked(b, 1, c).ok());
  EXPECT_EQ(c.format, Format::Binary);
}

TEST(ReadStl, TrailingBytesAreAcceptedWithAWarning) {
  std::string b = gen::binary(gen::cube(), "solid x") + std::string(83, 'z');
  Mesh m;
  ASSERT_TRUE(gen::read(b, m).ok());
  EXPECT_EQ(m.nTriangles(), 12u);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_EQ(m.warnings[0].code, Code::TrailingBytes);
  EXPECT_EQ(m.warnings[0].offset, 84u + 600u);
}

TEST(ReadStl, ConcatenatedBinaryFilesFormOneComplex) {
  std::string b = gen::binary(gen::cube(), "  alpha \0junk") + gen::binary(gen::cube(1, 0, 0), "beta");
  Mesh m;
  ASSERT_TRUE(gen::read(b, m).ok());
  ASSERT_EQ(m.solids.size(), 2u);
  EXPECT_EQ(m.solids[0].name, "alpha");
  EXPECT_EQ(m.solids[1].name, "beta");
  EXPECT_EQ(m.solids[1].firstTriangle, 12u);
  EXPECT_EQ(m.nTriangles(), 24u);
  EXPECT_EQ(m.nVertices(), 12u);  // the shared face welds across solids
}

TEST(ReadStl, AsciiKeywordsAnyCaseWhitespaceAndBom) {
  std::string f =
      "\xEF\xBB\xBF  \t\r\nSOLID  Mixed Name  \r\n  FaCeT NoRmAl 0 0 1\r  OUTER\tLOOP\n"
      "VERTEX 0 0 0 vertex 1 0 0\n vertex 0 1 0\n ENDLOOP trailing words\n ENDFACET more\nEndSolid Mixed\n";
  Mesh m;
  Status s = gen::read(f, m);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(m.format, Format::Ascii);
  ASSERT_EQ(m.solids.size(), 1u);
  EXPECT_EQ(m.solids[0].name, "Mixed Name");
  EXPECT_EQ(m.nTriangles(), 1u);
}

TEST(ReadStl, SeveralSolidsWithEmptyAndUtf8Names) {
  std::string f = "solid\n" + facet("0 0 0", "1 0 0", "0 1 0") + "endsolid\nsolid \xE6\x9C\x88\xE7\x90\x83\nendsolid\n";
  Mesh m;
  ASSERT_TRUE(gen::read(f, m).ok());
  ASSERT_EQ(m.solids.size(), 2u);
  EXPECT_EQ(m.solids[0].name, "");
  EXPECT_EQ(m.solids[0].triangleCount, 1u);
  EXPECT_EQ(m.solids[1].name, "\xE6\x9C\x88\xE7\x90\x83");
  EXPECT_EQ(m.solids[1].triangleCount, 0u);
}

TEST(ReadStl, NumbersFollowStrtofInTheCLocale) {
  const char* nums[] = {"1",
                        "-0",
                        "+1.5",
                        ".5",
                        "1.",
                        "1E+02",
                        "-1.25e-3",
                        "0x1p-2",
                        "3.4028234e38",
                        "0.1000000000000000055511151231257827",
                        "1.00000005960464477539062",
                        "7e-46",
                        "16777217",
                        "123456789012345678901234567890",
                        "1.17549435e-38",
                        "0.3",
                        "3.99999976",
                        "-123.456789012",
                        "1.5e-20",
                        "9.87654321e21",
                        "33554435",
                        "0.000000000000000000000000000001"};
  setlocale(LC_NUMERIC, "de_DE.UTF-8");  // the reader must not care (it may not exist; then a no-op)
  for (const char* n : nums) {
    std::string f =
        std::string("solid n\n") + facet((std::string(n) + " 0 0").c_str(), "1 1 0", "0 1 1") + "endsolid\n";
    Mesh m;
    Status s = gen::read(f, m);
    ASSERT_TRUE(s.ok()) << n << ": " << s.message;
    locale_t c = newlocale(LC_ALL_MASK, "C", locale_t(0));
    float expected = strtof_l(n, nullptr, c);
    freelocale(c);
    uint32_t a, b;
    std::memcpy(&a, &m.positions[0], 4);
    std::memcpy(&b, &expected, 4);
    EXPECT_EQ(a, b) << n;
  }
  setlocale(LC_NUMERIC, "C");
}

TEST(ReadStl, RandomDecimalNumbersMatchStrtof) {
  // Many digit counts and exponents, through the fast paths and the fallback alike.
  std::mt19937_64 rng(42);
  std::vector<std::string> nums;
  std::string f = "solid r\n";
  char buf[96];
  for (int i = 0; i < 20000; ++i) {
    int digits = 1 + int(rng() % 20);
    std::string mant;
    for (int d = 0; d < digits; ++d) mant += char('0' + rng() % 10);
    size_t dot = rng() % (mant.size() + 1);
    mant.insert(dot, ".");
    if (mant == ".") mant = "0.5";
    int ex = int(rng() % 49) - 30;  // stays below FLT_MAX (3.4e38)
    std::snprintf(buf, sizeof buf, "%s%se%d", rng() % 2 ? "-" : "", mant.c_str(), ex);
    nums.push_back(buf);
    // Vertex i is (number, i, 0): distinct, so positions[3*(3i)] is the number.
    std::snprintf(buf, sizeof buf, "%d", i);
    f += facet((nums.back() + " " + buf + " 0").c_str(), (std::string("1 ") + buf + " 1").c_str(),
               (std::string("2 ") + buf + " 2").c_str());
  }
  f += "endsolid\n";
  Mesh m;
  Status s = gen::read(f, m);
  ASSERT_TRUE(s.ok()) << s.message;
  locale_t c = newlocale(LC_ALL_MASK, "C", locale_t(0));
  for (size_t i = 0; i < nums.size(); ++i) {
    float expected = strtof_l(nums[i].c_str(), nullptr, c);
    uint32_t a, b;
    std::memcpy(&a, &m.positions[9 * i], 4);
    std::memcpy(&b, &expected, 4);
    ASSERT_EQ(a, b) << nums[i];
  }
  freelocale(c);
}

TEST(ReadStl, NegativeZeroWeldsWithPositiveZero) {
  std::string f = "solid z\n" + facet("-0 0 0", "1 0 0", "0 1 0") + facet("0 -0 0", "0 1 0", "1 0 0") + "endsolid\n";
  Mesh m;
  ASSERT_TRUE(gen::read(f, m).ok());
  EXPECT_EQ(m.nVertices(), 3u);
  EXPECT_TRUE(std::signbit(m.positions[0]));  // first-seen coordinates are kept as written
  EXPECT_EQ(m.triangles[3], 0u);
}

TEST(ReadStl, VertexIdsFollowFirstAppearance) {
  std::string f = "solid z\n" + facet("5 5 5", "1 0 0", "0 1 0") + facet("0 1 0", "1 0 0", "9 9 9") + "endsolid\n";
  Mesh m;
  ASSERT_TRUE(gen::read(f, m).ok());
  const uint32_t expected[6] = {0, 1, 2, 2, 1, 3};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(m.triangles[i], expected[i]);
  EXPECT_EQ(m.positions[9], 9.0f);
}

// Exact welding by first appearance, whatever size the weld table had: a file whose first
// part is a soup (the table is then sized at once for 3 vertices a triangle, where it doubled
// before) and whose rest welds, against a brute-force weld, whole (the input's size known, so
// the table is sized for a soup) and in chunks (size unknown: the table doubles).
TEST(ReadStl, ASoupThatWeldsLaterGetsTheIdsOfFirstAppearance) {
  const gen::Soup s = gen::soupThenWelded();
  const std::string bytes = gen::binary(s);
  std::map<std::array<uint32_t, 3>, uint32_t> ids;  // coordinates' bits (-0 as +0) -> id
  std::vector<float> positions;
  std::vector<uint32_t> triangles;
  for (const auto& f : s.f)
    for (uint32_t c : f) {
      const auto& p = s.v[c];
      std::array<uint32_t, 3> key;
      for (int k = 0; k < 3; ++k) {
        const float z = p[size_t(k)] + 0.0f;
        std::memcpy(&key[size_t(k)], &z, 4);
      }
      auto [it, fresh] = ids.emplace(key, uint32_t(ids.size()));
      if (fresh) positions.insert(positions.end(), p.begin(), p.end());
      triangles.push_back(it->second);
    }
  Mesh whole, chunked;
  ASSERT_TRUE(gen::read(bytes, whole).ok());
  ASSERT_TRUE(gen::readChunked(bytes, 4096, chunked).ok());
  ASSERT_EQ(whole.nVertices(), ids.size());
  ASSERT_EQ(whole.triangles.size(), triangles.size());
  EXPECT_EQ(std::memcmp(whole.positions.data(), positions.data(), positions.size() * 4), 0);
  EXPECT_EQ(std::memcmp(whole.triangles.data(), triangles.data(), triangles.size() * 4), 0);
  EXPECT_TRUE(gen::sameMesh(whole, chunked));
  // Sized once for the soup's projected 3 vertices a triangle (10,517 + 3 x 17,495), where
  // doubling from half a vertex a triangle stops at 42,064 vertices.
  EXPECT_GE(whole.positions.capacity(), 3u * 63002u);
  EXPECT_LT(chunked.positions.capacity(), 3u * 63002u);
}

TEST(ReadStl, VisCamColours) {
  gen::Soup s = gen::cube();
  s.attr.assign(12, 0);
  s.attr[0] = 0x8000 | (31 << 10) | (0 << 5) | 1;  // R=31, G=0, B=1
  std::string b = gen::binary(s, "no colour header");
  Mesh m;
  ASSERT_TRUE(gen::read(b, m).ok());
  EXPECT_EQ(m.colorConvention, ColorConvention::VisCam);
  EXPECT_EQ(m.colors[0], 255);
  EXPECT_EQ(m.colors[1], 0);
  EXPECT_EQ(m.colors[2], 8);
  EXPECT_EQ(m.colorValid[0], 1);
  EXPECT_EQ(m.colorValid[1], 0);
  EXPECT_EQ(m.attributes[0], s.attr[0]);
}

TEST(ReadStl, MagicsColours) {
  gen::Soup s = gen::cube();
  s.attr.assign(12, 0x8000);                 // default colour
  s.attr[3] = (31) | (16 << 5) | (0 << 10);  // own colour R=31, G=16, B=0
  std::string header = std::string("COLOR=") + char(10) + char(20) + char(30) + char(255) + " MATERIAL=abcdefghijkl";
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(s, header), m).ok());
  EXPECT_EQ(m.colorConvention, ColorConvention::Magics);
  EXPECT_EQ(m.colors[0], 10);
  EXPECT_EQ(m.colors[1], 20);
  EXPECT_EQ(m.colors[2], 30);
  EXPECT_EQ(m.colors[9], 255);
  EXPECT_EQ(m.colors[10], 132);
  EXPECT_EQ(m.colors[11], 0);
  for (int t = 0; t < 12; ++t) EXPECT_EQ(m.colorValid[t], 1);
}

// A stored normal points against the winding when n . ((b - a) x (c - a)) < 0, decided
// exactly (detail::normalMismatch: a filter, then pred::normalDotExact). Integer corners
// within 2^21 and normals n = alpha u + beta w (u = b - a, w = c - a, alpha and beta in
// {-1, 0, 1}), each nudged by 1 on one axis in half the cases: n is perpendicular to the
// normal, or nearly, and each term n_k N_k has some 70 bits, so the dot product in double is
// often a rounding error of either sign. The reference is the dot product in 128-bit
// integers. The reader counts the exact answer, in binary and in ASCII, on one thread and on
// two, and so do an EditableMesh's toMesh() and extractShell().
TEST(ReadStl, NormalMismatchIsDecidedExactly) {
  std::mt19937_64 rng(3);
  auto coord = [&]() { return float(int64_t(rng() % (uint64_t(1) << 22)) - (int64_t(1) << 21)); };
  gen::Soup s;
  std::vector<std::array<float, 3>> normals;
  uint32_t exact = 0, inDouble = 0, ties = 0;
  for (int i = 0; i < 60000; ++i) {
    float p[3][3];
    for (auto& q : p)
      for (float& x : q) x = coord();
    float u[3], w[3], n[3];
    for (int k = 0; k < 3; ++k) u[k] = p[1][k] - p[0][k], w[k] = p[2][k] - p[0][k];
    const int alpha = int(rng() % 3) - 1, beta = int(rng() % 3) - 1;
    for (int k = 0; k < 3; ++k) n[k] = float(alpha * int64_t(u[k]) + beta * int64_t(w[k]));
    if (rng() % 2) n[rng() % 3] += rng() % 2 ? 1.0f : -1.0f;
    __int128 N[3], dot = 0;
    for (int k = 0; k < 3; ++k) {
      const int i1 = (k + 1) % 3, i2 = (k + 2) % 3;
      N[k] = __int128(int64_t(u[i1])) * int64_t(w[i2]) - __int128(int64_t(u[i2])) * int64_t(w[i1]);
      dot += N[k] * int64_t(n[k]);
    }
    const int want = dot > 0 ? 1 : dot < 0 ? -1 : 0;
    ASSERT_EQ(detail::normalMismatch(n, detail::triangleFigures(p[0], p[1], p[2]), p[0], p[1], p[2]), want < 0) << i;
    ASSERT_EQ(pred::normalDotExact(n, p[0], p[1], p[2]), want) << i;
    const bool stored = n[0] != 0 || n[1] != 0 || n[2] != 0;
    exact += stored && want < 0;
    inDouble += stored && mismatchInDouble(n, p[0], p[1], p[2]);
    ties += stored && want == 0;
    const uint32_t base = uint32_t(s.v.size());
    for (auto& q : p) s.v.push_back({q[0], q[1], q[2]});
    s.f.push_back({base, base + 1, base + 2});
    normals.push_back({n[0], n[1], n[2]});
  }
  EXPECT_GT(ties, 1000u);
  EXPECT_NE(exact, inDouble) << exact;  // the double dot product gets some wrong
  // Corners of any magnitude (their differences inexact in double): a normal n = d - a that is
  // a float, d in or near the plane of (a, b, c), checked against pred::orient3d(a, b, c, d),
  // the same determinant (independently tested against CGAL).
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0, wrong = 0;
  for (int i = 0; i < 100000; ++i) {
    float p[4][3];
    const int e = int(rng() % 60) - 30;
    for (int q = 0; q < 3; ++q)
      for (int k = 0; k < 3; ++k) p[q][k] = float(std::ldexp(unit(rng), e + int(rng() % 8)));
    // d in the plane (b or c: an exact tie) or near it
    const int kind = int(rng() % 3);
    const double s = unit(rng), t = unit(rng);
    for (int k = 0; k < 3; ++k)
      p[3][k] = kind < 2 ? p[1 + kind][k]
                         : float(p[0][k] + s * (double(p[1][k]) - p[0][k]) + t * (double(p[2][k]) - p[0][k]));
    float n[3];
    bool exactN = true;
    for (int k = 0; k < 3; ++k) {
      n[k] = p[3][k] - p[0][k];
      exactN = exactN && double(n[k]) == double(p[3][k]) - double(p[0][k]);
    }
    if (!exactN || !std::isfinite(n[0] + n[1] + n[2])) continue;
    ++checked;
    const int want = pred::orient3d(p[0], p[1], p[2], p[3]);
    wrong += mismatchInDouble(n, p[0], p[1], p[2]) != (want < 0);
    ASSERT_EQ(detail::normalMismatch(n, detail::triangleFigures(p[0], p[1], p[2]), p[0], p[1], p[2]), want < 0) << i;
    if (n[0] != 0 || n[1] != 0 || n[2] != 0) ASSERT_EQ(pred::normalDotExact(n, p[0], p[1], p[2]), want) << i;
  }
  EXPECT_GT(checked, 5000);
  EXPECT_GT(wrong, 0) << checked;
  std::string bin = gen::binary(s);
  std::string ascii = "solid exact\n";
  char line[200];
  for (size_t t = 0; t < s.f.size(); ++t) {
    std::memcpy(&bin[84 + 50 * t], normals[t].data(), 12);
    std::snprintf(line, sizeof line, "facet normal %.9g %.9g %.9g\nouter loop\n", normals[t][0], normals[t][1],
                  normals[t][2]);
    ascii += line;
    for (int c = 0; c < 3; ++c) {
      const auto& q = s.v[3 * t + size_t(c)];
      std::snprintf(line, sizeof line, "vertex %.9g %.9g %.9g\n", q[0], q[1], q[2]);
      ascii += line;
    }
    ascii += "endloop\nendfacet\n";
  }
  ascii += "endsolid exact\n";
  for (unsigned threads : {1u, 2u}) {
    setParallelGrainForTesting(threads == 2 ? 1 : 0);
    for (const std::string* bytes : {&bin, &ascii}) {
      ReadOptions o;
      o.threads = threads;
      o.keepNormals = true;
      Mesh m;
      const uint64_t splits = parallelSplitsForTesting();
      ASSERT_TRUE(gen::read(*bytes, m, o).ok());
      EXPECT_EQ(m.normalMismatches, exact) << threads << (bytes == &bin ? " binary" : " ascii");
#if !defined(STLTOPO_WASM_TESTS)
      if (threads == 2 && bytes == &bin) EXPECT_GT(parallelSplitsForTesting(), splits) << "the threaded read";
#endif
      if (threads == 2 || bytes != &bin) continue;
      EditableMesh em;
      ASSERT_TRUE(em.init(m).ok());
      Mesh back;
      ASSERT_TRUE(em.toMesh(back).ok());
      EXPECT_EQ(back.normalMismatches, exact);
      // One shell of the soup's first triangles is each a shell of its own: extract one whose
      // normal is a tie that the double formula counted.
      Topology topo;
      TopologyOptions to;
      to.triangleShell = true;
      ASSERT_TRUE(buildTopology(m, topo, to).ok());
      bool extracted = false;
      for (uint32_t t = 0; t < m.nTriangles(); ++t) {
        const float* P = m.positions.data();
        const uint32_t* c = m.triangles.data() + 3 * size_t(t);
        const float *n = m.normals.data() + 3 * size_t(t), *a = P + 3 * size_t(c[0]), *b = P + 3 * size_t(c[1]),
                    *d = P + 3 * size_t(c[2]);
        if (pred::normalDotExact(n, a, b, d) != 0 || topo.triangleShell[t] == kInvalid || !mismatchInDouble(n, a, b, d))
          continue;
        Mesh one;
        ASSERT_TRUE(extractShell(m, topo, topo.triangleShell[t], one).ok());
        EXPECT_EQ(one.normalMismatches, 0u) << t;
        extracted = true;
        break;
      }
      EXPECT_TRUE(extracted);
    }
  }
  setParallelGrainForTesting(0);
}

TEST(ReadStl, NormalsAreKeptOnRequestAndMismatchesCounted) {
  gen::Soup s = gen::cube();
  std::string b = gen::binary(s);
  // Flip the stored normal of triangle 2.
  for (int k = 0; k < 3; ++k) {
    float x;
    std::memcpy(&x, &b[84 + 2 * 50 + 4 * k], 4);
    x = -x;
    std::memcpy(&b[84 + 2 * 50 + 4 * k], &x, 4);
  }
  ReadOptions o;
  o.keepNormals = true;
  Mesh m;
  ASSERT_TRUE(gen::read(b, m, o).ok());
  EXPECT_EQ(m.normalMismatches, 1u);
  ASSERT_EQ(m.normals.size(), 36u);
  EXPECT_EQ(m.normals[6 + 2], -1.0f);  // triangle 2 is a top (+z) triangle, stored flipped
}

TEST(ReadStl, VolumeAndAreaOfAUnitCube) {
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(gen::cube(0, 0, 0, 2)), m).ok());
  EXPECT_NEAR(m.volume, 8.0, 1e-12);
  EXPECT_NEAR(m.area, 24.0, 1e-12);
  EXPECT_EQ(m.bboxMax[0], 2.0f);
}

// --- errors, each with its location -----------------------------------------

TEST(ReadStlErrors, EmptyInput) {
  Status s = readErr("");
  EXPECT_EQ(s.code, Code::Empty);
}

TEST(ReadStlErrors, ShortNonSolidInputIsNotStl) {
  Status s = readErr("hello world, this is not an STL file");
  EXPECT_EQ(s.code, Code::NotStl);
  EXPECT_NE(s.message.find("84"), std::string::npos);
}

TEST(ReadStlErrors, TruncatedBinaryStatesCountBytesAndOffset) {
  std::string b = gen::binary(gen::cube(), "trunc");
  b.resize(84 + 50 * 5 + 20);
  Status s = readErr(b);
  EXPECT_EQ(s.code, Code::Truncated);
  EXPECT_EQ(s.offset, 354u);
  EXPECT_EQ(s.triangle, 5u);
  EXPECT_NE(s.message.find("12 triangles"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("684 bytes"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("354 bytes"), std::string::npos) << s.message;
}

TEST(ReadStlErrors, AbsurdCountIsTruncatedWithoutAllocating) {
  std::string b(1000, '\xff');
  Status s = readErr(b);
  EXPECT_EQ(s.code, Code::Truncated);
  EXPECT_NE(s.message.find("4294967295"), std::string::npos);
}

TEST(ReadStlErrors, CountBeyondMaxTrianglesIsTooLarge) {
  ReadOptions o;
  o.maxTriangles = 10;
  Status s = readErr(gen::binary(gen::cube()), o);
  EXPECT_EQ(s.code, Code::TooLarge);
  Status a = readErr(gen::ascii(gen::cube()), o);
  EXPECT_EQ(a.code, Code::TooLarge);
  EXPECT_EQ(a.triangle, 10u);
  EXPECT_GT(a.line, 0u);
}

TEST(ReadStlErrors, MaxBytes) {
  ReadOptions o;
  o.maxBytes = 100;
  Status s = readErr(gen::binary(gen::cube()), o);
  EXPECT_EQ(s.code, Code::TooLarge);
  EXPECT_EQ(s.offset, 100u);
}

TEST(ReadStlErrors, NonFiniteBinaryCoordinateNamesTheTriangle) {
  std::string b = gen::binary(gen::cube());
  float nan = std::nanf("");
  std::memcpy(&b[84 + 50 * 7 + 12 + 4], &nan, 4);
  Status s = readErr(b);
  EXPECT_EQ(s.code, Code::NonFinite);
  EXPECT_EQ(s.triangle, 7u);
  EXPECT_EQ(s.offset, 84u + 350u);
}

TEST(ReadStlErrors, AsciiInfAndHugeNumbersAreNonFinite) {
  for (const char* v : {"1e999 0 0", "inf 0 0", "nan 0 0", "-INFINITY 0 0"}) {
    std::string f = "solid x\n" + facet("0 0 0", "0 1 0", "1 1 1") + facet(v, "1 0 0", "0 1 0") + "endsolid\n";
    Status s = readErr(f);
    EXPECT_EQ(s.code, Code::NonFinite) << v;
    EXPECT_EQ(s.triangle, 1u) << v;
    EXPECT_EQ(s.line, 9u) << v;
  }
}

TEST(ReadStlErrors, EndInsideAFacetIsUnexpectedEnd) {
  std::string f = "solid x\n" + facet("0 0 0", "1 0 0", "0 1 0") + "facet normal 0 0 1\n outer loop\n vertex 1 2 3\n";
  Status s = readErr(f);
  EXPECT_EQ(s.code, Code::UnexpectedEnd);
  EXPECT_EQ(s.line, 11u);
  EXPECT_NE(s.message.find("line 9"), std::string::npos) << s.message;
}

TEST(ReadStlErrors, WrongVertexCountAndBadNumbersAreAsciiSyntax) {
  std::string four =
      "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nvertex 1 1 "
      "0\nendloop\nendfacet\nendsolid\n";
  Status s = readErr(four);
  EXPECT_EQ(s.code, Code::AsciiSyntax);
  EXPECT_EQ(s.line, 7u);
  std::string two =
      "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n";
  s = readErr(two);
  EXPECT_EQ(s.code, Code::AsciiSyntax);
  EXPECT_EQ(s.line, 6u);
  std::string bad =
      "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1,5 0 0\nvertex 0 1 "
      "0\nendloop\nendfacet\nendsolid\n";
  s = readErr(bad);
  EXPECT_EQ(s.code, Code::AsciiSyntax);
  EXPECT_EQ(s.line, 5u);
  EXPECT_NE(s.message.find("1,5"), std::string::npos);
  std::string extra =
      "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0 7\nvertex 1 0 0\nvertex 0 1 "
      "0\nendloop\nendfacet\nendsolid\n";
  EXPECT_EQ(readErr(extra).code, Code::AsciiSyntax);
}

TEST(ReadStlErrors, HugeNumberTokenIsCappedNotBuffered) {
  std::string f = "solid x\nfacet normal 0 0 1\nouter loop\nvertex " + std::string(1 << 20, '7') + " 0 0\n";
  Mesh m;
  Status s = gen::readChunked(f, 4096, m);
  EXPECT_EQ(s.code, Code::AsciiSyntax);
  EXPECT_EQ(s.line, 4u);
}

TEST(ReadStlWarnings, MissingEndsolidAndLongNames) {
  std::string f = "solid " + std::string(5000, 'n') + "\n" + facet("0 0 0", "1 0 0", "0 1 0");
  Mesh m;
  ASSERT_TRUE(gen::read(f, m).ok());
  ASSERT_EQ(m.warnings.size(), 2u);
  EXPECT_EQ(m.warnings[0].code, Code::NameTruncated);
  EXPECT_EQ(m.warnings[1].code, Code::MissingEndsolid);
  EXPECT_EQ(m.solids[0].name.size(), kMaxNameBytes);
  EXPECT_EQ(m.nTriangles(), 1u);
}

TEST(ReadStlWarnings, EmptySolidIsValid) {
  Mesh m;
  ASSERT_TRUE(gen::read("solid empty\nendsolid empty", m).ok());
  EXPECT_EQ(m.nTriangles(), 0u);
  EXPECT_EQ(m.solids.size(), 1u);
  EXPECT_TRUE(m.warnings.empty());
}

TEST(ReadStl, ReaderIsCleanAfterAnError) {
  Reader r;
  std::string bad = "solid x\nfacet oops\n";
  // feed() may only report the error once no reading of the bytes can succeed; finish() must.
  Status f = r.feed(reinterpret_cast<const uint8_t*>(bad.data()), bad.size());
  EXPECT_TRUE(f.ok() || f.code == Code::AsciiSyntax);
  Mesh m;
  EXPECT_EQ(r.finish(m).code, Code::AsciiSyntax);
  r.reset();
  std::string good = gen::binary(gen::cube());
  ASSERT_TRUE(r.feed(reinterpret_cast<const uint8_t*>(good.data()), good.size()).ok());
  ASSERT_TRUE(r.finish(m).ok());
  EXPECT_EQ(m.nTriangles(), 12u);
}

TEST(ReadStl, PeerChokersInTheReader) {
  // A count of 0 with a body: the body is trailing data (< 84 bytes) or a further part.
  std::string zero = gen::binary(gen::Soup{}, "zero") + std::string(50, '\1');
  Mesh m;
  ASSERT_TRUE(gen::read(zero, m).ok());
  EXPECT_EQ(m.nTriangles(), 0u);
  EXPECT_EQ(m.warnings[0].code, Code::TrailingBytes);
  // Under 84 bytes of binary-looking data.
  EXPECT_EQ(readErr(std::string(50, '\0')).code, Code::NotStl);
  // 'solid' header with binary content that is truncated: the size error wins.
  std::string solidBin = gen::binary(gen::cube(), "solid cad export");
  solidBin.resize(solidBin.size() - 10);
  EXPECT_EQ(readErr(solidBin).code, Code::Truncated);
}
