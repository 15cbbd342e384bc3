// Bad input: every file in tests/fixtures/regress (fuzzer finds and hand-made
// reproducers) and every input that other STL readers choked on must read or fail
// cleanly, the same way for every chunking, and a successful read must give a topology
// that validate() accepts.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include <sys/wait.h>
#include <unistd.h>

#include "stl_gen.h"

using namespace stltopo;
namespace fs = std::filesystem;

namespace {

const char* kRegressDir = STLTOPO_FIXTURES "/regress";

bool isError(Code c) { return c >= Code::Empty && c <= Code::Invalid; }
bool isWarning(Code c) { return c >= Code::TrailingBytes && c <= Code::NameTruncated; }

std::string describe(const Status& s) {
  return std::string(codeName(s.code)) + " [" + s.message + "] offset " + std::to_string(s.offset) + " line " +
         std::to_string(s.line) + " triangle " + std::to_string(s.triangle);
}

void expectSameStatus(const Status& a, const Status& b, const std::string& what) {
  EXPECT_EQ(a.code, b.code) << what << ": " << describe(a) << " vs " << describe(b);
  EXPECT_EQ(a.message, b.message) << what;
  EXPECT_EQ(a.offset, b.offset) << what;
  EXPECT_EQ(a.line, b.line) << what;
  EXPECT_EQ(a.triangle, b.triangle) << what;
}

using gen::sameArray;

void expectSameMesh(const Mesh& a, const Mesh& b, const std::string& what) {
  EXPECT_EQ(a.format, b.format) << what;
  EXPECT_TRUE(sameArray(a.positions, b.positions)) << what;
  EXPECT_TRUE(sameArray(a.triangles, b.triangles)) << what;
  EXPECT_TRUE(sameArray(a.attributes, b.attributes)) << what;
  EXPECT_TRUE(sameArray(a.colors, b.colors)) << what;
  ASSERT_EQ(a.solids.size(), b.solids.size()) << what;
  for (size_t i = 0; i < a.solids.size(); ++i) {
    EXPECT_EQ(a.solids[i].name, b.solids[i].name) << what;
    EXPECT_EQ(a.solids[i].triangleCount, b.solids[i].triangleCount) << what;
  }
  ASSERT_EQ(a.warnings.size(), b.warnings.size()) << what;
  for (size_t i = 0; i < a.warnings.size(); ++i) expectSameStatus(a.warnings[i], b.warnings[i], what + " warning");
  EXPECT_EQ(infoJson("f", a, nullptr), infoJson("f", b, nullptr)) << what;
}

// The whole contract for one input: a clean error or a valid mesh + topology, identical
// for every chunking. Returns the whole-buffer status (mesh in `out`).
Status checkInput(const std::string& bytes, const std::string& what, Mesh& out) {
  Status s = gen::read(bytes, out);
  if (!s.ok()) {
    EXPECT_TRUE(isError(s.code)) << what << ": " << describe(s);
    EXPECT_EQ(s.message.rfind(std::string(codeName(s.code)) + ": ", 0), 0u) << what << ": " << s.message;
    EXPECT_GT(s.message.size(), std::strlen(codeName(s.code)) + 2) << what;
    std::string j = errorJson("f", s);
    EXPECT_NE(j.find(std::string("\"code\":\"") + codeName(s.code) + "\""), std::string::npos) << j;
  } else {
    for (const Status& w : out.warnings) EXPECT_TRUE(isWarning(w.code)) << what << ": " << describe(w);
    for (double tol : {0.0, 1e-6, 0.5, 1e30, 1e-300, std::numeric_limits<double>::infinity()}) {
      TopologyOptions to;
      to.tolerance = tol;
      Topology t;
      Status ts = buildTopology(out, t, to);
      EXPECT_TRUE(ts.ok()) << what << " tolerance " << tol << ": " << ts.message;
      if (!ts.ok()) continue;
      Status v = validate(out, t);
      EXPECT_TRUE(v.ok()) << what << " tolerance " << tol << ": " << v.message;
      std::string j = infoJson("f", out, &t);
      EXPECT_TRUE(!j.empty() && j.front() == '{' && j.back() == '}') << what;
    }
  }
  for (size_t chunk : {1, 2, 7, 50, 83, 84, 4095, 4096, 4097}) {
    if (chunk > bytes.size() + 1) break;
    Mesh m;
    Status c = gen::readChunked(bytes, chunk, m);
    std::string w = what + " in chunks of " + std::to_string(chunk);
    expectSameStatus(s, c, w);
    if (s.ok() && c.ok()) expectSameMesh(out, m, w);
  }
  return s;
}

Status checkInput(const std::string& bytes, const std::string& what) {
  Mesh m;
  return checkInput(bytes, what, m);
}

std::string binaryWithCount(const gen::Soup& s, uint32_t count, const std::string& header = "regress") {
  std::string b = gen::binary(s, header);
  std::memcpy(&b[80], &count, 4);
  return b;
}

std::string facet(const std::string& a, const std::string& b, const std::string& c) {
  return "facet normal 0 0 1\n outer loop\n  vertex " + a + "\n  vertex " + b + "\n  vertex " + c +
         "\n endloop\nendfacet\n";
}

// Runs the CLI on `bytes` (written to a temporary file); returns the exit status and
// the first line of --json output.
int runCli(const std::string& bytes, std::string& json) {
  std::string path = (fs::temp_directory_path() / ("stltopo-regress-" + std::to_string(::getpid()) + ".stl")).string();
  {
    std::ofstream f(path, std::ios::binary);
    f.write(bytes.data(), std::streamsize(bytes.size()));
  }
  std::string cmd = std::string("'") + STLTOPO_CLI + "' info --json '" + path + "'";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return -1;
  json.clear();
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) json += buf;
  int rc = ::pclose(p);
  std::remove(path.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

TEST(Regress, EveryRegressionFileReadsOrFailsCleanly) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(kRegressDir))
    if (e.is_regular_file() && e.path().extension() != ".md") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty()) << kRegressDir;
  for (const fs::path& p : files) {
    SCOPED_TRACE(p.filename().string());
    checkInput(gen::readFile(p.string()), p.filename().string());
  }
}

// The inputs that crashed or misled other readers (admesh, three.js, numpy-stl, ...).
TEST(Regress, PeerChokersThroughTheCli) {
#if defined(__EMSCRIPTEN__)
  GTEST_SKIP() << "spawns the native CLI";
#endif
  const gen::Soup cube = gen::cube();
  const std::string good = gen::binary(cube);
  float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::string binNan = good, binInf = good, binNegInf = good;
  std::memcpy(&binNan[84 + 50 * 3 + 12], &nan, 4);
  std::memcpy(&binInf[84 + 50 * 11 + 44], &inf, 4);
  float ninf = -inf;
  std::memcpy(&binNegInf[84 + 12 + 4], &ninf, 4);
  std::string nanNormal = good;  // a NaN stored normal is not an error: normals are ignored
  std::memcpy(&nanNormal[84], &nan, 4);
  std::string solidTruncated = gen::binary(cube, "solid cad export");
  solidTruncated.resize(solidTruncated.size() - 10);
  const std::string asciiOne = "solid x\n" + facet("0 0 0", "1 0 0", "0 1 0");

  struct Case {
    const char* name;
    std::string bytes;
    Code code;     // expected whole-buffer code
    Code warning;  // expected first warning on success (Code::Ok: none)
  };
  const Case cases[] = {
      {"empty file", "", Code::Empty, Code::Ok},
      {"one byte", "s", Code::NotStl, Code::Ok},
      {"83 zero bytes", std::string(83, '\0'), Code::NotStl, Code::Ok},
      {"under 84 bytes of text", "hello world, this is not an STL file", Code::NotStl, Code::Ok},
      {"84-byte header, count 0", binaryWithCount({}, 0), Code::Ok, Code::Ok},
      {"84-byte header, count 1", binaryWithCount({}, 1), Code::Truncated, Code::Ok},
      {"count larger than the file", binaryWithCount(cube, 13), Code::Truncated, Code::Ok},
      {"count 2^32-1", binaryWithCount(cube, 0xFFFFFFFFu), Code::Truncated, Code::Ok},
      {"count at maxTriangles", binaryWithCount(cube, 1u << 28), Code::Truncated, Code::Ok},
      {"count 0 with a 50-byte body", binaryWithCount({}, 0) + good.substr(84, 50), Code::Ok, Code::TrailingBytes},
      {"count 0 with a whole body", binaryWithCount(cube, 0), Code::Truncated, Code::Ok},
      {"count smaller than the body", binaryWithCount(cube, 11), Code::Ok, Code::TrailingBytes},
      {"binary NaN vertex", binNan, Code::NonFinite, Code::Ok},
      {"binary +Inf vertex", binInf, Code::NonFinite, Code::Ok},
      {"binary -Inf vertex", binNegInf, Code::NonFinite, Code::Ok},
      {"binary NaN normal", nanNormal, Code::Ok, Code::Ok},
      {"ASCII nan", "solid x\n" + facet("nan 0 0", "1 0 0", "0 1 0") + "endsolid\n", Code::NonFinite, Code::Ok},
      {"ASCII inf", "solid x\n" + facet("0 inf 0", "1 0 0", "0 1 0") + "endsolid\n", Code::NonFinite, Code::Ok},
      {"ASCII 1e999", "solid x\n" + facet("1e999 0 0", "1 0 0", "0 1 0") + "endsolid\n", Code::NonFinite, Code::Ok},
      {"ASCII -1e999", "solid x\n" + facet("0 0 -1e999", "1 0 0", "0 1 0") + "endsolid\n", Code::NonFinite, Code::Ok},
      {"ASCII 1e999 normal",
       "solid x\nfacet normal 1e999 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 "
       "0\nendloop\nendfacet\nendsolid\n",
       Code::Ok, Code::Ok},
      {"ASCII 1e-999 underflows to 0", "solid x\n" + facet("1e-999 0 0", "1 0 0", "0 1 0") + "endsolid\n", Code::Ok,
       Code::Ok},
      {"solid header, binary content", gen::binary(cube, "solid cad export"), Code::Ok, Code::Ok},
      {"solid header, binary content, truncated", solidTruncated, Code::Truncated, Code::Ok},
      {"solid header, binary content, trailing", gen::binary(cube, "solid cad export") + "\n\n", Code::Ok,
       Code::TrailingBytes},
      {"ASCII without endsolid", asciiOne, Code::Ok, Code::MissingEndsolid},
      {"ASCII without endsolid or newline", asciiOne.substr(0, asciiOne.size() - 1), Code::Ok, Code::MissingEndsolid},
      {"ASCII 'solid' only", "solid", Code::Ok, Code::MissingEndsolid},
      {"ASCII ends inside a facet", asciiOne.substr(0, asciiOne.find("endloop")), Code::UnexpectedEnd, Code::Ok},
      {"0xFF x 1", std::string(1, '\xff'), Code::NotStl, Code::Ok},
      {"0xFF x 83", std::string(83, '\xff'), Code::NotStl, Code::Ok},
      {"0xFF x 84", std::string(84, '\xff'), Code::Truncated, Code::Ok},
      {"0xFF x 1000", std::string(1000, '\xff'), Code::Truncated, Code::Ok},
      {"0x00 x 84", std::string(84, '\0'), Code::Ok, Code::Ok},
      {"0x00 x 1000", std::string(1000, '\0'), Code::Ok, Code::TrailingBytes},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Mesh m;
    Status s = checkInput(c.bytes, c.name, m);
    EXPECT_EQ(s.code, c.code) << c.name << ": " << describe(s);
    if (s.ok()) {
      Code first = m.warnings.empty() ? Code::Ok : m.warnings[0].code;
      EXPECT_EQ(first, c.warning) << c.name << ": " << (m.warnings.empty() ? "no warning" : describe(m.warnings[0]));
    }
    // The CLI neither crashes nor hangs: exit 0 or 1 and one JSON line with the same code.
    std::string json;
    int rc = runCli(c.bytes, json);
    EXPECT_EQ(rc, s.ok() ? 0 : 1) << c.name << ": " << json;
    if (!s.ok())
      EXPECT_NE(json.find(std::string("\"code\":\"") + codeName(s.code) + "\""), std::string::npos) << json;
    else
      EXPECT_EQ(json.find("\"error\""), std::string::npos) << json;
  }
}

TEST(Regress, NonFiniteLocations) {
  std::string b = gen::binary(gen::cube());
  float inf = std::numeric_limits<float>::infinity();
  std::memcpy(&b[84 + 50 * 4 + 36 + 8], &inf, 4);  // triangle 4, corner 2, z
  Status s = checkInput(b, "binary inf");
  EXPECT_EQ(s.code, Code::NonFinite);
  EXPECT_EQ(s.triangle, 4u);
  EXPECT_EQ(s.offset, 84u + 200u);
  EXPECT_EQ(s.line, 0u);
  std::string a = "solid x\n" + facet("0 0 0", "1 0 0", "0 1 1e999") + "endsolid\n";
  s = checkInput(a, "ascii 1e999");
  EXPECT_EQ(s.code, Code::NonFinite);
  EXPECT_EQ(s.triangle, 0u);
  EXPECT_EQ(s.line, 2u);
  EXPECT_EQ(s.offset, 8u);
}

// A 100 MB line of digits (fed as 1 MiB chunks of the same buffer) is refused without
// buffering it; so is a 100 MB 'solid' name glued to the keyword, which is cut.
TEST(Regress, HugeTokensAreCappedWhileStreaming) {
  const size_t kChunk = 1 << 20, kChunks = 100;
  std::string digits(kChunk, '7');
  {
    Reader r;
    std::string head = "solid x\nfacet normal 0 0 1\nouter loop\nvertex ";
    ASSERT_TRUE(r.feed(reinterpret_cast<const uint8_t*>(head.data()), head.size()).ok());
    Status s;
    for (size_t i = 0; i < kChunks && s.ok(); ++i) s = r.feed(reinterpret_cast<const uint8_t*>(digits.data()), kChunk);
    Mesh m;
    if (s.ok()) s = r.finish(m);
    EXPECT_EQ(s.code, Code::AsciiSyntax) << s.message;
    EXPECT_EQ(s.line, 4u);
    EXPECT_EQ(s.offset, head.size() - 0u);
  }
  {
    Reader r;
    std::string head = "solid";
    std::string names(kChunk, 'n');
    ASSERT_TRUE(r.feed(reinterpret_cast<const uint8_t*>(head.data()), head.size()).ok());
    for (size_t i = 0; i < kChunks; ++i)
      ASSERT_TRUE(r.feed(reinterpret_cast<const uint8_t*>(names.data()), kChunk).ok());
    std::string tail = " more\n" + facet("0 0 0", "1 0 0", "0 1 0") + "endsolid\n";
    ASSERT_TRUE(r.feed(reinterpret_cast<const uint8_t*>(tail.data()), tail.size()).ok());
    Mesh m;
    Status s = r.finish(m);
    ASSERT_TRUE(s.ok()) << s.message;
    ASSERT_EQ(m.solids.size(), 1u);
    EXPECT_EQ(m.solids[0].name, std::string(kMaxNameBytes, 'n'));
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_EQ(m.warnings[0].code, Code::NameTruncated);
    EXPECT_EQ(m.nTriangles(), 1u);
  }
}

// Numbers and names just around the caps read the same whole and in every chunking.
TEST(Regress, TokensAroundTheCaps) {
  for (size_t len : {kMaxNumberChars - 1, kMaxNumberChars, kMaxNumberChars + 1, kMaxNumberChars + 6}) {
    std::string num = std::string(len - 1, '0') + "1";
    std::string f = "solid x\n" + facet(num + " 0 0", "1 0 0", "0 1 0") + "endsolid\n";
    Status s = checkInput(f, "number of " + std::to_string(len) + " chars");
    EXPECT_EQ(s.ok(), len <= kMaxNumberChars) << len << ": " << s.message;
  }
  for (size_t len : {kMaxNameBytes - 1, kMaxNameBytes, kMaxNameBytes + 1, kMaxNameBytes + 5, kMaxNameBytes + 6}) {
    for (const char* sep : {"", " "}) {
      std::string f =
          std::string("solid") + sep + std::string(len, 'a') + " b\n" + facet("0 0 0", "1 0 0", "0 1 0") + "endsolid\n";
      Mesh m;
      Status s = checkInput(f, "name of " + std::to_string(len) + " bytes, sep '" + sep + "'", m);
      ASSERT_TRUE(s.ok()) << s.message;
      EXPECT_LE(m.solids[0].name.size(), kMaxNameBytes);
    }
  }
}

// A tolerance far below the coordinate spacing (here 1e-30 on coordinates near 100) must
// not pile every vertex into one clamped grid cell: that made the weld quadratic (11 s for
// 90k vertices). Every vertex stays its own representative, as with the exact weld.
TEST(Regress, TinyToleranceStaysLinear) {
  gen::Soup s;
  const int n = 300;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) s.v.push_back({1 + 0.37f * float(i), 1 + 0.37f * float(j), 1.5f});
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      uint32_t a = uint32_t(i * n + j), b = a + uint32_t(n), c = b + 1, d = a + 1;
      s.f.push_back({a, b, c});
      s.f.push_back({a, c, d});
    }
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(s), m).ok());
  for (double tol : {1e-30, 1e-300, std::numeric_limits<double>::denorm_min()}) {
    auto t0 = std::chrono::steady_clock::now();
    TopologyOptions to;
    to.tolerance = tol;
    Topology t;
    ASSERT_TRUE(buildTopology(m, t, to).ok());
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(secs, 10.0) << tol;  // about 0.05 s (0.5 s under ASan); quadratic was 30+ s
    EXPECT_TRUE(validate(m, t).ok());
    for (uint32_t v = 0; v < m.nVertices(); ++v) ASSERT_EQ(t.vertexWeld[v], v) << tol;
    EXPECT_EQ(t.nHoles, 1u);
  }
}

// validate() is for topologies that may be broken: it must report, never read out of
// bounds, whatever value sits in any of the arrays.
TEST(Regress, ValidateSurvivesCorruptedTopologies) {
  gen::Soup s = gen::torus(4, 3, {2, 5});
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(s), m).ok());
  Topology good;
  ASSERT_TRUE(buildTopology(m, good).ok());
  ASSERT_TRUE(validate(m, good).ok());
  const uint32_t values[] = {0, 1, 2, 5, 100, 0x7fffffffu, kInvalid - 1, kInvalid};
  auto copy = [](const Topology& t) {
    Topology c;
    auto dup = [](auto& dst, const auto& src) {
      ASSERT_TRUE(dst.resize(src.size()));
      for (size_t i = 0; i < src.size(); ++i) dst[i] = src[i];
    };
    c.nTriangles = t.nTriangles;
    c.nVertices = t.nVertices;
    dup(c.next, t.next);
    dup(c.prev, t.prev);
    dup(c.vert, t.vert);
    dup(c.face, t.face);
    dup(c.pairKind, t.pairKind);
    dup(c.triangleHalfedge, t.triangleHalfedge);
    dup(c.vertexHalfedge, t.vertexHalfedge);
    dup(c.vertexWeld, t.vertexWeld);
    dup(c.loopHalfedge, t.loopHalfedge);
    dup(c.loopOffsets, t.loopOffsets);
    dup(c.loopHalfedges, t.loopHalfedges);
    dup(c.loopIsSeam, t.loopIsSeam);
    dup(c.loopPerimeter, t.loopPerimeter);
    dup(c.triangleDegenerate, t.triangleDegenerate);
    dup(c.vertexNonManifold, t.vertexNonManifold);
    c.nEdges = t.nEdges;
    c.nBoundaryEdges = t.nBoundaryEdges;
    c.nNonManifoldEdges = t.nNonManifoldEdges;
    c.nInconsistentEdges = t.nInconsistentEdges;
    c.nNonManifoldVertices = t.nNonManifoldVertices;
    c.nDegenerate = t.nDegenerate;
    c.nShells = t.nShells;
    c.nUsedVertices = t.nUsedVertices;
    c.nHoles = t.nHoles;
    c.nSeams = t.nSeams;
    return c;
  };
  using Field = Array<uint32_t> Topology::*;
  const Field fields[] = {&Topology::next,
                          &Topology::prev,
                          &Topology::vert,
                          &Topology::face,
                          &Topology::triangleHalfedge,
                          &Topology::vertexHalfedge,
                          &Topology::vertexWeld,
                          &Topology::loopHalfedge,
                          &Topology::loopOffsets,
                          &Topology::loopHalfedges};
  int checked = 0;
  for (Field f : fields) {
    size_t n = (good.*f).size();
    for (size_t i = 0; i < n; i += std::max<size_t>(1, n / 7)) {
      for (uint32_t v : values) {
        Topology t = copy(good);
        if ((t.*f)[i] == v) continue;
        (t.*f)[i] = v;
        Status st = validate(m, t);  // must not crash (ASan/UBSan in the sanitizer build)
        if (!st.ok()) {
          EXPECT_EQ(st.code, Code::Invalid);
          EXPECT_FALSE(st.message.empty());
        }
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100);
}
