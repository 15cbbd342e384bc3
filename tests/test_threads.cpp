// Threads give the output of one thread (issue 24): every array, count, status and report
// of every fixture, fuzz seed and generated mesh, read, built and checked with 1, 2, 3 and
// 8 threads, compared byte for byte. setParallelGrainForTesting(1) makes every threaded
// stage split even the smallest input, and the tests check that the splits happened.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "stl_gen.h"
#include "stltopo/stltopo.h"

#ifndef STLTOPO_FIXTURES
#error "STLTOPO_FIXTURES must name the tests/fixtures directory"
#endif

namespace {

// The bytes of everything a configuration produces, for byte comparison.
struct Dump {
  std::string out;
  template <class T>
  void arr(const char* name, const stltopo::Array<T>& a) {
    out += name;
    out += '=';
    out += std::to_string(a.size());
    out += ':';
    if (a.size()) out.append(reinterpret_cast<const char*>(a.data()), a.size() * sizeof(T));
    out += '\n';
  }
  template <class T>
  void val(const char* name, const T& v) {
    out += name;
    out += '=';
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
    out += '\n';
  }
  void status(const char* name, const stltopo::Status& s) {
    out += name;
    out += '=';
    out += stltopo::codeName(s.code);
    out += ' ' + s.message + ' ' + std::to_string(s.offset) + ' ' + std::to_string(s.line) + ' ' +
           std::to_string(s.triangle) + ' ' + std::to_string(s.element) + '\n';
  }
};

void dumpTopology(Dump& d, const stltopo::Topology& t) {
  d.arr("next", t.next);
  d.arr("prev", t.prev);
  d.arr("vert", t.vert);
  d.arr("face", t.face);
  d.arr("pairKind", t.pairKind);
  d.arr("triangleHalfedge", t.triangleHalfedge);
  d.arr("vertexHalfedge", t.vertexHalfedge);
  d.arr("vertexWeld", t.vertexWeld);
  d.arr("loopHalfedge", t.loopHalfedge);
  d.arr("loopOffsets", t.loopOffsets);
  d.arr("loopHalfedges", t.loopHalfedges);
  d.arr("loopIsSeam", t.loopIsSeam);
  d.arr("loopPerimeter", t.loopPerimeter);
  d.arr("triangleDegenerate", t.triangleDegenerate);
  d.arr("vertexNonManifold", t.vertexNonManifold);
  d.arr("triangleShell", t.triangleShell);
  uint32_t counts[] = {t.nTriangles,
                       t.nVertices,
                       t.nEdges,
                       t.nBoundaryEdges,
                       t.nNonManifoldEdges,
                       t.nInconsistentEdges,
                       t.nNonManifoldVertices,
                       t.nDegenerate,
                       t.nShells,
                       t.nUsedVertices,
                       t.nHoles,
                       t.nSeams,
                       t.nWeldedVertices};
  d.val("counts", counts);
  d.val("tolerance", t.tolerance);
}

// Reads `bytes` (whole, or fed in `chunk`-byte pieces) with `threads` threads and builds
// every topology, the checks, the intersections and the reports from it.
std::string run(const std::string& bytes, unsigned threads, size_t chunk, bool everything) {
  Dump d;
  stltopo::ReadOptions ro;
  ro.threads = threads;
  ro.keepNormals = true;
  stltopo::Mesh m;
  stltopo::Status s = chunk ? gen::readChunked(bytes, chunk, m, ro) : gen::read(bytes, m, ro);
  d.status("read", s);
  if (!s.ok()) return d.out;
  d.arr("positions", m.positions);
  d.arr("triangles", m.triangles);
  d.arr("attributes", m.attributes);
  d.arr("normals", m.normals);
  d.arr("colors", m.colors);
  d.arr("colorValid", m.colorValid);
  d.val("format", m.format);
  d.val("colorConvention", m.colorConvention);
  d.val("normalMismatches", m.normalMismatches);
  d.val("area", m.area);
  d.val("volume", m.volume);
  d.val("bboxMin", m.bboxMin);
  d.val("bboxMax", m.bboxMax);
  for (const stltopo::Solid& so : m.solids)
    d.out += so.name + ' ' + std::to_string(so.firstTriangle) + ' ' + std::to_string(so.triangleCount) + '\n';
  for (const stltopo::Status& w : m.warnings) d.status("warning", w);
  if (!everything) return d.out;
  for (int mode = 0; mode < 3; ++mode) {
    stltopo::TopologyOptions to;
    to.threads = threads;
    to.triangleShell = true;
    to.prevAndFace = mode != 1;
    to.tolerance = mode == 2 ? 1e-3 : 0;
    stltopo::Topology t;
    s = stltopo::buildTopology(m, t, to);
    d.status("topology", s);
    if (!s.ok()) continue;
    dumpTopology(d, t);
    d.out += stltopo::infoJson("f", m, &t) + '\n';
    if (mode != 0) continue;  // the geometry and the extras once, on the exact weld
    stltopo::IntersectionOptions io;
    io.threads = threads;
    io.maxPairs = 1000;
    stltopo::GeometryReport geo;
    s = stltopo::analyzeGeometry(m, t, geo, io);
    d.status("geometry", s);
    if (s.ok()) {
      d.arr("zeroArea", geo.checks.zeroArea);
      d.arr("duplicateOffsets", geo.checks.duplicateOffsets);
      d.arr("duplicateTriangles", geo.checks.duplicateTriangles);
      d.arr("duplicateOrientation", geo.checks.duplicateOrientation);
      d.arr("pairs", geo.intersections.pairs);
      d.arr("kinds", geo.intersections.kinds);
      d.arr("points", geo.intersections.points);
      d.arr("triangleIntersects", geo.intersections.triangleIntersects);
      uint64_t ic[] = {geo.intersections.nCrossing, geo.intersections.nTouching, geo.intersections.nCoplanar,
                       geo.intersections.nIntersectingTriangles, geo.intersections.complete};
      d.val("intersectionCounts", ic);
      stltopo::Defects defects;
      s = stltopo::findShellsAndDefects(m, t, nullptr, &defects);
      d.status("defects", s);
      stltopo::ReportExtras extras;
      extras.shells = &geo.shells;
      extras.defects = s.ok() ? &defects : nullptr;
      extras.checks = &geo.checks;
      extras.intersections = &geo.intersections;
      extras.nesting = &geo.nesting;
      extras.solid = geo.solid;
      d.out += stltopo::infoJson("f", m, &t, extras) + '\n';
    }
  }
  d.out += stltopo::infoJson("f", m, nullptr) + '\n';
  return d.out;
}

// Every input in one configuration against one thread, whole and streamed.
void expectSameForAllThreads(const std::string& name, const std::string& bytes) {
  const bool small = bytes.size() < (size_t(1) << 20);
  const std::string one = run(bytes, 1, 0, true);
  for (unsigned threads : {2u, 3u, 8u})
    EXPECT_TRUE(run(bytes, threads, 0, true) == one) << name << ": " << threads << " threads differ from one";
  // Streamed in pieces: records straddle the pieces, and the batches start anywhere.
  for (size_t chunk : {size_t(173), size_t(4096)}) {
    if (!small && chunk < 4096) continue;
    EXPECT_TRUE(run(bytes, 3, chunk, false) == run(bytes, 1, chunk, false)) << name << ": " << chunk << "-byte pieces";
  }
}

std::vector<std::string> filesUnder(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec))
    if (it->is_regular_file()) out.push_back(it->path().string());
  std::sort(out.begin(), out.end());
  return out;
}

// Sets the test grain for one test and restores the default afterwards.
struct SmallGrain {
  explicit SmallGrain(size_t g) { stltopo::setParallelGrainForTesting(g); }
  ~SmallGrain() { stltopo::setParallelGrainForTesting(0); }
};

#if defined(STLTOPO_WASM_TESTS)
constexpr bool kThreaded = false;  // the wasm build has no threads: every count is one thread
#else
constexpr bool kThreaded = true;
#endif

TEST(Threads, FixturesAreTheSameForEveryThreadCount) {
  SmallGrain grain(1);
  const uint64_t splits = stltopo::parallelSplitsForTesting();
  size_t n = 0;
  for (const std::string& path : gen::fixtureFiles(gen::kWithoutLarge)) {
    expectSameForAllThreads(path, gen::readFile(path));
    ++n;
  }
  EXPECT_GT(n, 50u);
  if (kThreaded) EXPECT_GT(stltopo::parallelSplitsForTesting(), splits + 100) << "the threaded paths did not run";
}

// The loops that wasm runs in chunks (detail::forChunks) give the whole loop's result: every
// fixture and a shuffled torus with holes, with chunks of 1, 7 and 64 items against none.
TEST(Threads, ChunkedLoopsGiveTheWholeLoopsResult) {
  struct Chunk {
    explicit Chunk(size_t n) { stltopo::setChunkItemsForTesting(n); }
    ~Chunk() { stltopo::setChunkItemsForTesting(0); }
  };
  std::vector<std::pair<std::string, std::string>> inputs;
  for (const std::string& path : gen::fixtureFiles(gen::kWithoutLarge)) inputs.emplace_back(path, gen::readFile(path));
  gen::Soup t = gen::torus(60, 40, {7, 500, 501, 2000});
  std::mt19937 rng(11);
  std::shuffle(t.f.begin(), t.f.end(), rng);
  inputs.emplace_back("shuffled torus", gen::binary(t));
  size_t n = 0;
  for (const auto& [name, bytes] : inputs) {
    const std::string whole = run(bytes, 1, 0, true);
    for (size_t c : {size_t(1), size_t(7), size_t(64)}) {
      Chunk chunk(c);
      EXPECT_TRUE(run(bytes, 1, 0, true) == whole) << name << ": chunks of " << c;
    }
    ++n;
  }
  EXPECT_GT(n, 50u);
}

TEST(Threads, FuzzSeedsAreTheSameForEveryThreadCount) {
  SmallGrain grain(1);
  size_t n = 0;
  for (const std::string& path : filesUnder(gen::fixturePath("../fuzz/seeds"))) {
    expectSameForAllThreads(path, gen::readFile(path));
    ++n;
  }
  EXPECT_GT(n, 20u);
}

// The read splits a binary part only from 2 x 65536 records (its default grain): below that,
// the threads' private weld arrays cost more fresh memory than the second thread saves
// (bench/PROFILE.md, *Stop 49*). A smaller file reads as one thread does, with no split.
TEST(Threads, TheReadSplitsOnlyPartsOfAtLeast131072Records) {
  const std::string below = gen::binary(gen::torus(256, 255));  // 130,560 triangles
  const std::string at = gen::binary(gen::torus(256, 256));     // 131,072
  stltopo::ReadOptions ro;
  ro.threads = 2;
  stltopo::Mesh m;
  uint64_t splits = stltopo::parallelSplitsForTesting();
  ASSERT_TRUE(gen::read(below, m, ro).ok());
  ASSERT_EQ(m.nTriangles(), 130560u);
  EXPECT_EQ(stltopo::parallelSplitsForTesting(), splits) << "a part below 131,072 records was read on threads";
  splits = stltopo::parallelSplitsForTesting();
  ASSERT_TRUE(gen::read(at, m, ro).ok());
  ASSERT_EQ(m.nTriangles(), 131072u);
  if (kThreaded) EXPECT_GT(stltopo::parallelSplitsForTesting(), splits) << "a part of 131,072 records was read on one thread";
  // In 1 MiB chunks, as the npm package feeds it: the part's count decides, not the chunk's.
  splits = stltopo::parallelSplitsForTesting();
  ASSERT_TRUE(gen::readChunked(at, size_t(1) << 20, m, ro).ok());
  if (kThreaded) EXPECT_GT(stltopo::parallelSplitsForTesting(), splits) << "read in chunks";
}

// Generated meshes at the stages' own grain (no test grain) and at grain 1: grid order and
// shuffled, with holes, -0 and +0, several binary parts, a non-finite coordinate late in the
// file (the threaded read must give the one-thread error), and a truncated file.
TEST(Threads, GeneratedMeshesAreTheSameForEveryThreadCount) {
  gen::Soup t = gen::torus(120, 90, {7, 500, 501, 3000});
  std::string grid = gen::binary(t);
  gen::Soup sh = t;
  std::mt19937 rng(5);
  std::shuffle(sh.f.begin(), sh.f.end(), rng);
  for (size_t i = 0; i < sh.f.size(); i += 3) std::rotate(sh.f[i].begin(), sh.f[i].begin() + 1, sh.f[i].end());
  std::string shuffled = gen::binary(sh);
  gen::Soup zeros = gen::cube();
  for (auto& v : zeros.v)
    for (float& x : v)
      if (x == 0) x = -0.0f;
  gen::Soup both = gen::cube();
  gen::append(both, zeros);
  gen::append(both, t);
  std::string signedZeros = gen::binary(both);
  std::string parts = grid + gen::binary(sh, "COLOR=\x10\x20\x30\xff second part") + grid;
  // 151,200 triangles in one solid: past twice the binary parser's default grain (65,536 records
  // a part), so that grain 0 splits too (the other cases are smaller); read only, on 1 and 2
  // threads, at grain 0 (the whole pipeline on it is slow under the sanitizers).
  gen::Soup seven = t;
  for (int k = 1; k < 7; ++k) gen::append(seven, k % 2 ? sh : t);
  const std::string large = gen::binary(seven);  // one solid
  std::string nonFinite = shuffled;
  {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(&nonFinite[84 + 50 * 15000 + 12 + 12 + 4], &nan, 4);  // triangle 15000, corner 1, y
  }
  std::string truncated = shuffled.substr(0, shuffled.size() - 75);
  std::string withWords = grid;
  for (size_t r = 0; r < 2000; ++r) withWords[84 + 50 * r * 7 + 49] = char(0x80 | (r & 0x7f));
  const std::pair<const char*, const std::string*> cases[] = {{"grid", &grid},
                                                              {"shuffled", &shuffled},
                                                              {"signed zeros", &signedZeros},
                                                              {"parts", &parts},
                                                              {"non-finite", &nonFinite},
                                                              {"truncated", &truncated},
                                                              {"viscam words", &withWords}};
  for (size_t g : {size_t(0), size_t(1), size_t(64)}) {
    SmallGrain grain(g);
    const uint64_t splits = stltopo::parallelSplitsForTesting();
    for (const auto& [name, bytes] : cases)
      expectSameForAllThreads(std::string(name) + " grain " + std::to_string(g), *bytes);
    if (g == 0) EXPECT_TRUE(run(large, 2, 0, false) == run(large, 1, 0, false)) << "seven tori, 2 threads";
    if (kThreaded) EXPECT_GT(stltopo::parallelSplitsForTesting(), splits) << "grain " << g;
  }
  // The non-finite case is an error, and the same one.
  stltopo::Mesh m;
  stltopo::ReadOptions ro;
  ro.threads = 3;
  stltopo::Status s = gen::read(nonFinite, m, ro);
  EXPECT_EQ(s.code, stltopo::Code::NonFinite);
  EXPECT_EQ(s.triangle, 15000u);
}

// The threaded read welds its first batch by ranges, then by pieces where a batch's corners
// repeat its own vertices (grid order) and by lookups in the mesh's table where they do not
// (random order): src/mesh_builder_threads.cpp, addBatchParallel. Each way gives one thread's mesh,
// here also with a table that grows during a batch (a soup whose vertices are few times
// shared, past the table's reservation) and a non-finite coordinate in a batch of lookups.
TEST(Threads, TheReadWeldsGridOrderByPiecesAndRandomOrderByLookups) {
  if (!kThreaded) GTEST_SKIP() << "no threads in this build";
  const gen::Soup t = gen::torus(120, 90, {7, 500});
  const std::string grid = gen::binary(t);
  gen::Soup sh = t;
  std::mt19937 rng(11);
  std::shuffle(sh.f.begin(), sh.f.end(), rng);
  const std::string shuffled = gen::binary(sh);
  gen::Soup soup;  // 20,000 triangles on 40,000 random points, some of them -0 and +0
  std::uniform_real_distribution<float> coord(-100.0f, 100.0f);
  for (int i = 0; i < 40000; ++i) soup.v.push_back({coord(rng), coord(rng), i % 97 == 0 ? -0.0f : coord(rng)});
  for (int i = 0; i < 40000; i += 97) soup.v[size_t(i) + 1][2] = 0.0f;
  std::uniform_int_distribution<uint32_t> point(0, 39999);
  for (int i = 0; i < 20000; ++i) soup.f.push_back({point(rng), point(rng), point(rng)});
  const std::string random = gen::binary(soup);
  std::string nonFinite = shuffled;
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(&nonFinite[84 + 50 * 9000 + 12 + 24 + 8], &inf, 4);  // triangle 9000, corner 2, z
  auto ways = [] {
    return std::vector<uint64_t>{stltopo::threadedReadBatchesForTesting(0), stltopo::threadedReadBatchesForTesting(1),
                                 stltopo::threadedReadBatchesForTesting(2)};
  };
  SmallGrain grain(64);  // batches of 512 records, then of 4,096
  struct Case {
    const char* name;
    const std::string* bytes;
    unsigned way;  // the way of the batches after the first
  };
  for (const Case& c : {Case{"grid", &grid, 1}, Case{"shuffled", &shuffled, 2}, Case{"random soup", &random, 2},
                        Case{"non-finite", &nonFinite, 2}}) {
    const std::string one = run(*c.bytes, 1, 0, false);
    const std::vector<uint64_t> before = ways();
    EXPECT_TRUE(run(*c.bytes, 2, 0, false) == one) << c.name << ": 2 threads differ from one";
    const std::vector<uint64_t> after = ways();
    EXPECT_EQ(after[0], before[0] + 1) << c.name << ": its first batch by ranges";
    EXPECT_GT(after[c.way], before[c.way]) << c.name << ": the way of the batches after the first";
    EXPECT_EQ(after[3 - c.way], before[3 - c.way]) << c.name << ": the other way";
    EXPECT_TRUE(run(*c.bytes, 3, 4096, false) == run(*c.bytes, 1, 4096, false)) << c.name << ": in 4096-byte pieces";
  }
  stltopo::Mesh m;
  stltopo::ReadOptions ro;
  ro.threads = 2;
  const stltopo::Status s = gen::read(nonFinite, m, ro);
  EXPECT_EQ(s.code, stltopo::Code::NonFinite);
  EXPECT_EQ(s.triangle, 9000u);
  ASSERT_TRUE(gen::read(random, m, ro).ok());
  EXPECT_GT(m.nVertices(), 20000u / 2 + 16) << "the weld table did not have to grow";
}

// A soup whose rest welds (gen::soupThenWelded): on 2 threads its weld table is sized for the
// soup in a batch welded by lookups (Builder::growTable from addBatchLookups), and the arrays
// are still those of one thread.
TEST(Threads, ASoupThatWeldsLaterIsTheSameForEveryThreadCount) {
  if (!kThreaded) GTEST_SKIP() << "no threads in this build";
  const std::string bytes = gen::binary(gen::soupThenWelded());
  SmallGrain grain(64);  // batches of 512 records, then of 4,096
  const std::string one = run(bytes, 1, 0, false);
  const uint64_t lookups = stltopo::threadedReadBatchesForTesting(2);
  EXPECT_TRUE(run(bytes, 2, 0, false) == one) << "2 threads differ from one";
  EXPECT_GT(stltopo::threadedReadBatchesForTesting(2), lookups) << "no batch welded by lookups";
  EXPECT_TRUE(run(bytes, 3, 4096, false) == one) << "3 threads in 4096-byte pieces differ";
  stltopo::Mesh m;
  stltopo::ReadOptions ro;
  ro.threads = 2;
  ASSERT_TRUE(gen::read(bytes, m, ro).ok());
  // The table grew (10,517 vertices) in the second batch (records 512 to 4,607), by lookups,
  // and was sized for 3 vertices a triangle to the end (see ReadStl.ASoupThatWelds...).
  EXPECT_GE(m.positions.capacity(), 3u * 63002u);
}

// The plan, the change log and the result of a repair with every step, on `threads`.
std::string repairWith(const std::string& bytes, unsigned threads) {
  stltopo::Mesh mesh;
  stltopo::ReadOptions ro;
  ro.threads = threads;
  Dump d;
  stltopo::Status s = gen::read(bytes, mesh, ro);
  d.status("read", s);
  if (!s.ok()) return d.out;
  stltopo::RepairOptions o;
  o.steps = 0;
  for (const char* name : {"duplicates", "zero-area", "stitch", "orient", "split-nonmanifold", "fill-holes", "small-shells"}) {
    stltopo::RepairStepKind k;
    if (stltopo::repairStepFromName(name, k)) o.steps |= stltopo::repairStepBit(k);
  }
  o.stitchTolerance = 1e-3;
  o.maxPairs = 20000;
  o.threads = threads;
  stltopo::RepairPlan plan;
  s = stltopo::planRepair(mesh, o, plan);
  d.status("plan", s);
  if (!s.ok()) return d.out;
  d.out += stltopo::repairPlanJson(plan) + '\n';
  stltopo::EditableMesh em;
  stltopo::TopologyOptions to;
  to.threads = threads;
  stltopo::RepairLog log;
  s = em.init(mesh, to);
  if (s.ok()) s = stltopo::applyRepair(em, plan, log);
  d.status("apply", s);
  d.out += stltopo::repairLogJson(log) + '\n';
  stltopo::Mesh result;
  s = em.toMesh(result, nullptr, nullptr);
  d.status("result", s);
  d.arr("positions", result.positions);
  d.arr("triangles", result.triangles);
  return d.out;
}

// RepairOptions::threads: the same plan, log and result for every count, with the stages
// split down to single items. (Not in the wasm suite: there every count is one thread.)
TEST(Threads, RepairIsTheSameForEveryThreadCount) {
  if (!kThreaded) GTEST_SKIP() << "no threads in this build";
  SmallGrain grain(1);
  const uint64_t splits = stltopo::parallelSplitsForTesting();
  size_t n = 0;
  for (const std::string& path : gen::fixtureFiles()) {
    const std::string bytes = gen::readFile(path);
    if (bytes.size() > (size_t(1) << 20)) continue;  // the time of the suite (and of the sanitizer run)
    const std::string one = repairWith(bytes, 1);
    if (one.compare(0, 8, "read=ok ") == 0)
      EXPECT_NE(one.find("\"steps\""), std::string::npos) << path << "\n" << one.substr(0, 300);
    EXPECT_TRUE(repairWith(bytes, 3) == one) << path << ": 3 threads differ from one";
    ++n;
  }
  EXPECT_GT(n, 50u);
  if (kThreaded) EXPECT_GT(stltopo::parallelSplitsForTesting(), splits + 100) << "the threaded paths did not run";
}

#if defined(STLTOPO_CLI) && !defined(STLTOPO_WASM_TESTS)  // the CLI runs as a subprocess: not in wasm
// The CLI's stdout and exit status for `args` (file names quoted by the caller).
std::string cli(const std::string& args) {
  std::string cmd = std::string("'") + STLTOPO_CLI + "' " + args + " 2>&1; echo \"exit $?\"";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return "popen failed";
  std::string out;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  ::pclose(p);
  return out;
}

// The whole CLI, all fixtures in one call per flag set: --threads 1 against 2, 3 and 8 with
// the stages split down to single items.
TEST(Threads, CliPrintsTheSameBytesForEveryThreadCount) {
  std::string files;
  for (const std::string& path : gen::fixtureFiles(gen::kWithoutLarge)) files += " '" + path + "'";
  for (const char* flags :
       {"info --json --shells --defects --intersections --max-pairs 1000", "info --tolerance 0.001"}) {
    const std::string one = cli(std::string(flags) + " --threads 1" + files);
    EXPECT_NE(one.find("triangles"), std::string::npos);
    for (const char* threads : {"2", "3", "8"})
      EXPECT_TRUE(cli(std::string(flags) + " --test-parallel-grain 1 --threads " + threads + files) == one)
          << flags << " --threads " << threads;
  }
  // 0: the machine's cores (the default is 1).
  EXPECT_EQ(cli("info --json --threads 0" + files), cli("info --json" + files));
  EXPECT_NE(cli("info --threads -1 x.stl").find("bad --threads '-1'"), std::string::npos);
  EXPECT_NE(cli("info --threads 1025 x.stl").find("bad --threads '1025'"), std::string::npos);
  EXPECT_NE(cli("repair --threads x a.stl b.stl").find("bad --threads 'x'"), std::string::npos);
}

// `repair --threads N`: the same plan, log and file for every count.
TEST(Threads, CliRepairIsTheSameForEveryThreadCount) {
  const std::string dir = ::testing::TempDir();
  size_t n = 0;
  for (const std::string& path : gen::fixtureFiles()) {
    if (std::filesystem::file_size(path) > (size_t(1) << 20) || n++ % 4) continue;  // a quarter: the suite's time
    std::string outs[2];
    std::string files[2];
    for (int i = 0; i < 2; ++i) {
      files[i] = dir + "/threads-repair-" + std::to_string(i) + ".stl";
      std::filesystem::remove(files[i]);
      outs[i] = cli("repair --test-parallel-grain 1 --threads " + std::string(i ? "3" : "1") + " --stitch-tolerance 0.001 '" +
                    path + "' '" + files[i] + "'");
      const size_t at = outs[i].find(files[i]);
      if (at != std::string::npos) outs[i].replace(at, files[i].size(), "OUT");
    }
    EXPECT_EQ(outs[0], outs[1]) << path;
    EXPECT_EQ(gen::readFile(files[0]), gen::readFile(files[1])) << path;
  }
}
#endif

}  // namespace

// The threaded intersection pass against one thread where its limits decide: a soup with
// many intersecting pairs cut at maxPairs below, at and above their number, a stack of
// parallel slanted triangles whose boxes all overlap (the work limit stops it, no pair is
// found), and a caller that cancels. Truncated lists must be the serial join's.
TEST(Threads, IntersectionLimitsAreTheSameForEveryThreadCount) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> coord(0, 40);
  gen::Soup soup;
  for (int t = 0; t < 600; ++t) {
    for (int c = 0; c < 3; ++c)
      soup.v.push_back({float(coord(rng)), float(coord(rng)), float(coord(rng))});
    const uint32_t b = uint32_t(soup.v.size()) - 3;
    soup.f.push_back({b, b + 1, b + 2});
  }
  gen::Soup stack;
  for (int t = 0; t < 1500; ++t) {
    const float z = 0.001f * float(t);
    stack.v.push_back({0, 0, z});
    stack.v.push_back({10, 0, z + 5});
    stack.v.push_back({0, 10, z});
    const uint32_t b = uint32_t(stack.v.size()) - 3;
    stack.f.push_back({b, b + 1, b + 2});
  }
  struct Result {
    stltopo::Status status;
    stltopo::Intersections found;
  };
  auto pass = [](const stltopo::Mesh& m, const stltopo::Topology& t, unsigned threads, uint64_t maxPairs,
                 bool cancel) {
    stltopo::TriangleChecks checks;
    Result r;
    r.status = stltopo::checkTriangles(m, &t, checks, 1);
    stltopo::IntersectionOptions io;
    io.threads = threads;
    io.maxPairs = maxPairs;
    if (cancel) io.progress = [](void*, double) { return false; };
    if (r.status.ok()) r.status = stltopo::findIntersections(m, t, checks, r.found, io);
    return r;
  };
  auto same = [](const Result& a, const Result& b) {
    return a.status.code == b.status.code && gen::sameArray(a.found.pairs, b.found.pairs) &&
           gen::sameArray(a.found.kinds, b.found.kinds) && gen::sameArray(a.found.points, b.found.points) &&
           gen::sameArray(a.found.triangleIntersects, b.found.triangleIntersects) &&
           a.found.complete == b.found.complete && a.found.nCrossing == b.found.nCrossing &&
           a.found.nTouching == b.found.nTouching && a.found.nCoplanar == b.found.nCoplanar;
  };
  for (size_t g : {size_t(1), size_t(0)}) {
    SmallGrain grain(g);
    for (const gen::Soup* s : {&soup, &stack}) {
      stltopo::Mesh m;
      ASSERT_TRUE(gen::read(gen::binary(*s), m).ok());
      stltopo::Topology t;
      ASSERT_TRUE(stltopo::buildTopology(m, t).ok());
      const Result all = pass(m, t, 1, 1u << 30, false);
      ASSERT_TRUE(all.status.ok());
      const uint64_t p = all.found.nPairs();
      if (s == &soup) {
        EXPECT_GT(p, 1000u);
        EXPECT_TRUE(all.found.complete);
      } else {
        EXPECT_EQ(p, 0u);
      }
      // ~0: the work limit (8 * maxPairs + ...) saturates instead of wrapping.
      for (uint64_t maxPairs : {uint64_t(1), p / 3 + 1, p - 1, p, p + 1, uint64_t(1) << 30, ~uint64_t(0)}) {
        if (maxPairs == 0) continue;
        const Result one = pass(m, t, 1, maxPairs, false);
        // The serial limits: cut at maxPairs pairs; the stack's work limit (8 + 64 * 1500 tests
        // of ~10^6 overlapping boxes) stops it with none found.
        if (s == &soup) EXPECT_EQ(one.found.complete, maxPairs > p) << maxPairs;
        if (s == &stack) EXPECT_EQ(one.found.complete, maxPairs > (uint64_t(1) << 20)) << maxPairs;
        for (unsigned threads : {2u, 3u, 8u})
          EXPECT_TRUE(same(pass(m, t, threads, maxPairs, false), one))
              << (s == &soup ? "soup" : "stack") << " maxPairs " << maxPairs << ", " << threads << " threads, grain "
              << g;
      }
      const Result cancelled = pass(m, t, 3, 1u << 30, true);
      EXPECT_EQ(cancelled.status.code, stltopo::Code::Aborted);
    }
  }
}
