// Edits per second through the EditableMesh API.
//   stltopo_edits FILE [N] [--json]
// Loads FILE (readStl + EditableMesh::init, not timed), then times N edits of each kind on
// elements picked at random (fixed seed), one kind after the other on the same mesh:
// removeTriangle; addTriangle (the removed triangles put back); flipEdge, splitEdge and
// collapseEdge on random half-edges; reverseTriangle; fillHole (fan) on the holes of N fresh
// removals. A refused edit counts as an attempt; "done" counts the edits that were made.
// No stats() or loops() are read between edits (those are O(n) after an edit, by contract).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "edit.h"

using namespace stltopo;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: stltopo_edits FILE [N] [--json]\n");
    return 2;
  }
  uint32_t n = 100000;
  bool json = false;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--json")) json = true;
    else n = uint32_t(std::atol(argv[i]));
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
    double ms;
  };
  std::vector<Row> rows;
  auto timed = [&](const char* op, auto&& body) {
    uint32_t done = 0;
    auto t0 = Clock::now();
    for (uint32_t i = 0; i < n; ++i) done += body() ? 1 : 0;
    double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    rows.push_back(Row{op, n, done, ms});
  };
  std::vector<uint32_t> removed;
  timed("removeTriangle", [&]() {
    uint32_t t = liveTriangle();
    const uint32_t* c = em.triangles().data() + 3 * size_t(t);
    removed.insert(removed.end(), {c[0], c[1], c[2]});
    return em.removeTriangle(t).ok();
  });
  size_t k = 0;
  timed("addTriangle", [&]() {
    bool ok = em.addTriangle(removed[k], removed[k + 1], removed[k + 2]).ok();
    k += 3;
    return ok;
  });
  timed("flipEdge", [&]() { return em.flipEdge(liveHalfedge()).ok(); });
  timed("splitEdge", [&]() { return em.splitEdge(liveHalfedge(), 0.5).ok(); });
  timed("collapseEdge", [&]() { return em.collapseEdge(liveHalfedge(), 0.5).ok(); });
  timed("reverseTriangle", [&]() { return em.reverseTriangle(liveTriangle()).ok(); });
  std::vector<uint32_t> holes;
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t t = liveTriangle();
    uint32_t h = em.triangleHalfedge()[t];
    if (em.removeTriangle(t).ok() && h != kInvalid) holes.push_back(h);
  }
  k = 0;
  timed("fillHole", [&]() {
    uint32_t h = holes[k++];
    return em.halfedgeAlive(h) && em.isBoundary(h) && em.fillHole(h, FillMethod::Fan).ok();
  });
  s = em.validate();
  if (!s.ok()) {
    std::fprintf(stderr, "validate after the edits: %s\n", s.message.c_str());
    return 1;
  }
  if (json) std::printf("{\"triangles\":%u,\"edits\":[", mesh.nTriangles());
  else std::printf("%s: %u triangles, %u edits per kind\n", argv[1], mesh.nTriangles(), n);
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    double perSec = r.attempts / (r.ms / 1e3);
    if (json)
      std::printf("%s{\"op\":\"%s\",\"attempts\":%u,\"done\":%u,\"ms\":%.3f,\"perSecond\":%.0f}", i ? "," : "", r.op,
                  r.attempts, r.done, r.ms, perSec);
    else
      std::printf("  %-16s %8u attempts %8u done %9.1f ms %12.0f /s\n", r.op, r.attempts, r.done, r.ms, perSec);
  }
  if (json) std::printf("]}\n");
  return 0;
}
