// Edits per second through the EditableMesh API.
//   stltopo_edits FILE [N] [--json]
// Loads FILE (readStl + EditableMesh::init + reserve, not timed), then times N edits of each kind on
// elements picked at random (fixed seed), one kind after the other on the same mesh:
// removeTriangle; addTriangle (the removed triangles put back); flipEdge, splitEdge and
// collapseEdge on random half-edges; reverseTriangle; fillHole (fan) on the holes of up to N
// fresh removals that share no vertex. A refused edit counts as an attempt; "done" counts the edits that were made.
// No stats() or loops() are read between edits (those are O(n) after an edit, by contract).
// The rate is per CPU second of the process (the VM's cores are shared; wall time is shown too).
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "stltopo/stltopo.h"

using namespace stltopo;
using Clock = std::chrono::steady_clock;

static double cpuMs() {  // CPU time of the process: immune to waiting for a busy core
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: stltopo_edits FILE [N] [--json]\n");
    return 2;
  }
  uint32_t n = 100000;
  bool json = false;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--json"))
      json = true;
    else
      n = uint32_t(std::atol(argv[i]));
  }
  std::ifstream f(argv[1], std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  Mesh mesh;
  Status s = readStl(bytes.data(), bytes.size(), mesh);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message.c_str());
    return 1;
  }
  EditableMesh em;
  s = em.init(mesh);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message.c_str());
    return 1;
  }
  // Room for the edits (split adds 1 vertex and 2 triangles each, fill up to N), so that no
  // timed edit is the one that doubles an array.
  s = em.reserve(2 * n, 4 * n);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message.c_str());
    return 1;
  }
  std::mt19937_64 rng(1);
  auto pick = [&](uint32_t bound) { return uint32_t(rng() % bound); };
  auto liveTriangle = [&]() {
    uint32_t t = pick(em.nTriangles());
    while (!em.triangleAlive(t)) t = (t + 1) % em.nTriangles();
    return t;
  };
  auto liveHalfedge = [&]() {
    uint32_t e = pick(em.nHalfedges());
    while (!em.halfedgeAlive(e)) e = (e + 1) % em.nHalfedges();
    return e;
  };
  struct Row {
    const char* op;
    uint32_t attempts, done;
    double ms, cpu;
  };
  std::vector<Row> rows;
  auto timed = [&](const char* op, auto&& body, uint32_t count) {
    uint32_t done = 0;
    auto t0 = Clock::now();
    double c0 = cpuMs();
    for (uint32_t i = 0; i < count; ++i) done += body() ? 1 : 0;
    double cpu = cpuMs() - c0;
    double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    rows.push_back(Row{op, count, done, ms, cpu});
  };
  std::vector<uint32_t> removed;
  timed(
      "removeTriangle",
      [&]() {
        uint32_t t = liveTriangle();
        const uint32_t* c = em.triangles().data() + 3 * size_t(t);
        removed.insert(removed.end(), {c[0], c[1], c[2]});
        return em.removeTriangle(t).ok();
      },
      n);
  size_t k = 0;
  timed(
      "addTriangle",
      [&]() {
        bool ok = em.addTriangle(removed[k], removed[k + 1], removed[k + 2]).ok();
        k += 3;
        return ok;
      },
      n);
  timed(
      "flipEdge", [&]() { return em.flipEdge(liveHalfedge()).ok(); }, n);
  timed(
      "splitEdge", [&]() { return em.splitEdge(liveHalfedge(), 0.5).ok(); }, n);
  timed(
      "collapseEdge", [&]() { return em.collapseEdge(liveHalfedge(), 0.5).ok(); }, n);
  timed(
      "reverseTriangle", [&]() { return em.reverseTriangle(liveTriangle()).ok(); }, n);
  // Holes that share no vertex: triangles none of whose corners an earlier pick used.
  std::vector<uint32_t> holes;
  {
    std::vector<uint8_t> used(em.nVertices(), 0);
    for (uint64_t tries = 0; holes.size() < n && tries < 50ull * n; ++tries) {
      uint32_t t = pick(em.nTriangles());
      const uint32_t* c = em.triangles().data() + 3 * size_t(t);
      if (!em.triangleAlive(t) || used[c[0]] || used[c[1]] || used[c[2]]) continue;
      used[c[0]] = used[c[1]] = used[c[2]] = 1;
      uint32_t h = em.triangleHalfedge()[t];
      if (h != kInvalid && em.removeTriangle(t).ok()) holes.push_back(h);
    }
  }
  k = 0;
  timed(
      "fillHole",
      [&]() {
        uint32_t h = holes[k++];
        return em.halfedgeAlive(h) && em.isBoundary(h) && em.fillHole(h, FillMethod::Fan).ok();
      },
      uint32_t(holes.size()));
  s = em.validate();
  if (!s.ok()) {
    std::fprintf(stderr, "validate after the edits: %s\n", s.message.c_str());
    return 1;
  }
  if (json)
    std::printf("{\"triangles\":%u,\"edits\":[", mesh.nTriangles());
  else
    std::printf("%s: %u triangles, %u edits per kind\n", argv[1], mesh.nTriangles(), n);
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    double perSec = r.attempts / (r.cpu / 1e3);
    if (json)
      std::printf("%s{\"op\":\"%s\",\"attempts\":%u,\"done\":%u,\"ms\":%.3f,\"cpuMs\":%.3f,\"perCpuSecond\":%.0f}",
                  i ? "," : "", r.op, r.attempts, r.done, r.ms, r.cpu, perSec);
    else
      std::printf("  %-16s %8u attempts %8u done %9.1f ms wall %9.1f ms cpu %12.0f /s cpu\n", r.op, r.attempts, r.done,
                  r.ms, r.cpu, perSec);
  }
  if (json) std::printf("]}\n");
  return 0;
}
