// Fuzz target: repair plans with random options on random input. Input: [base][base
// parameters][damage bytes][option bytes].
//   base % 4 == 0: a torus grid, [n][m][hole mask] (3..10 x 3..10 quads, up to 8 quads left out)
//   base % 4 == 1: two cubes sharing a side (non-manifold edges)
//   base % 4 == 2: two cubes touching at a corner (a non-manifold vertex)
//   base % 4 == 3: [length lo][length hi][STL bytes] read with readStl (a read error ends the input)
// Then up to 16 damage bytes (flip, remove, duplicate a triangle, move a vertex a little)
// and the options (steps, stitch tolerance, hole limits, fill refine/fair, walls, small
// shells, intersections, keepResult). Checks: planning changes nothing; apply's result equals
// the plan's prediction; when apply took the plan's own result, running the steps gives the
// same log and mesh; applying into a Mesh (the CLI's way) gives the same mesh and log; the
// result passes validate(); undo, step by step, gives back the input's arrays exactly.

#include "../stl_gen.h"
#include "fuzz_common.h"

using namespace stltopo;

namespace {
struct Bytes {
  const uint8_t* p;
  size_t n;
  uint32_t byte() {
    if (n == 0) return 0;
    --n;
    return *p++;
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in{data, size};
  const uint32_t base = in.byte();
  gen::Soup soup;
  Mesh m;
  switch (base % 4) {
    case 0: {
      int n = 3 + int(in.byte() % 8), k = 3 + int(in.byte() % 8);
      uint32_t mask = in.byte();
      std::vector<int> skip;
      for (int i = 0; i < 8; ++i)
        if (mask & (1u << i)) skip.push_back((i * 7) % (n * k));
      soup = gen::torus(n, k, skip);
      break;
    }
    case 1:
    case 2:
      soup = gen::cube();
      gen::append(soup, base % 4 == 1 ? gen::cube(1, 0, 0) : gen::cube(1, 1, 1));
      break;
    default: {
      size_t len = in.byte();
      len |= size_t(in.byte()) << 8;
      len = std::min(len, in.n);
      Status s = readStl(in.p, len, m);
      in.p += len;
      in.n -= len;
      if (!s.ok() || m.nTriangles() > 4000) return 0;
      break;
    }
  }
  if (base % 4 != 3) {
    // Damage: up to 16 (kind, triangle) pairs.
    const uint32_t nd = in.byte() % 17;
    for (uint32_t i = 0; i < nd && !soup.f.empty(); ++i) {
      uint32_t kind = in.byte(), t = in.byte() % uint32_t(soup.f.size());
      switch (kind % 4) {
        case 0: std::swap(soup.f[t][1], soup.f[t][2]); break;
        case 1: soup.f.erase(soup.f.begin() + t); break;
        case 2: soup.f.push_back(soup.f[t]); break;
        default: soup.v[soup.f[t][0]][kind % 3] += float(int(kind) - 128) * 1e-3f; break;
      }
    }
    if (!gen::read(gen::binary(soup), m).ok()) return 0;
  }
  RepairOptions o;
  o.steps = in.byte() & ((1u << kRepairStepCount) - 1);
  const uint32_t tol = in.byte();
  o.stitchTolerance = tol < 128 ? 0 : double(tol - 127) * 1e-3;
  o.maxHoleEdges = in.byte();
  const uint32_t flags = in.byte();
  o.fillRefine = flags & 1;
  o.fillFair = flags & 2;
  o.removeOppositeDuplicates = flags & 4;
  o.intersections = flags & 8;
  o.maxPairs = 1 + in.byte() * 64;
  o.minShellTriangles = in.byte() % 32;
  if (flags & 16) o.exclude.push_back({RepairStepKind(in.byte() % kRepairStepCount), in.byte() % 4});
  o.keepResult = !(flags & 32);

  Mesh before;
  {
    EditableMesh probe;
    FUZZ_CHECK(probe.init(m).ok());
    FUZZ_CHECK(probe.toMesh(before, nullptr, nullptr).ok());
  }
  RepairPlan plan;
  Status s = planRepair(m, o, plan);
  if (!s.ok()) {
    if (s.code != Code::OutOfMemory && s.code != Code::Aborted) std::fprintf(stderr, "plan: %s\n", s.message.c_str());
    FUZZ_CHECK(s.code == Code::OutOfMemory || s.code == Code::Aborted);
    return 0;
  }
  EditableMesh em;
  FUZZ_CHECK(em.init(m).ok());
  RepairLog log;
  s = applyRepair(em, plan, log);
  FUZZ_CHECK(s.ok());
  if (log.afterReport != plan.afterReport) {
    std::fprintf(stderr, "plan: %s\nresult: %s\n", plan.afterReport.c_str(), log.afterReport.c_str());
    FUZZ_CHECK(log.afterReport == plan.afterReport);
  }
  s = em.validate();
  if (!s.ok()) std::fprintf(stderr, "validate: %s\n", s.message.c_str());
  FUZZ_CHECK(s.ok());
  if (plan.resultTaken()) {
    // apply took the plan's own result: running the steps (a second apply of the plan) must
    // give the same log and mesh.
    EditableMesh ran;
    RepairLog ranLog;
    FUZZ_CHECK(ran.init(m).ok());
    FUZZ_CHECK(applyRepair(ran, plan, ranLog).ok());
    if (repairLogJson(ranLog) != repairLogJson(log)) {
      std::fprintf(stderr, "taken: %s\nran: %s\n", repairLogJson(log).c_str(), repairLogJson(ranLog).c_str());
      FUZZ_CHECK(false);
    }
    Mesh a, b;
    FUZZ_CHECK(em.toMesh(a, nullptr, nullptr).ok() && ran.toMesh(b, nullptr, nullptr).ok());
    FUZZ_CHECK(gen::sameMesh(a, b));
  } else {
    FUZZ_CHECK(!o.keepResult);
  }
  {
    // The CLI's way, into a Mesh (a fresh plan, whose result it takes when it kept one): the
    // same mesh and log.
    RepairPlan again;
    FUZZ_CHECK(planRepair(m, o, again).ok());
    Mesh out, a;
    RepairLog outLog;
    FUZZ_CHECK(applyRepair(m, again, out, outLog).ok());
    FUZZ_CHECK(again.resultTaken() == o.keepResult);
    FUZZ_CHECK(em.toMesh(a, nullptr, nullptr).ok());
    FUZZ_CHECK(gen::sameMesh(out, a));
    FUZZ_CHECK(repairLogJson(outLog) == repairLogJson(log));
  }
  while (!log.steps.empty()) {
    s = undoRepairStep(em, log);
    if (!s.ok()) std::fprintf(stderr, "undo: %s\n", s.message.c_str());
    FUZZ_CHECK(s.ok());
    FUZZ_CHECK(em.validate().ok());
  }
  Mesh back;
  FUZZ_CHECK(em.toMesh(back, nullptr, nullptr).ok());
  FUZZ_CHECK(gen::sameMesh(back, before));
  return 0;
}
