// In-process timer of the repair (issue 23): a plain load (read + buildTopology, the
// `info` path), planRepair, EditableMesh::init and applyRepair, with the time of each step
// in the plan and in the apply (RepairOptions::onStep: a step's time includes the runner's
// rebuild of the mesh after it), medians of N runs. "whole" is plan + init + apply, the
// whole repair of a loaded mesh into an editor, the JS API's way: EditableMesh.from(mesh)
// defers its editor, and applyRepair(mesh, plan, em, log) takes the plan's result ("init" is
// then 0). --init: EditableMesh::init(mesh) first, then applyRepair(em, plan, log), an
// editor of the input that the apply replaces with the result. --cli: the CLI's way
// instead, applyRepair(mesh, plan, result, log) into the Mesh it writes, which takes the
// plan's result without an EditableMesh of the input or of the result ("init" is then 0).
// The CLI reads the file and plans; the plan builds the topology it needs, and the CLI
// builds no other: so its "whole" (its repair beyond a plain load) is read + plan + apply -
// load, that is plan + apply - (load - read), the plain load's topology taken out ("read"
// is the readStl part of the load).
// Prints one JSON object. apply takes the plan's own result (RepairPlan::result), so its
// steps take no time there: the time of each step is the plan's ("planSteps"); --no-keep
// (RepairOptions::keepResult = false) makes apply run the steps again, as before plans
// kept their result.
//   stltopo_repair_bench FILE [--reps N] [--steps a,b,...] [--no-intersections] [--threads N] [--no-keep]
//                        [--cli | --init]
// --threads N: RepairOptions::threads, and the load and init on as many.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "stltopo/stltopo.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}
struct StepTimes {
  std::map<std::string, double> seconds;
  Clock::time_point t0;
};
void onStep(void* user, stltopo::RepairStepKind k, bool done) {
  auto* st = static_cast<StepTimes*>(user);
  if (!done)
    st->t0 = Clock::now();
  else
    st->seconds[stltopo::repairStepName(k)] += since(st->t0);
}
}  // namespace

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // As the CLI (which `stltopo repair` runs) and stltopo_stages do: freed arrays stay in the
  // heap for the next ones, instead of fresh pages that the kernel must zero first.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: stltopo_repair_bench FILE [--reps N] [--steps a,b,...] [--no-intersections] [--threads N] "
                 "[--no-keep] [--cli | --init]\n");
    return 2;
  }
  int reps = 3;
  bool cli = false, initFirst = false;
  stltopo::RepairOptions ro;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--cli"))
      cli = true;
    else if (!std::strcmp(argv[i], "--init"))
      initFirst = true;
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc)
      ro.threads = unsigned(std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--no-intersections"))
      ro.intersections = false;
    else if (!std::strcmp(argv[i], "--no-keep"))
      ro.keepResult = false;
    else if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) {
      ro.steps = 0;
      std::string list = argv[++i];
      size_t a = 0;
      while (a <= list.size()) {
        size_t b = list.find(',', a);
        if (b == std::string::npos) b = list.size();
        stltopo::RepairStepKind k;
        if (!stltopo::repairStepFromName(list.substr(a, b - a), k)) {
          std::fprintf(stderr, "unknown step\n");
          return 2;
        }
        ro.steps |= stltopo::repairStepBit(k);
        a = b + 1;
      }
    }
  }
  std::ifstream f(argv[1], std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::vector<double> load, read, plan, apply, init, whole;
  std::map<std::string, std::vector<double>> steps, planSteps;
  stltopo::RepairLog last;
  for (int r = 0; r < reps; ++r) {
    auto t0 = Clock::now();
    stltopo::Mesh mesh;
    stltopo::Topology topo;
    stltopo::ReadOptions rdo;
    rdo.threads = ro.threads;
    if (!stltopo::readStl(bytes.data(), bytes.size(), mesh, rdo).ok()) return 1;
    read.push_back(since(t0));
    stltopo::TopologyOptions lean;
    lean.prevAndFace = false;
    lean.threads = ro.threads;
    if (!stltopo::buildTopology(mesh, topo, lean).ok()) return 1;
    load.push_back(since(t0));
    StepTimes pst;
    stltopo::RepairOptions timed = ro;
    timed.onStep = onStep;
    timed.user = &pst;
    t0 = Clock::now();
    stltopo::RepairPlan p;
    if (!stltopo::planRepair(mesh, timed, p).ok()) return 1;
    plan.push_back(since(t0));
    for (auto& [k, v] : pst.seconds) planSteps[k].push_back(v);
    StepTimes st;
    p.options.onStep = onStep;
    p.options.user = &st;
    stltopo::EditableMesh em;
    stltopo::TopologyOptions to;
    to.threads = ro.threads;
    stltopo::RepairLog log;
    if (cli) {
      // The CLI's way (`stltopo repair IN OUT`): applyRepair from the loaded Mesh into the
      // Mesh it writes, which takes the plan's result without building an EditableMesh.
      init.push_back(0);
      t0 = Clock::now();
      stltopo::Mesh result;
      if (!stltopo::applyRepair(mesh, p, result, log, to).ok()) return 1;
      apply.push_back(since(t0));
    } else if (!initFirst) {
      // The JS API's way: EditableMesh.from(mesh) defers the editor (no tolerance), and its
      // applyRepair(plan) is applyRepair(mesh, plan, em, log), which takes the plan's result
      // into em without an editor of the input (bindings/edit.cpp, applyRepairStaged).
      init.push_back(0);
      t0 = Clock::now();
      if (!stltopo::applyRepair(mesh, p, em, log, to).ok()) return 1;
      apply.push_back(since(t0));
    } else {
      t0 = Clock::now();
      if (!em.init(mesh, to).ok()) return 1;
      init.push_back(since(t0));
      t0 = Clock::now();
      if (!stltopo::applyRepair(em, p, log).ok()) return 1;
      apply.push_back(since(t0));
    }
    for (auto& [k, v] : st.seconds) steps[k].push_back(v);
    // The CLI reads the file and plans: the topology the plan builds is the only one it makes,
    // and the plain load's (load - read) is not part of its way. Its repair beyond a plain
    // load is therefore plan + apply - (load - read).
    whole.push_back(plan.back() + init.back() + apply.back() - (cli ? load.back() - read.back() : 0));
    if (r + 1 == reps) last = std::move(log);
  }
  std::printf(
      "{\"triangles\":%u,\"load\":%.4f,\"read\":%.4f,\"plan\":%.4f,\"init\":%.4f,\"apply\":%.4f,\"whole\":%.4f,"
      "\"steps\":{",
      last.before.stats.triangles, median(load), median(read), median(plan), median(init), median(apply), median(whole));
  bool first = true;
  for (auto& [k, v] : steps) {
    std::printf("%s\"%s\":%.4f", first ? "" : ",", k.c_str(), median(v));
    first = false;
  }
  std::printf("},\"planSteps\":{");
  first = true;
  for (auto& [k, v] : planSteps) {
    std::printf("%s\"%s\":%.4f", first ? "" : ",", k.c_str(), median(v));
    first = false;
  }
  std::printf(
      "},\"cli\":%s,\"holesBefore\":%u,\"holesAfter\":%u,\"inconsistentBefore\":%u,\"inconsistentAfter\":%u,\"solid\":%"
      "s}\n",
      cli ? "true" : "false", last.before.stats.holes, last.after.stats.holes, last.before.stats.inconsistentEdges,
      last.after.stats.inconsistentEdges, last.after.solid ? "true" : "false");
  return 0;
}
