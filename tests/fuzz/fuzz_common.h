// Shared checks for the libFuzzer targets. A broken invariant calls __builtin_trap(),
// which libFuzzer reports as a crash (with the input saved as crash-<sha1>).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "../stl_gen.h"
#include "geometry_detail.h"  // private (src/): the patch certificates' test hooks
#include "stltopo/stltopo.h"

namespace fuzz {

using namespace stltopo;

[[noreturn]] inline void fail(const char* what, int line) {
  std::fprintf(stderr, "fuzz check failed (line %d): %s\n", line, what);
  __builtin_trap();
}
#define FUZZ_CHECK(cond)                        \
  do {                                          \
    if (!(cond)) ::fuzz::fail(#cond, __LINE__); \
  } while (0)

inline bool isErrorCode(Code c) { return c >= Code::Empty && c <= Code::Invalid; }
inline bool isWarningCode(Code c) { return c >= Code::TrailingBytes && c <= Code::NameTruncated; }

inline bool startsWith(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

// A read error: a known error code, a message "<code>: ..." and a JSON rendering.
inline void checkError(const Status& s) {
  FUZZ_CHECK(isErrorCode(s.code));
  FUZZ_CHECK(s.code != Code::Invalid && s.code != Code::Aborted);  // the reader never returns these
  FUZZ_CHECK(s.message.size() > std::strlen(codeName(s.code)) + 2);
  FUZZ_CHECK(startsWith(s.message, std::string(codeName(s.code)) + ": "));
  std::string j = errorJson("f", s);
  FUZZ_CHECK(!j.empty() && j.front() == '{' && j.back() == '}');
}

// A successfully read mesh is well formed.
inline void checkMesh(const Mesh& m, const ReadOptions& o) {
  FUZZ_CHECK(m.format == Format::Binary || m.format == Format::Ascii);
  FUZZ_CHECK(m.positions.size() % 3 == 0 && m.triangles.size() % 3 == 0);
  const uint32_t nv = m.nVertices(), nt = m.nTriangles();
  FUZZ_CHECK(nt <= o.maxTriangles);
  for (size_t i = 0; i < m.triangles.size(); ++i) FUZZ_CHECK(m.triangles[i] < nv);
  for (size_t i = 0; i < m.positions.size(); ++i) FUZZ_CHECK(std::isfinite(m.positions[i]));
  // Vertex ids follow first appearance in corner order.
  uint32_t seen = 0;
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    FUZZ_CHECK(m.triangles[i] <= seen);
    if (m.triangles[i] == seen) ++seen;
  }
  FUZZ_CHECK(seen == nv);
  FUZZ_CHECK(m.attributes.size() == nt);
  FUZZ_CHECK(m.normals.size() == (o.keepNormals ? size_t(nt) * 3 : 0));
  if (m.colorConvention == ColorConvention::None) {
    FUZZ_CHECK(m.colors.empty() && m.colorValid.empty());
  } else {
    FUZZ_CHECK(m.colors.size() == size_t(nt) * 3 && m.colorValid.size() == nt);
  }
  uint32_t next = 0;
  for (const Solid& s : m.solids) {
    FUZZ_CHECK(s.firstTriangle == next);
    FUZZ_CHECK(s.name.size() <= kMaxNameBytes);
    next += s.triangleCount;
  }
  FUZZ_CHECK(next == nt);
  FUZZ_CHECK(!m.solids.empty() || nt == 0);
  for (const Status& w : m.warnings) {
    FUZZ_CHECK(isWarningCode(w.code));
    FUZZ_CHECK(startsWith(w.message, std::string(codeName(w.code)) + ": "));
  }
  FUZZ_CHECK(std::isfinite(m.area) && m.area >= 0 && std::isfinite(m.volume));
  if (nv > 0)
    for (int k = 0; k < 3; ++k) FUZZ_CHECK(m.bboxMin[k] <= m.bboxMax[k]);
}

// Topology + validate + report on a successfully read mesh.
inline void checkTopology(const Mesh& m, const TopologyOptions& to, Topology& t) {
  Status s = buildTopology(m, t, to);
  if (!s.ok()) {
    std::fprintf(stderr, "buildTopology: %s\n", s.message.c_str());
    FUZZ_CHECK(s.ok());
  }
  s = validate(m, t);
  if (!s.ok()) {
    std::fprintf(stderr, "validate: %s\n", s.message.c_str());
    FUZZ_CHECK(s.ok());
  }
  FUZZ_CHECK(t.nBoundaryEdges + t.nNonManifoldEdges + t.nInconsistentEdges <= t.nEdges);
  // The report-only topology (prevAndFace = false, as the CLIs build it) is the same.
  const std::string lean = gen::leanTopologyDifference(m, t, to.tolerance);
  if (!lean.empty()) {
    std::fprintf(stderr, "prevAndFace = false differs: %s\n", lean.c_str());
    FUZZ_CHECK(lean.empty());
  }
  FUZZ_CHECK(t.nDegenerate <= t.nTriangles);
  std::string j = infoJson("f", m, &t);
  FUZZ_CHECK(!j.empty() && j.front() == '{' && j.back() == '}');
}

using gen::sameArray;

// The intersection pass's work limit in the checks: a fuzz input may be a coplanar soup, so
// each run is kept short.
constexpr uint64_t kFuzzMaxPairs = 1u << 16;

// The exact geometry (issue 21) of a topology with triangleShell: the invariants of every
// list, the work limit, and the report with every extra. Returns that report.
inline std::string checkGeometry(const Mesh& m, const Topology& t, const Array<Shell>& shells, const Defects& d) {
  GeometryReport g;
  IntersectionOptions io;
  io.maxPairs = kFuzzMaxPairs;
  Status s = analyzeGeometry(m, t, g, io);
  if (!s.ok()) {
    std::fprintf(stderr, "analyzeGeometry: %s\n", s.message.c_str());
    FUZZ_CHECK(s.ok());
  }
  const uint32_t nt = m.nTriangles();
  const TriangleChecks& c = g.checks;
  for (size_t i = 0; i < c.zeroArea.size(); ++i) {
    const uint32_t z = c.zeroArea[i];
    FUZZ_CHECK(z < nt && (i == 0 || c.zeroArea[i - 1] < z));
    const uint32_t* v = m.triangles.data() + 3 * size_t(z);
    const uint32_t a = t.vertexWeld[v[0]], b = t.vertexWeld[v[1]], cc = t.vertexWeld[v[2]];
    FUZZ_CHECK(a != b && b != cc && a != cc);  // zero-area and degenerate are disjoint
  }
  uint32_t members = 0;
  for (uint32_t k = 0; k < c.nDuplicateGroups(); ++k) {
    const uint32_t b = c.duplicateOffsets[k], e = c.duplicateOffsets[k + 1];
    FUZZ_CHECK(e >= b + 2 && c.duplicateOrientation[k] <= 2);
    for (uint32_t i = b + 1; i < e; ++i) FUZZ_CHECK(c.duplicateTriangles[i - 1] < c.duplicateTriangles[i]);
    if (k > 0) FUZZ_CHECK(c.duplicateTriangles[c.duplicateOffsets[k - 1]] < c.duplicateTriangles[b]);
    members += e - b - 1;
  }
  FUZZ_CHECK(members == c.nDuplicateTriangles);
  if (t.tolerance == 0) {  // the topology's shortcut and hashing every triangle agree
    TriangleChecks alone;
    FUZZ_CHECK(checkTriangles(m, nullptr, alone).ok());
    FUZZ_CHECK(sameArray(alone.zeroArea, c.zeroArea) && sameArray(alone.duplicateTriangles, c.duplicateTriangles) &&
               sameArray(alone.duplicateOffsets, c.duplicateOffsets) &&
               sameArray(alone.duplicateOrientation, c.duplicateOrientation));
  }
  const Intersections& x = g.intersections;
  FUZZ_CHECK(x.nCrossing + x.nTouching + x.nCoplanar == x.nPairs());
  FUZZ_CHECK(x.nPairs() <= io.maxPairs);
  uint32_t flagged = 0;
  for (uint32_t tri = 0; tri < nt; ++tri) flagged += x.triangleIntersects[tri];
  FUZZ_CHECK(flagged == x.nIntersectingTriangles);
  for (size_t i = 0; i < x.nPairs(); ++i) {
    const uint32_t a = x.pairs[2 * i], b = x.pairs[2 * i + 1];
    FUZZ_CHECK(a < b && b < nt && x.kinds[i] <= 2 && x.triangleIntersects[a] && x.triangleIntersects[b]);
    FUZZ_CHECK(t.triangleShell[a] != kInvalid && t.triangleShell[b] != kInvalid);
    if (i > 0) FUZZ_CHECK((uint64_t(x.pairs[2 * i - 2]) << 32 | x.pairs[2 * i - 1]) < (uint64_t(a) << 32 | b));
  }
  // The patch certificates never hide a pair: with every node of 2 or more positions tried,
  // and every one above 8 tried as a union of its children, the pass finds what it finds
  // with no patches (when both complete: where a pass stops depends on the tests it made).
  {
    Intersections off, small;
    geometry_detail::setPatchCertificatesForTesting(false);
    const Status a = findIntersections(m, t, c, off, io);
    geometry_detail::setPatchCertificatesForTesting(true);
    geometry_detail::setPatchMinimumForTesting(2);
    geometry_detail::setPatchTaskSizeForTesting(8);
    const Status b = findIntersections(m, t, c, small, io);
    geometry_detail::setPatchMinimumForTesting(0);
    geometry_detail::setPatchTaskSizeForTesting(0);
    FUZZ_CHECK(a.ok() && b.ok());
    if (off.complete && small.complete)
      FUZZ_CHECK(sameArray(off.pairs, small.pairs) && sameArray(off.kinds, small.kinds));
  }
  const ShellNesting& n = g.nesting;
  for (size_t k = 0; k < shells.size(); ++k) {
    if (n.depth[k] == kInvalid) {
      FUZZ_CHECK(n.parent[k] == kInvalid);
      continue;
    }
    FUZZ_CHECK(shells[k].closed() && n.intersectsOffsets[k] == n.intersectsOffsets[k + 1]);
    FUZZ_CHECK((n.parent[k] == kInvalid) == (n.depth[k] == 0));
    if (n.parent[k] != kInvalid) FUZZ_CHECK(n.parent[k] < shells.size() && n.depth[n.parent[k]] + 1 <= n.depth[k]);
  }
  if (g.solid) FUZZ_CHECK(x.complete && x.nPairs() == 0 && t.watertight() && t.manifold());
  ReportExtras e{&g.shells, &d, 3};
  e.checks = &c;
  e.intersections = &x;
  e.nesting = &n;
  e.solid = g.solid;
  std::string j = infoJson("f", m, &t, e);
  FUZZ_CHECK(!j.empty() && j.front() == '{' && j.back() == '}');
  FUZZ_CHECK(!infoText("f", m, &t, e).empty());
  // The checks the plain report makes itself are the same.
  FUZZ_CHECK(infoJson("f", m, &t).find("\"zeroAreaTriangles\":" + std::to_string(c.zeroArea.size()) + ",") !=
             std::string::npos);
  return j;
}

// The shell report and the defect lists of the report-only topology with triangleShell:
// the shells' counts add up to the whole report's, the lists have its counts, and each
// (of the first few) shell extracted on its own is one shell with the same report.
inline void checkShells(const Mesh& m, TopologyOptions to, const Topology& full) {
  to.prevAndFace = false;
  to.triangleShell = true;
  Topology t;
  FUZZ_CHECK(buildTopology(m, t, to).ok());
  Array<Shell> shells;
  Defects d;
  Status s = findShellsAndDefects(m, t, &shells, &d);
  if (!s.ok()) {
    std::fprintf(stderr, "findShellsAndDefects: %s\n", s.message.c_str());
    FUZZ_CHECK(s.ok());
  }
  FUZZ_CHECK(shells.size() == full.nShells);
  uint64_t tris = 0, edges = 0, bnd = 0, nme = 0, inc = 0, holes = 0, seams = 0;
  for (const Shell& sh : shells) {
    tris += sh.triangles;
    edges += sh.edges;
    bnd += sh.boundaryEdges;
    nme += sh.nonManifoldEdges;
    inc += sh.inconsistentEdges;
    holes += sh.holes;
    seams += sh.seams;
  }
  FUZZ_CHECK(tris == full.nTriangles - full.nDegenerate && edges == full.nEdges && bnd == full.nBoundaryEdges);
  FUZZ_CHECK(nme == full.nNonManifoldEdges && inc == full.nInconsistentEdges && holes == full.nHoles &&
             seams == full.nSeams);
  FUZZ_CHECK(d.nonManifoldEdgeVertices.size() == 2 * size_t(full.nNonManifoldEdges));
  FUZZ_CHECK(d.inconsistentEdgeVertices.size() == 2 * size_t(full.nInconsistentEdges));
  FUZZ_CHECK(d.nonManifoldVertices.size() == full.nNonManifoldVertices &&
             d.degenerateTriangles.size() == full.nDegenerate);
  std::string j = infoJson("f", m, &t, ReportExtras{&shells, &d, 3});
  FUZZ_CHECK(!j.empty() && j.front() == '{' && j.back() == '}');
  const std::string whole = checkGeometry(m, t, shells, d);
  // The loops that wasm runs in chunks (detail::forChunks) give the whole loops' result, here
  // in chunks of 3 items: the topology, the shells and defects, the checks and the pass.
  {
    setChunkItemsForTesting(3);
    Topology tc;
    Array<Shell> sc;
    Defects dc;
    GeometryReport gc;
    IntersectionOptions io;
    io.maxPairs = kFuzzMaxPairs;
    const bool ok = buildTopology(m, tc, to).ok() && findShellsAndDefects(m, tc, &sc, &dc).ok() &&
                    analyzeGeometry(m, tc, gc, io).ok();
    setChunkItemsForTesting(0);
    FUZZ_CHECK(ok);
    FUZZ_CHECK(sameArray(tc.next, t.next) && sameArray(tc.vert, t.vert) && sameArray(tc.pairKind, t.pairKind) &&
               sameArray(tc.triangleShell, t.triangleShell) && sameArray(tc.vertexNonManifold, t.vertexNonManifold) &&
               sameArray(tc.loopHalfedges, t.loopHalfedges));
    ReportExtras e{&gc.shells, &dc, 3};
    e.checks = &gc.checks;
    e.intersections = &gc.intersections;
    e.nesting = &gc.nesting;
    e.solid = gc.solid;
    FUZZ_CHECK(infoJson("f", m, &tc, e) == whole);
  }
  for (uint32_t i = 0; i < shells.size() && i < 4; ++i) {
    Mesh part;
    FUZZ_CHECK(extractShell(m, t, i, part).ok());
    FUZZ_CHECK(part.nTriangles() == shells[i].triangles && part.nVertices() >= 3);
    if (to.tolerance > 0) continue;  // welded vertices apart from the others may weld differently alone
    Topology pt;
    FUZZ_CHECK(buildTopology(part, pt, to).ok());
    FUZZ_CHECK(pt.nShells == 1 && pt.nEdges == shells[i].edges && pt.nUsedVertices == shells[i].vertices);
  }
}

inline bool sameStatus(const Status& a, const Status& b) {
  return a.code == b.code && a.message == b.message && a.offset == b.offset && a.line == b.line &&
         a.triangle == b.triangle && a.element == b.element;
}

// Bit-for-bit equality of two read results.
inline void checkSameMesh(const Mesh& a, const Mesh& b) {
  FUZZ_CHECK(a.format == b.format);
  FUZZ_CHECK(sameArray(a.positions, b.positions));
  FUZZ_CHECK(sameArray(a.triangles, b.triangles));
  FUZZ_CHECK(sameArray(a.attributes, b.attributes));
  FUZZ_CHECK(sameArray(a.normals, b.normals));
  FUZZ_CHECK(sameArray(a.colors, b.colors));
  FUZZ_CHECK(sameArray(a.colorValid, b.colorValid));
  FUZZ_CHECK(a.colorConvention == b.colorConvention);
  FUZZ_CHECK(a.solids.size() == b.solids.size());
  for (size_t i = 0; i < a.solids.size(); ++i) {
    FUZZ_CHECK(a.solids[i].name == b.solids[i].name);
    FUZZ_CHECK(a.solids[i].firstTriangle == b.solids[i].firstTriangle);
    FUZZ_CHECK(a.solids[i].triangleCount == b.solids[i].triangleCount);
  }
  FUZZ_CHECK(a.warnings.size() == b.warnings.size());
  for (size_t i = 0; i < a.warnings.size(); ++i) FUZZ_CHECK(sameStatus(a.warnings[i], b.warnings[i]));
  FUZZ_CHECK(a.normalMismatches == b.normalMismatches);
  FUZZ_CHECK(std::memcmp(&a.area, &b.area, sizeof a.area) == 0);
  FUZZ_CHECK(std::memcmp(&a.volume, &b.volume, sizeof a.volume) == 0);
  FUZZ_CHECK(std::memcmp(a.bboxMin, b.bboxMin, sizeof a.bboxMin) == 0);
  FUZZ_CHECK(std::memcmp(a.bboxMax, b.bboxMax, sizeof a.bboxMax) == 0);
}

}  // namespace fuzz
