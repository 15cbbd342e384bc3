// Allocation failure: this test binary replaces malloc, calloc and realloc (glibc; not in
// sanitizer builds, whose allocator owns them) so that a chosen allocation fails. Every
// read and topology must then return out-of-memory (or succeed, when the failed
// allocation had a fallback) and never throw, abort or crash, and the next read must work.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "stl_gen.h"

extern "C" void* __libc_malloc(size_t);
extern "C" void* __libc_calloc(size_t, size_t);
extern "C" void* __libc_realloc(void*, size_t);
extern "C" void __libc_free(void*);

namespace {
bool armed = false;
long countdown = 0;             // while armed: the allocation that sees 1 fails
long seen = 0;                  // allocations while armed
size_t failAbove = ~size_t(0);  // while armed: every allocation larger than this fails

// The core probes a standard container's growth with malloc + free (detail::canAllocate)
// right before the container allocates the same size: a real allocator then hands back
// the block just freed. So an allocation that follows such a probe does not fail here; the
// failure moves on to the next one.
void* lastBlock = nullptr;
size_t lastSize = 0;
bool lastFreed = false;

size_t failedSize = 0;           // the size of the last allocation made to fail
bool failNow(size_t n) {
  if (!armed) return false;
  ++seen;
  bool afterProbe = lastFreed && n <= lastSize;
  lastFreed = false;
  if (n > failAbove) return (failedSize = n), true;
  if (countdown == 1 && afterProbe) return false;
  if (countdown > 0 && --countdown == 0) return (failedSize = n), true;
  return false;
}
void* track(void* p, size_t n) {
  if (armed) {
    lastBlock = p;
    lastSize = n;
  }
  return p;
}
// Counts the allocations from here on, and fails the k-th (k > 0) of them.
void arm(long k) {
  seen = 0;
  countdown = k;
  armed = true;
}
void disarm() {
  armed = false;
  countdown = 0;
}
// attempt(k) for k = 0, where nothing fails and the armed call's allocations are counted,
// then for every k up to that count, where allocation k fails; each under a trace naming
// `what` and k. attempt arms (arm(k)) and disarms around the call it sweeps. Returns the
// count.
template <class Attempt>
long sweepEach(const std::string& what, Attempt&& attempt) {
  long n = 0;
  for (long k = 0; k == 0 || k <= n; ++k) {
    SCOPED_TRACE(what + ", allocation " + std::to_string(k) + " of " + std::to_string(n));
    seen = 0;  // (an attempt that stops before it arms counts nothing)
    attempt(k);
    if (k == 0) n = seen;
  }
  return n;
}
}  // namespace

extern "C" void* malloc(size_t n) { return failNow(n) ? nullptr : track(__libc_malloc(n), n); }
extern "C" void* calloc(size_t a, size_t b) { return failNow(a * b) ? nullptr : track(__libc_calloc(a, b), a * b); }
extern "C" void* realloc(void* p, size_t n) { return failNow(n) ? nullptr : track(__libc_realloc(p, n), n); }
extern "C" void free(void* p) {
  if (armed && p && p == lastBlock) lastFreed = true;
  __libc_free(p);
}

using namespace stltopo;

namespace {

struct Outcome {
  Status read, topo;
  std::string json;
};

// One read + topology of `bytes`, with allocation `k` (1-based) failing when k > 0.
Outcome run(const std::string& bytes, const TopologyOptions& to, long k, size_t chunk = 0) {
  Outcome r;
  Mesh m;
  Topology t;
  arm(k);
  if (chunk == 0) {
    r.read = readStl(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), m);
  } else {
    Reader reader;
    for (size_t i = 0; i < bytes.size() && r.read.ok(); i += chunk)
      r.read = reader.feed(reinterpret_cast<const uint8_t*>(bytes.data()) + i, std::min(chunk, bytes.size() - i));
    if (r.read.ok()) r.read = reader.finish(m);
  }
  if (r.read.ok()) r.topo = buildTopology(m, t, to);
  disarm();
  if (r.read.ok() && r.topo.ok()) r.json = infoJson("f", m, &t);
  return r;
}

// Fails each allocation of the read + topology of `bytes` in turn. `fellBack`, when given,
// gets the size of each failed allocation that had a fallback (the run succeeded).
void sweep(const std::string& bytes, const TopologyOptions& to, size_t chunk = 0, std::vector<size_t>* fellBack = nullptr) {
  Outcome good = run(bytes, to, 0, chunk);
  ASSERT_TRUE(good.read.ok() && good.topo.ok()) << good.read.message << good.topo.message;
  const long n = seen;
  ASSERT_GT(n, 5);
  long failures = 0;
  for (long k = 1; k <= n; ++k) {
    SCOPED_TRACE("allocation " + std::to_string(k) + " of " + std::to_string(n));
    Outcome r = run(bytes, to, k, chunk);
    const Status& s = r.read.ok() ? r.topo : r.read;
    if (!s.ok()) {
      EXPECT_EQ(s.code, Code::OutOfMemory) << s.message;
      ++failures;
    } else {
      EXPECT_EQ(r.json, good.json);
      if (fellBack) fellBack->push_back(failedSize);
    }
    // The module keeps working: the next read is the good one.
    Outcome again = run(bytes, to, 0, chunk);
    EXPECT_EQ(again.json, good.json);
  }
  EXPECT_GT(failures, n / 2);  // most allocations have no fallback
}

gen::Soup cubesSharingAnEdge() {
  gen::Soup s = gen::cube();
  gen::append(s, gen::cube(1, 1, 0));
  gen::append(s, gen::cube(1, 0, 0));  // three cubes on one edge: non-manifold queues
  return s;
}

}  // namespace

TEST(AllocFail, BinaryReadAndTopology) {
  sweep(gen::binary(cubesSharingAnEdge(), "a header name longer than the short-string buffer"), {});
}

TEST(AllocFail, BinaryReadAndToleranceWeld) {
  TopologyOptions to;
  to.tolerance = 1e-3;
  sweep(gen::binary(cubesSharingAnEdge(), "tolerance"), to);
}

// The threaded topology's arrays of its own per part (the edge grouping's counts, 4 B a
// vertex, and the numbering's choices, 8 B a vertex, for each part after the first) fall back
// to fewer parts when one cannot be allocated: the same result on fewer threads. On 4 threads
// every one of those 4 + 3 allocations can fail and the topology still succeed, with the same
// report as always (sweep checks it).
TEST(AllocFail, ThreadedTopologyRunsInFewerPartsWhenAPartsArrayFails) {
  setParallelGrainForTesting(1);  // so that a small mesh splits
  const gen::Soup torus = gen::torus(12, 8, {3, 40});
  const size_t nv = 12 * 8;
  TopologyOptions four;
  four.threads = 4;
  std::vector<size_t> fellBack;
  sweep(gen::binary(torus, "a torus with two holes"), four, 0, &fellBack);
  setParallelGrainForTesting(0);
  EXPECT_EQ(std::count(fellBack.begin(), fellBack.end(), 4 * nv), 4);
  EXPECT_EQ(std::count(fellBack.begin(), fellBack.end(), 8 * nv), 3);
}

namespace {
template <class T>
std::vector<T> vec(const Array<T>& a) {
  return std::vector<T>(a.data(), a.data() + a.size());
}
// Every array of a topology but prev and face, and the counts (through the report).
void expectSameButPrevAndFace(const Mesh& m, const Topology& a, const Topology& b) {
  EXPECT_EQ(vec(a.next), vec(b.next));
  EXPECT_EQ(vec(a.vert), vec(b.vert));
  EXPECT_EQ(vec(a.pairKind), vec(b.pairKind));
  EXPECT_EQ(vec(a.triangleHalfedge), vec(b.triangleHalfedge));
  EXPECT_EQ(vec(a.vertexHalfedge), vec(b.vertexHalfedge));
  EXPECT_EQ(vec(a.loopHalfedge), vec(b.loopHalfedge));
  EXPECT_EQ(vec(a.loopOffsets), vec(b.loopOffsets));
  EXPECT_EQ(vec(a.loopHalfedges), vec(b.loopHalfedges));
  EXPECT_EQ(vec(a.vertexNonManifold), vec(b.vertexNonManifold));
  EXPECT_EQ(infoJson("f", m, &a), infoJson("f", m, &b));
}
}  // namespace

// TopologyOptions::prevAndFaceIfRoom: when the allocation of prev or of face fails, the
// topology goes on without both (the arrays of prevAndFace = false, the same report) instead
// of failing; every other failed allocation still gives out-of-memory, or the full result
// where it had a fallback. Without the option, the same failures are out-of-memory.
TEST(AllocFail, PrevAndFaceIfRoomGoesOnWithoutThem) {
  const std::string bytes = gen::binary(gen::torus(12, 8, {3, 40}), "a torus with two holes");
  Mesh m;
  ASSERT_TRUE(readStl(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), m).ok());
  Topology full, lean;
  TopologyOptions to, leanOptions;
  leanOptions.prevAndFace = false;
  ASSERT_TRUE(buildTopology(m, full, to).ok());
  ASSERT_TRUE(buildTopology(m, lean, leanOptions).ok());
  const uint32_t nh = full.nHalfedges();
  ASSERT_EQ(full.prev.size(), nh);
  ASSERT_TRUE(lean.prev.empty() && lean.face.empty());
  for (bool ifRoom : {true, false}) {
    to.prevAndFaceIfRoom = ifRoom;
    std::vector<size_t> wentOn;
    long failures = 0;
    sweepEach(ifRoom ? "if room" : "not if room", [&](long k) {
      Topology t;
      arm(k);
      Status s = buildTopology(m, t, to);
      disarm();
      if (!s.ok()) {
        EXPECT_EQ(s.code, Code::OutOfMemory) << s.message;
        ++failures;
        return;
      }
      if (t.prev.size() == nh) {
        EXPECT_EQ(vec(t.prev), vec(full.prev));
        EXPECT_EQ(vec(t.face), vec(full.face));
        expectSameButPrevAndFace(m, t, full);
      } else {
        EXPECT_TRUE(t.prev.empty() && t.face.empty()) << t.prev.size() << " " << t.face.size();
        expectSameButPrevAndFace(m, t, lean);
        wentOn.push_back(failedSize);
      }
    });
    if (ifRoom) {  // the failures of prev's and of face's allocation, and no other
      EXPECT_EQ(wentOn, std::vector<size_t>(2, sizeof(uint32_t) * nh));
    } else {
      EXPECT_TRUE(wentOn.empty());
    }
    EXPECT_GT(failures, 5);
  }
}

TEST(AllocFail, AsciiSolidsStreamed) {
  std::string two = gen::ascii(gen::cube(), "first solid with a long enough name") +
                    gen::ascii(gen::cube(2, 0, 0), "second solid with a long enough name");
  sweep(two, {}, 7);
}

TEST(AllocFail, ConcatenatedBinaryParts) {
  std::string parts;
  for (int i = 0; i < 6; ++i)
    parts += gen::binary(gen::cube(float(2 * i), 0, 0), "part number " + std::to_string(i) + " of many");
  sweep(parts, {});
}

TEST(AllocFail, LargeAllocationsFailAtEverySize) {
  // Every allocation above `limit` fails, for limits from 127 up (a status's message is a
  // short string): out-of-memory or success.
  std::string bytes = gen::binary(gen::torus(40, 30), "torus");
  TopologyOptions tol;
  tol.tolerance = 1e-4;
  for (const TopologyOptions& to : {TopologyOptions{}, tol}) {
    Outcome good = run(bytes, to, 0);
    ASSERT_TRUE(good.read.ok() && good.topo.ok());
    for (size_t limit = 127; limit < (size_t(1) << 22); limit = limit * 2 + 1) {
      SCOPED_TRACE("limit " + std::to_string(limit));
      failAbove = limit;
      Outcome r = run(bytes, to, 0);
      failAbove = ~size_t(0);
      const Status& s = r.read.ok() ? r.topo : r.read;
      if (!s.ok())
        EXPECT_EQ(s.code, Code::OutOfMemory) << s.message;
      else
        EXPECT_EQ(r.json, good.json);
      EXPECT_EQ(run(bytes, to, 0).json, good.json);
    }
  }
}

// ---------------------------------------------------------------------------
// Edits: each allocation of each kind of edit fails in turn. The edit then returns
// out-of-memory and changes nothing, or succeeds (the allocation had a fallback) with the
// same result as without the failure; the mesh stays consistent either way.

#include "edit_check.h"

namespace {

using Edit = std::function<Status(EditableMesh&)>;

void makeOpenTorus(EditableMesh& em) {
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(gen::torus(6, 5, {7})), m).ok());
  ASSERT_TRUE(em.init(m).ok());
  AttributeRules avg;
  avg.merge = avg.split = Rule::Average;
  ASSERT_TRUE(em.addAttribute("temp", Element::Vertex, ValueType::F64, 2, nullptr, avg).ok());
  ASSERT_TRUE(em.addAttribute("crease", Element::Edge, ValueType::U8, 1, nullptr, avg).ok());
}

void sweepEdit(const char* name, const Edit& edit) {
  SCOPED_TRACE(name);
  EditableMesh good;
  makeOpenTorus(good);
  arm(0);
  Status s = edit(good);
  disarm();
  ASSERT_TRUE(s.ok()) << s.message;
  const long n = seen;
  const std::string goodJson = good.infoJson("f");
  long failures = 0;
  for (long k = 1; k <= n; ++k) {
    SCOPED_TRACE("allocation " + std::to_string(k) + " of " + std::to_string(n));
    EditableMesh em;
    makeOpenTorus(em);
    editcheck::Snapshot before(em);
    arm(k);
    Status r = edit(em);
    disarm();
    if (!r.ok()) {
      EXPECT_EQ(r.code, Code::OutOfMemory) << r.message;
      EXPECT_TRUE(editcheck::Snapshot(em) == before) << "a failed edit changed the mesh";
      ++failures;
    } else {
      EXPECT_EQ(em.infoJson("f"), goodJson);
    }
    EXPECT_EQ(editcheck::differenceFromRebuild(em), "");
  }
  EXPECT_GT(n, 0);
}

}  // namespace

TEST(AllocFail, EditsFailCleanly) {
  sweepEdit("removeTriangle", [](EditableMesh& em) { return em.removeTriangle(5); });
  sweepEdit("addTriangle", [](EditableMesh& em) {
    uint32_t b = em.loops().loopHalfedge[0];
    return em.addTriangle(em.vert()[b], em.vert()[b ^ 1u], em.vert()[em.next()[b] ^ 1u]);
  });
  sweepEdit("addVertex", [](EditableMesh& em) { return em.addVertex(1, 2, 3); });
  sweepEdit("flipEdge", [](EditableMesh& em) { return em.flipEdge(em.triangleHalfedge()[20]); });
  sweepEdit("splitEdge", [](EditableMesh& em) { return em.splitEdge(em.triangleHalfedge()[20], 0.25); });
  uint32_t collapsible = kInvalid;  // the first triangle side from 30 on whose collapse is done
  for (uint32_t t = 30; t < 60 && collapsible == kInvalid; ++t) {
    EditableMesh trial;
    makeOpenTorus(trial);
    if (trial.collapseEdge(trial.triangleHalfedge()[t]).ok()) collapsible = t;
  }
  ASSERT_NE(collapsible, kInvalid);
  sweepEdit("collapseEdge", [&](EditableMesh& em) { return em.collapseEdge(em.triangleHalfedge()[collapsible]); });
  sweepEdit("reverseTriangle", [](EditableMesh& em) { return em.reverseTriangle(3); });
  sweepEdit("reverseTriangles", [](EditableMesh& em) {
    const uint32_t ids[] = {3, 4, 10};
    return em.reverseTriangles(ids, 3);
  });
  sweepEdit("reverseShell", [](EditableMesh& em) { return em.reverseShell(3); });
  sweepEdit("fillHole", [](EditableMesh& em) {
    Array<uint32_t> added;
    return em.fillHole(em.loops().loopHalfedge[0], FillMethod::Ear, &added);
  });
  sweepEdit("compact", [](EditableMesh& em) { return em.compact(); });
  sweepEdit("reserve", [](EditableMesh& em) { return em.reserve(100, 100); });
}

namespace {
// once(k, out) runs a call with allocation k failing (0: none) and gives its result in out.
// The good run (into `good`), then each of its allocations failing in turn: out of memory,
// or the good result; and after each, the good run again (nothing was left broken).
template <class Once>
void sweepResult(Once&& once, long atLeast, std::string& good) {
  Status first = once(0, good);
  ASSERT_TRUE(first.ok()) << first.message;
  const long n = seen;
  ASSERT_GE(n, atLeast);
  for (long k = 1; k <= n; ++k) {
    SCOPED_TRACE("allocation " + std::to_string(k) + " of " + std::to_string(n));
    std::string got;
    Status st = once(k, got);
    if (!st.ok())
      EXPECT_EQ(st.code, Code::OutOfMemory) << st.message;
    else
      EXPECT_EQ(got, good);
    std::string again;
    EXPECT_TRUE(once(0, again).ok());
    EXPECT_EQ(again, good);
  }
}
}  // namespace

// The shell report, the defect lists and extractShell: each allocation of the topology
// (with triangleShell) and of those fails in turn.
TEST(AllocFail, ShellsDefectsAndExtractShell) {
  gen::Soup s = cubesSharingAnEdge();
  gen::append(s, gen::cube(5, 0, 0));
  std::swap(s.f[40][1], s.f[40][2]);  // a flipped face in the fourth cube
  s.f.push_back({0, 0, 1});           // a degenerate triangle
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(s), m).ok());
  TopologyOptions to;
  to.triangleShell = true;
  to.prevAndFace = false;
  auto once = [&](long k, std::string& out) {
    Topology t;
    Array<Shell> shells;
    Defects d;
    Mesh part;
    arm(k);
    Status st = buildTopology(m, t, to);
    if (st.ok()) st = findShellsAndDefects(m, t, &shells, &d);
    if (st.ok()) st = extractShell(m, t, 1, part);
    disarm();
    out.clear();
    if (st.ok()) out = infoJson("f", m, &t, ReportExtras{&shells, &d, 1000}) + infoJson("part", part, nullptr);
    return st;
  };
  std::string good;
  sweepResult(once, 11, good);
}

namespace {
bool sameMesh(const Mesh& a, const Mesh& b) {
  return a.positions.size() == b.positions.size() && a.triangles.size() == b.triangles.size() &&
         std::equal(a.positions.begin(), a.positions.end(), b.positions.begin()) &&
         std::equal(a.triangles.begin(), a.triangles.end(), b.triangles.begin());
}

// The repair (issue 23): each allocation of planRepair, of an applyRepair that runs the
// steps itself (keepResult off), and of undoRepair fails in turn. A plan is then
// out-of-memory or the good plan; an apply is out-of-memory, with the editor valid and as the
// completed steps left it (undoing the log gives back the input), or the good result and
// log; an undo leaves a state the log still undoes.
void sweepRepair(const Mesh& m, RepairOptions o) {
  o.keepResult = false;
  Mesh input;
  {
    EditableMesh em;
    ASSERT_TRUE(em.init(m).ok());
    ASSERT_TRUE(em.toMesh(input).ok());
  }
  // The plan.
  RepairPlan plan;
  arm(0);
  ASSERT_TRUE(planRepair(m, o, plan).ok());
  disarm();
  const long nPlan = seen;
  const std::string goodPlan = repairPlanJson(plan);
  ASSERT_GT(nPlan, 20);
  for (long k = 1; k <= nPlan; ++k) {
    SCOPED_TRACE("plan allocation " + std::to_string(k) + " of " + std::to_string(nPlan));
    RepairPlan p;
    arm(k);
    Status st = planRepair(m, o, p);
    disarm();
    if (!st.ok())
      EXPECT_EQ(st.code, Code::OutOfMemory) << st.message;
    else
      EXPECT_EQ(repairPlanJson(p), goodPlan);
  }
  // The apply.
  Mesh goodMesh;
  std::string goodLog;
  {
    EditableMesh em;
    ASSERT_TRUE(em.init(m).ok());
    RepairLog log;
    arm(0);
    ASSERT_TRUE(applyRepair(em, plan, log).ok());
    disarm();
    ASSERT_TRUE(em.toMesh(goodMesh).ok());
    goodLog = repairLogJson(log);
  }
  const long nApply = seen;
  ASSERT_GT(nApply, 20);
  // The editor after an apply: valid, its mesh into `now`; and whether that is the good result.
  auto meshOf = [](EditableMesh& em, Mesh& now) {
    EXPECT_TRUE(em.validate().ok());
    EXPECT_TRUE(em.toMesh(now).ok());
  };
  auto expectGood = [&](const Mesh& now, const RepairLog& log) {
    EXPECT_TRUE(sameMesh(now, goodMesh));
    EXPECT_EQ(repairLogJson(log), goodLog);
  };
  // After a failed apply (`st`): the log undoes em back to the input.
  auto expectUndoneToInput = [&](EditableMesh& em, RepairLog& log, const Status& st) {
    const std::string logJson = repairLogJson(log);
    Status undone = undoRepair(em, log);
    ASSERT_TRUE(undone.ok()) << undone.message << "\n" << st.message << "\n" << logJson;
    Mesh back;
    ASSERT_TRUE(em.toMesh(back).ok());
    EXPECT_TRUE(sameMesh(back, input)) << st.message << "\n" << logJson;
  };
  long failures = 0;
  for (long k = 1; k <= nApply; ++k) {
    SCOPED_TRACE("apply allocation " + std::to_string(k) + " of " + std::to_string(nApply));
    EditableMesh em;
    ASSERT_TRUE(em.init(m).ok());
    RepairLog log;
    arm(k);
    Status st = applyRepair(em, plan, log);
    disarm();
    Mesh now;
    meshOf(em, now);
    if (st.ok()) {
      expectGood(now, log);
      continue;
    }
    ++failures;
    EXPECT_EQ(st.code, Code::OutOfMemory) << st.message;
    expectUndoneToInput(em, log, st);
  }
  EXPECT_GT(failures, nApply / 2);
  // From the Mesh, applyRepair(mesh, plan, em, log): it builds the editor of the mesh and
  // runs the steps (the plan kept no result). On failure em is empty with no step logged
  // (nothing was built), or the editor as the completed steps left it.
  const long nCli = sweepEach("apply from the Mesh", [&](long k) {
    EditableMesh em;
    RepairLog log;
    arm(k);
    Status st = applyRepair(m, plan, em, log);
    disarm();
    Mesh now;
    meshOf(em, now);
    if (st.ok()) {
      expectGood(now, log);
      return;
    }
    EXPECT_EQ(st.code, Code::OutOfMemory) << st.message;
    if (log.steps.empty() && em.nTriangles() == 0) return;
    expectUndoneToInput(em, log, st);
  });
  EXPECT_GT(nCli, 20);
  // Taking the plan's result (keepResult on): a failed apply leaves the editor as it was.
  RepairOptions keep = o;
  keep.keepResult = true;
  const long nTake = sweepEach("apply taking the result", [&](long k) {
    RepairPlan kept;
    ASSERT_TRUE(planRepair(m, keep, kept).ok());
    EditableMesh em;
    ASSERT_TRUE(em.init(m).ok());
    RepairLog log;
    arm(k);
    Status st = applyRepair(em, kept, log);
    disarm();
    Mesh now;
    meshOf(em, now);
    if (st.ok()) {
      expectGood(now, log);
    } else {
      EXPECT_EQ(st.code, Code::OutOfMemory) << st.message;
      EXPECT_TRUE(sameMesh(now, input));
      EXPECT_FALSE(kept.resultTaken());
    }
  });
  EXPECT_GT(nTake, 0);
  // The CLI's way into a Mesh, applyRepair(mesh, plan, out, log), with the plan's result
  // and without: `out` changes only on success.
  for (const bool withResult : {true, false}) {
    const std::string what =
        std::string("apply into a Mesh ") + (withResult ? "taking the result" : "running the steps");
    const long nOut = sweepEach(what, [&](long k) {
      RepairPlan p;
      ASSERT_TRUE(planRepair(m, withResult ? keep : o, p).ok());
      Mesh out;
      RepairLog log;
      arm(k);
      Status st = applyRepair(m, p, out, log);
      disarm();
      if (st.ok()) {
        expectGood(out, log);
      } else {
        EXPECT_EQ(st.code, Code::OutOfMemory) << st.message;
        EXPECT_EQ(out.nTriangles(), 0u);
        EXPECT_EQ(out.nVertices(), 0u);
        EXPECT_FALSE(p.resultTaken());
      }
    });
    // (Taking a result that is a Mesh already allocates nothing.)
    if (!withResult) EXPECT_GT(nOut, 20);
  }
  // Undo.
  const long nUndo = sweepEach("undo", [&](long k) {
    EditableMesh em;
    ASSERT_TRUE(em.init(m).ok());
    RepairLog log;
    ASSERT_TRUE(applyRepair(em, plan, log).ok());
    arm(k);
    Status st = undoRepair(em, log);
    disarm();
    if (k == 0) {
      ASSERT_TRUE(st.ok());
    } else if (!st.ok()) {
      EXPECT_EQ(st.code, Code::OutOfMemory) << st.message;
    }
    EXPECT_TRUE(em.validate().ok());
    ASSERT_TRUE(undoRepair(em, log).ok());
    Mesh back;
    ASSERT_TRUE(em.toMesh(back).ok());
    EXPECT_TRUE(sameMesh(back, input));
  });
  ASSERT_GT(nUndo, 5);
}

const RepairOptions& allSteps() {
  static const RepairOptions o = [] {
    RepairOptions r;
    r.steps = (1u << kRepairStepCount) - 1;
    r.stitchTolerance = 0.01;
    r.fillRefine = r.fillFair = true;
    r.minShellTriangles = 20;
    return r;
  }();
  return o;
}
}  // namespace

// A torus with two holes, three flipped triangles and a duplicate. The default steps:
// duplicates, orient (not the last step: the runner keeps its edits unbuilt for fill-holes)
// and fill-holes do items, so failures land in each of them and between them. Then every
// step, fill-holes refining and fairing.
TEST(AllocFail, RepairFailsCleanly) {
  gen::Soup s = gen::torus(12, 8, {13, 60});
  for (size_t k : {7u, 40u, 101u}) std::swap(s.f[k][1], s.f[k][2]);
  s.f.push_back(s.f[50]);
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(s), m).ok());
  {
    SCOPED_TRACE("default steps");
    RepairPlan p;
    ASSERT_TRUE(planRepair(m, RepairOptions{}, p).ok());
    for (const RepairStepPlan& sp : p.steps)
      if (sp.kind == RepairStepKind::Duplicates || sp.kind == RepairStepKind::Orient ||
          sp.kind == RepairStepKind::FillHoles)
        ASSERT_GT(sp.nDone(), 0u) << repairStepName(sp.kind);
    sweepRepair(m, RepairOptions{});
  }
  {
    SCOPED_TRACE("every step");
    sweepRepair(m, allSteps());
  }
  // split-nonmanifold with items: two cubes sharing a vertex, and three sharing an edge.
  gen::Soup pinch = gen::cube();
  gen::append(pinch, gen::cube(1, 1, 1));
  for (const gen::Soup* soup : {static_cast<const gen::Soup*>(&pinch), static_cast<const gen::Soup*>(nullptr)}) {
    SCOPED_TRACE(soup ? "two cubes sharing a vertex" : "three cubes sharing an edge");
    Mesh c;
    ASSERT_TRUE(gen::read(gen::binary(soup ? *soup : cubesSharingAnEdge()), c).ok());
    RepairPlan p;
    ASSERT_TRUE(planRepair(c, allSteps(), p).ok());
    bool split = false;
    for (const RepairStepPlan& sp : p.steps) split |= sp.kind == RepairStepKind::SplitNonManifold && sp.nDone() > 0;
    ASSERT_TRUE(split);
    sweepRepair(c, allSteps());
  }
}

// admesh's own damaged files (tests/judge/admesh), every step: stitch (block exact),
// small shells (block remove-unconnected), zero-area needles and caps with small shells
// (conveyor remove-unconnected), a hole filled, refined and faired (block fill-holes).
TEST(AllocFail, RepairFailsCleanlyOnAdmeshFiles) {
  const std::string root = std::string(STLTOPO_FIXTURES) + "/../judge/admesh/";
  for (const char* f : {"block/exact-bad.stl", "block/remove-unconnected-bad.stl", "block/fill-holes-bad.stl",
                        "conveyor/remove-unconnected-bad.stl"}) {
    SCOPED_TRACE(f);
    Mesh m;
    ASSERT_TRUE(gen::read(gen::readFile(root + f), m).ok());
    sweepRepair(m, allSteps());
  }
}

// The intersection pass (analyzeGeometry, with the shell list and nesting): each allocation
// fails in turn. Out of memory, or the report of the good run. A torus with holes, flipped
// triangles and a duplicate (patches that certify and patches that do not: a failed edge
// table there once left the next certificate writing through an empty array), and the same
// beside two crossing cubes (pairs, nesting).
TEST(AllocFail, IntersectionPassFailsCleanly) {
  gen::Soup s = gen::torus(12, 8, {13, 60});
  for (size_t k : {7u, 40u, 101u}) std::swap(s.f[k][1], s.f[k][2]);
  s.f.push_back(s.f[50]);
  gen::Soup crossing = s;
  gen::append(crossing, gen::cube(10, 0, 0, 2));
  gen::append(crossing, gen::cube(11, 1, 1, 2));
  for (const gen::Soup* soup : {&s, &crossing}) {
    SCOPED_TRACE(soup == &s ? "torus" : "torus and crossing cubes");
    Mesh m;
    ASSERT_TRUE(gen::read(gen::binary(*soup), m).ok());
    TopologyOptions to;
    to.triangleShell = true;
    auto once = [&](long k, std::string& out) {
      Topology t;
      GeometryReport g;
      arm(k);
      Status st = buildTopology(m, t, to);
      if (st.ok()) st = analyzeGeometry(m, t, g, IntersectionOptions{});
      disarm();
      out.clear();
      if (st.ok()) {
        ReportExtras e;
        e.shells = &g.shells;
        e.checks = &g.checks;
        e.intersections = &g.intersections;
        e.nesting = &g.nesting;
        e.solid = g.solid;
        out = infoJson("f", m, &t, e);
      }
      return st;
    };
    std::string good;
    sweepResult(once, 20, good);
    EXPECT_EQ(good.find("\"selfIntersections\":0,") == std::string::npos, soup == &crossing) << good;
  }
}

// meshFromIndexed (both welds, with solids and colours) and writeStl
// (binary with colours, and ASCII with the solids' names): each allocation fails in turn.
// Out of memory, or the good result.
TEST(AllocFail, IndexedAndWriteFailCleanly) {
  gen::Soup s = gen::torus(8, 6, {5});
  std::vector<float> positions;
  for (const auto& v : s.v) positions.insert(positions.end(), {v[0], v[1], v[2]});
  positions.insert(positions.end(), positions.begin(), positions.begin() + 6);  // repeated positions
  std::vector<uint32_t> triangles;
  for (const auto& f : s.f) triangles.insert(triangles.end(), {f[0], f[1], f[2]});
  const uint32_t nt = uint32_t(s.f.size());
  std::vector<uint8_t> colors(3 * size_t(nt), 200), valid(nt, 1);
  Solid parts[2];
  parts[0].name = std::string(40, 'a');  // longer than a short string's buffer
  parts[0].firstTriangle = 0;
  parts[0].triangleCount = nt / 2;
  parts[1].name = "second part";
  parts[1].firstTriangle = nt / 2;
  parts[1].triangleCount = nt - nt / 2;
  IndexedMesh in;
  in.positions = positions.data();
  in.positionsLength = positions.size();
  in.triangles = triangles.data();
  in.trianglesLength = triangles.size();
  in.colors = colors.data();
  in.colorValid = valid.data();
  in.solids = parts;
  in.nSolids = 2;
  for (Weld weld : {Weld::Exact, Weld::None}) {
    SCOPED_TRACE(weld == Weld::Exact ? "exact weld" : "no weld");
    IndexedOptions io;
    io.weld = weld;
    auto once = [&](long k, std::string& out) {
      Mesh m;
      Array<uint32_t> map;
      arm(k);
      Status st = meshFromIndexed(in, m, &map, io);
      disarm();
      out.clear();
      if (st.ok()) out = infoJson("f", m, nullptr) + std::to_string(map.size());
      return st;
    };
    std::string good;
    sweepResult(once, 4, good);
  }
  Mesh m;
  ASSERT_TRUE(meshFromIndexed(in, m).ok());
  for (bool ascii : {false, true}) {
    SCOPED_TRACE(ascii ? "ascii" : "binary");
    WriteOptions wo;
    wo.format = ascii ? Format::Ascii : Format::Binary;
    auto once = [&](long k, std::string& out) {
      out.clear();
      arm(k);
      Status st = writeStl(
          m,
          [](void* user, const uint8_t* data, size_t size) {
            const bool was = armed;  // the test's own buffer is not the writer's
            armed = false;
            static_cast<std::string*>(user)->append(reinterpret_cast<const char*>(data), size);
            armed = was;
            return true;
          },
          &out, wo);
      disarm();
      return st;
    };
    std::string good;
    sweepResult(once, 1, good);  // the writer's chunk buffer at least
    EXPECT_GT(good.size(), 84u);
  }
}
