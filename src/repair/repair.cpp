// The repair runner: plan (on a scratch copy), apply (with the change log), undo, and the
// plan and log as JSON. See include/stltopo/repair.h; the steps are in src/repair/*.cpp.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#if defined(__wasm_simd128__)
#include <wasm_simd128.h>
#endif

#include "edit/stats.h"
#include "geometry_detail.h"
#include "repair/steps.h"
#include "report_json.h"
#include "stltopo/geometry.h"
#include "stltopo/report.h"
#include "stltopo/shells.h"
#include "stltopo/topology.h"
#include "text_format.h"
#include "triangle_figures.h"
#include "try_alloc.h"

namespace stltopo {

namespace {

constexpr const char* kStepNames[kRepairStepCount] = {"duplicates",        "zero-area",  "stitch",      "orient",
                                                      "split-nonmanifold", "fill-holes", "small-shells"};
constexpr const char* kRepairArrays = "the repair's arrays";

// A run's result when its last step changed the mesh and its EditableMesh was not made
// again from it (run()'s `result`): `pending`, the result (compacted) and its topology, from
// which that EditableMesh is made (init(mesh, topo)) when one is wanted.
struct RunResult {
  bool pending = false;
  Mesh mesh;
  Topology topo;
};

// What a plan's run left (RepairPlan::result): the repaired mesh and the change log, with
// what they were made from.
}  // namespace

struct RepairResult {
  std::mutex lock;
  bool taken = false;
  uint64_t inputKey = 0;  // meshKey of the input as the plan found it (compacted)
  RepairOptions options;  // the plan's (onStep and user cleared)
  // The repaired mesh: `em`, or, when made.pending, made's mesh and topology (made into an
  // EditableMesh when an applyRepair takes it into one; one that wants the Mesh takes it as
  // it is).
  EditableMesh em;
  RunResult made;
  RepairLog log;
};

namespace {

// The attributes repair carries: the file's (the ones init() makes from a Mesh).
bool fileAttribute(const std::string& n) {
  return n == kAttrWord || n == kAttrColor || n == kAttrColorValid || n == kAttrNormal;
}

uint64_t mix(uint64_t h, uint64_t x) {
  h ^= x + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
  return h * 0xFF51AFD7ED558CCDull;
}

// A hash of the counts, then the positions, then the triangles. The words go two at a time
// into four independent chains of mix(), folded together at the end of each part: one chain
// waits on every multiply (the 1M torus: 8.5 ms a fingerprint natively), four chains of
// pairs take about an eighth of that. `positionsState` (when given) receives the hash after
// the positions, which is the same for every mesh with m's counts and positions:
// fingerprintAfterPositions continues from it.
// The n words word(0), ..., word(n - 1) into h.
template <class Word>
uint64_t hashWords(uint64_t h, size_t n, Word&& word) {
  uint64_t lane[4] = {h, h ^ 0x243F6A8885A308D3ull, h ^ 0x13198A2E03707344ull, h ^ 0xA4093822299F31D0ull};
  size_t i = 0;
  for (; i + 8 <= n; i += 8)
    for (size_t k = 0; k < 4; ++k) lane[k] = mix(lane[k], uint64_t(word(i + 2 * k)) << 32 | word(i + 2 * k + 1));
  for (; i < n; ++i) lane[0] = mix(lane[0], word(i));
  return mix(mix(mix(mix(lane[0], lane[1]), lane[2]), lane[3]), n);
}
uint64_t fingerprintAfterPositions(uint64_t h, const Mesh& m) {
  const uint32_t* t = m.triangles.data();
  return hashWords(h, m.triangles.size(), [t](size_t i) { return t[i]; });
}
uint64_t fingerprintOf(const Mesh& m, uint64_t* positionsState = nullptr) {
  uint64_t h = mix(0x5354'4C54'4F50'4F21ull, m.nVertices());
  h = mix(h, m.nTriangles());
  const float* p = m.positions.data();
  h = hashWords(h, m.positions.size(), [p](size_t i) {
    uint32_t u;
    std::memcpy(&u, p + i, 4);
    return (u << 1) == 0 ? 0u : u;  // -0 and 0 are one position
  });
  if (positionsState) *positionsState = h;
  return fingerprintAfterPositions(h, m);
}

// fingerprintOf (positions, triangles) and everything else of the Mesh that a repair
// carries into its result and its reports: attribute words, colours, normals, solids,
// warnings and the format. Two meshes with the same key repair to the same result and log.
uint64_t meshKey(const Mesh& m, uint64_t fingerprint) {
  uint64_t h = mix(fingerprint, uint64_t(m.format) << 8 | uint64_t(m.colorConvention));
  auto bytes = [&h](const void* p, size_t n) {
    const uint8_t* b = static_cast<const uint8_t*>(p);
    h = mix(h, n);
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      uint64_t x;
      std::memcpy(&x, b + i, 8);
      h = mix(h, x);
    }
    uint64_t x = 0;
    if (n > i) std::memcpy(&x, b + i, n - i);  // (an empty array's data() may be null)
    h = mix(h, x);
  };
  bytes(m.attributes.data(), m.attributes.size() * sizeof(uint16_t));
  bytes(m.normals.data(), m.normals.size() * sizeof(float));
  bytes(m.colors.data(), m.colors.size());
  bytes(m.colorValid.data(), m.colorValid.size());
  h = mix(h, m.solids.size());
  for (const Solid& sd : m.solids) {
    bytes(sd.name.data(), sd.name.size());
    h = mix(h, uint64_t(sd.firstTriangle) << 32 | sd.triangleCount);
  }
  h = mix(h, m.warnings.size());
  for (const Status& w : m.warnings) {
    h = mix(h, uint64_t(w.code));
    bytes(w.message.data(), w.message.size());
    h = mix(h, w.offset);
    h = mix(h, w.line);
    h = mix(h, uint64_t(w.triangle) << 32 | w.element);
  }
  return h;
}

// Whether n bytes at a and b are equal (memcmp(a, b, n) == 0). In wasm, 64 bytes a step
// with SIMD (8 without): Emscripten's memcmp (musl's) compares 4 bytes a step, which took
// 9 ms of the 1M torus's wasm plan (sameContent and the change log's diffs).
bool sameBytes(const void* a, const void* b, size_t n) {
#if defined(__EMSCRIPTEN__)
  const uint8_t *x = static_cast<const uint8_t*>(a), *y = static_cast<const uint8_t*>(b);
  size_t i = 0;
#if defined(__wasm_simd128__)
  for (; i + 64 <= n; i += 64) {
    v128_t d = wasm_v128_xor(wasm_v128_load(x + i), wasm_v128_load(y + i));
    d = wasm_v128_or(d, wasm_v128_xor(wasm_v128_load(x + i + 16), wasm_v128_load(y + i + 16)));
    d = wasm_v128_or(d, wasm_v128_xor(wasm_v128_load(x + i + 32), wasm_v128_load(y + i + 32)));
    d = wasm_v128_or(d, wasm_v128_xor(wasm_v128_load(x + i + 48), wasm_v128_load(y + i + 48)));
    if (wasm_v128_any_true(d)) return false;
  }
#endif
  for (; i + 8 <= n; i += 8) {
    uint64_t u, v;
    std::memcpy(&u, x + i, 8);
    std::memcpy(&v, y + i, 8);
    if (u != v) return false;
  }
  for (; i < n; ++i)
    if (x[i] != y[i]) return false;
  return true;
#else
  return n == 0 || std::memcmp(a, b, n) == 0;
#endif
}

// Whether EditableMesh::init gives the same state from a and b (with one topology): the
// same positions, triangles, attribute words, colours, normals, solids, warnings and format.
template <class T>
bool sameArray(const Array<T>& a, const Array<T>& b) {
  return a.size() == b.size() && (a.empty() || sameBytes(a.data(), b.data(), a.size() * sizeof(T)));
}
bool sameContent(const Mesh& a, const Mesh& b) {
  if (a.format != b.format || a.colorConvention != b.colorConvention || !sameArray(a.positions, b.positions) ||
      !sameArray(a.triangles, b.triangles) || !sameArray(a.attributes, b.attributes) ||
      !sameArray(a.normals, b.normals) || !sameArray(a.colors, b.colors) || !sameArray(a.colorValid, b.colorValid) ||
      a.solids.size() != b.solids.size() || a.warnings.size() != b.warnings.size())
    return false;
  for (size_t i = 0; i < a.solids.size(); ++i)
    if (a.solids[i].name != b.solids[i].name || a.solids[i].firstTriangle != b.solids[i].firstTriangle ||
        a.solids[i].triangleCount != b.solids[i].triangleCount)
      return false;
  for (size_t i = 0; i < a.warnings.size(); ++i) {
    const Status &x = a.warnings[i], &y = b.warnings[i];
    if (x.code != y.code || x.message != y.message || x.offset != y.offset || x.line != y.line ||
        x.triangle != y.triangle || x.element != y.element)
      return false;
  }
  return true;
}

// Whether two option sets make the same plan (onStep, user, threads and keepResult aside:
// they change no plan, log or result).
bool sameRepair(const RepairOptions& a, const RepairOptions& b) {
  if (a.steps != b.steps || a.removeOppositeDuplicates != b.removeOppositeDuplicates ||
      a.stitchTolerance != b.stitchTolerance || a.maxHoleEdges != b.maxHoleEdges || a.maxHoleArea != b.maxHoleArea ||
      a.maxHolePerimeter != b.maxHolePerimeter || a.fillRefine != b.fillRefine || a.fillFair != b.fillFair ||
      a.minShellTriangles != b.minShellTriangles || a.minShellVolume != b.minShellVolume ||
      a.intersections != b.intersections || a.maxPairs != b.maxPairs || a.exclude.size() != b.exclude.size())
    return false;
  for (size_t i = 0; i < a.exclude.size(); ++i)
    if (a.exclude[i].step != b.exclude[i].step || a.exclude[i].item != b.exclude[i].item) return false;
  return true;
}

double triangleArea(const float* a, const float* b, const float* c) {
  double u[3], w[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = double(b[k]) - a[k];
    w[k] = double(c[k]) - a[k];
  }
  double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2], z = u[0] * w[1] - u[1] * w[0];
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}
double meshTriangleArea(const Mesh& m, uint32_t t) {
  const uint32_t* c = m.triangles.data() + 3 * size_t(t);
  return triangleArea(&m.positions[3 * size_t(c[0])], &m.positions[3 * size_t(c[1])], &m.positions[3 * size_t(c[2])]);
}

Status checkOptions(const RepairOptions& o) {
  auto bad = [](const char* what) {
    return Status::error(Code::InvalidArgument, std::string("repair options: ") + what);
  };
  if (o.steps >> kRepairStepCount) return bad("steps has bits of no step");
  if (!std::isfinite(o.stitchTolerance) || o.stitchTolerance < 0)
    return bad("stitchTolerance must be a finite number >= 0");
  if (!std::isfinite(o.maxHoleArea) || o.maxHoleArea < 0) return bad("maxHoleArea must be a finite number >= 0");
  if (!std::isfinite(o.maxHolePerimeter) || o.maxHolePerimeter < 0)
    return bad("maxHolePerimeter must be a finite number >= 0");
  if (!std::isfinite(o.minShellVolume) || o.minShellVolume < 0)
    return bad("minShellVolume must be a finite number >= 0");
  if (o.maxPairs == 0) return bad("maxPairs must be at least 1");
  for (const RepairOptions::Exclusion& x : o.exclude)
    if (int(x.step) >= kRepairStepCount) return bad("an exclusion names no step");
  return Status{};
}

// Only the file's attributes are carried (repair rebuilds the mesh between steps).
Status checkAttributes(const EditableMesh& em) {
  STLTOPO_TRY {
    for (const std::string& n : em.attributeNames())
      if (!fileAttribute(n))
        return Status::error(
            Code::InvalidArgument,
            "repair carries only the file's attributes (attribute, color, colorValid, normal); remove \"" + n +
                "\" first");
  }
  STLTOPO_CATCH { return detail::oom(kRepairArrays); }
  return Status{};
}

Status runStepIn(RepairStepKind k, repair_detail::StepContext& ctx) {
  switch (k) {
    case RepairStepKind::Duplicates: return repair_detail::runDuplicates(ctx);
    case RepairStepKind::ZeroArea: return repair_detail::runZeroArea(ctx);
    case RepairStepKind::Stitch: return repair_detail::runStitch(ctx);
    case RepairStepKind::SplitNonManifold: return repair_detail::runSplitNonManifold(ctx);
    case RepairStepKind::FillHoles: return repair_detail::runFillHoles(ctx);
    case RepairStepKind::Orient: return repair_detail::runOrient(ctx);
    case RepairStepKind::SmallShells: return repair_detail::runSmallShells(ctx);
  }
  return Status::error(Code::InvalidArgument, "no such repair step");
}

// A step, with its items' lists and texts (std containers) failing to allocate as out of
// memory: the runner then restores the mesh as it was before the step. (The wasm build has
// no exceptions: there such a failure aborts, and the JS layer starts a fresh module.)
Status runStep(RepairStepKind k, repair_detail::StepContext& ctx) {
  STLTOPO_TRY { return runStepIn(k, ctx); }
  STLTOPO_CATCH { return detail::oom("a repair step's items"); }
}

// The pass's pairs carried through the steps (run()): the pairs of the mesh as it is now,
// known without a pass when every step since the pass only removed triangles (duplicates,
// small shells), reversed them (orient) or added triangles that meet no other triangle but
// in the corners and sides they share (fill-holes checks each new triangle with the pass's
// exact pair test). A pair's triangles keep their points and the corners they share
// through those steps, so it intersects, and in the same way, exactly when it did, and the
// new triangles make no pair. A step that moves, merges, splits or collapses anything
// (zero-area, stitch, split-nonmanifold, when they did an item) makes them unknown.
struct KnownPairs {
  bool valid = false;
  Intersections found;
  // Follows a step that changed the mesh: `maps` (toMesh's, of the slots after the step)
  // and the step's kind.
  Status follow(RepairStepKind k, const CompactMaps& maps, uint32_t nTriangles) {
    if (!valid) return Status{};
    if (k == RepairStepKind::ZeroArea || k == RepairStepKind::Stitch || k == RepairStepKind::SplitNonManifold) {
      valid = false;
      found = Intersections{};
      return Status{};
    }
    Intersections next;
    next.complete = found.complete;
    next.work = found.work;
    if (!next.triangleIntersects.assign(nTriangles, 0)) return detail::oom(kRepairArrays);
    for (size_t i = 0; i < found.nPairs(); ++i) {
      const uint32_t a = found.pairs[2 * i], b = found.pairs[2 * i + 1];
      if (a >= maps.triangles.size() || b >= maps.triangles.size()) return bad();
      const uint32_t x = maps.triangles[a], y = maps.triangles[b];
      if (x == kInvalid || y == kInvalid) continue;                    // a triangle removed: the pair goes
      if (x >= y || x >= nTriangles || y >= nTriangles) return bad();  // survivors keep their order
      if (!next.pairs.push_back(x) || !next.pairs.push_back(y) || !next.kinds.push_back(found.kinds[i]) ||
          !next.points.push_back(found.points[3 * i]) || !next.points.push_back(found.points[3 * i + 1]) ||
          !next.points.push_back(found.points[3 * i + 2]))
        return detail::oom(kRepairArrays);
      geometry_detail::countPair(next, x, y, found.kinds[i]);
    }
    found = std::move(next);
    return Status{};
  }
  static Status bad() { return Status::error(Code::Invalid, "repair: the pairs do not fit the step's maps"); }
  // Whether figuresOf may take them for a mesh of nTriangles: only when the pass that found
  // them was complete and its work well under the limit for this mesh (a pass on the mesh
  // now makes about the same tests; a pass near the limit might not complete).
  bool usable(const RepairOptions& o, uint32_t nTriangles) const {
    return valid && found.complete && found.work <= geometry_detail::workLimit(o.maxPairs, nTriangles) / 4 &&
           found.triangleIntersects.size() == nTriangles;
  }
};

// The figures of `mesh` (compacted, as the runner holds it; topo: its topology). With
// `geometry`, the intersection pass too (self-intersections and solid), on `topo` when it has
// triangleShell (toMesh's with triangleShell equals a fresh build's), else on a fresh build
// with it. `keep`: the pass's pairs, kept. `known`: pairs carried to this mesh, taken (and
// used up) instead of the pass when they are usable; `solid` is then made from them as
// analyzeGeometry makes it. No shell list: `solid` comes from finishSolid (a shell pass only
// for a mesh that can be solid, and then only the volumes). `checksOut`: the triangle checks
// the figures came from, kept (for the report of the same mesh: reportOf).
Status figuresOf(const Mesh& mesh, const Topology& topo, const RepairOptions& o, bool geometry, RepairFigures& f,
                 Intersections* keep = nullptr, KnownPairs* known = nullptr, TriangleChecks* checksOut = nullptr) {
  f = RepairFigures{};
  // What em.stats() gives of an EditableMesh made from them (mesh is compacted: each of its
  // vertices is used by a triangle).
  f.stats = edit_detail::statsOf(topo, mesh.nVertices());
  if (!geometry || !o.intersections) {
    TriangleChecks checks;
    Status s = checkTriangles(mesh, &topo, checks, o.threads);
    if (!s.ok()) return s;
    f.zeroAreaTriangles = uint32_t(checks.zeroArea.size());
    f.duplicateTriangles = checks.nDuplicateTriangles;
    if (checksOut) *checksOut = std::move(checks);
    return Status{};
  }
  Topology t;
  const bool shells = topo.triangleShell.size() == mesh.nTriangles();
  if (!shells) {
    TopologyOptions to;
    to.prevAndFace = false;
    to.triangleShell = true;
    to.threads = o.threads;
    Status s = buildTopology(mesh, t, to);
    if (!s.ok()) return s;
  }
  const Topology& T = shells ? topo : t;
  GeometryReport g;
  Status s;
  if (known && known->usable(o, mesh.nTriangles())) {
    s = checkTriangles(mesh, &T, g.checks, o.threads);
    g.intersections = std::move(known->found);
    known->valid = false;
    if (s.ok()) s = geometry_detail::finishSolid(mesh, T, g);
  } else {
    IntersectionOptions io;
    io.maxPairs = o.maxPairs;
    io.threads = o.threads;
    s = analyzeGeometry(mesh, T, g, io, false);  // of the shells, only `solid` (no shell list)
  }
  if (!s.ok()) return s;
  f.zeroAreaTriangles = uint32_t(g.checks.zeroArea.size());
  f.duplicateTriangles = g.checks.nDuplicateTriangles;
  f.selfIntersections = uint32_t(std::min<uint64_t>(g.intersections.nPairs(), kInvalid - 1));
  f.solid = g.solid;
  if (keep) *keep = std::move(g.intersections);
  if (checksOut) *checksOut = std::move(g.checks);
  return Status{};
}

// infoJson of mesh (with topo), given its triangle checks when they are known (the same
// report: infoJson runs them itself otherwise).
// The checks are run here when unknown (infoJson would run them, and report their figures
// as unknown when they cannot allocate: here that is out of memory).
Status reportOf(const Mesh& mesh, const Topology& topo, const TriangleChecks* checks, unsigned threads,
                std::string& out) {
  TriangleChecks own;
  if (!checks) {
    Status s = checkTriangles(mesh, &topo, own, threads);
    if (!s.ok()) return s;
    checks = &own;
  }
  ReportExtras e;
  e.checks = checks;
  STLTOPO_TRY { out = infoJson("", mesh, &topo, e); }
  STLTOPO_CATCH { return detail::oom(kRepairArrays); }
  return Status{};
}

// The attribute values of triangle t of a Mesh, in the order `names` lists them.
struct AttrLayout {
  std::vector<std::string> names;
  std::vector<size_t> strides;
};
AttrLayout layoutOf(const Mesh& m) {
  AttrLayout l;
  if (!m.attributes.empty()) {
    l.names.push_back(kAttrWord);
    l.strides.push_back(2);
  }
  if (!m.colors.empty()) {
    l.names.push_back(kAttrColor);
    l.strides.push_back(3);
    l.names.push_back(kAttrColorValid);
    l.strides.push_back(1);
  }
  if (!m.normals.empty()) {
    l.names.push_back(kAttrNormal);
    l.strides.push_back(12);
  }
  return l;
}
// The layout of the attributes `names` (a step log's: layoutOf's names, in its order); false
// when one is not a file attribute.
bool layoutOfNames(const std::vector<std::string>& names, AttrLayout& l) {
  l = AttrLayout{};
  for (const std::string& n : names) {
    if (!fileAttribute(n)) return false;
    l.names.push_back(n);
    l.strides.push_back(n == kAttrWord ? 2 : n == kAttrColor ? 3 : n == kAttrColorValid ? 1 : 12);
  }
  return true;
}
const uint8_t* meshAttr(const Mesh& m, const std::string& n, uint32_t t) {
  if (n == kAttrWord) return reinterpret_cast<const uint8_t*>(m.attributes.data() + t);
  if (n == kAttrColor) return m.colors.data() + 3 * size_t(t);
  if (n == kAttrColorValid) return m.colorValid.data() + t;
  return reinterpret_cast<const uint8_t*>(m.normals.data() + 3 * size_t(t));
}
uint8_t* meshAttrW(Mesh& m, const std::string& n, uint32_t t) { return const_cast<uint8_t*>(meshAttr(m, n, t)); }

template <class T>
bool append(Array<T>& a, const T* p, size_t n) {
  size_t o = a.size();
  if (!a.resize(o + n)) return false;
  std::memcpy(a.data() + o, p, n * sizeof(T));
  return true;
}

// diffStep's comparison of em's triangles (now) with those of `before` (was), and the log
// entry of a triangle as it was before the step. Made, it starts L's attribute layout.
struct TriangleDiff {
  struct Column {
    const uint8_t* now;
    const uint8_t* was;
    size_t stride;
  };
  const Mesh& before;
  const uint32_t* now;  // em's corners
  AttrLayout lay;
  std::vector<Column> columns;  // the attributes compared: em's bytes against the mesh's
  TriangleDiff(const Mesh& b, const EditableMesh& em, RepairStepLog& L)
      : before(b), now(em.triangles().data()), lay(layoutOf(b)) {
    L.attributeNames = lay.names;
    L.attributeBefore.clear();
    L.attributeBefore.resize(lay.names.size());
    for (size_t a = 0; a < lay.names.size(); ++a) {
      const AttributeView* v = em.attribute(lay.names[a]);
      if (v && b.nTriangles() > 0)
        columns.push_back(Column{static_cast<const uint8_t*>(v->data), meshAttr(b, lay.names[a], 0), lay.strides[a]});
    }
  }
  // Whether triangles [t0, t0 + n) have their corners and attribute bytes as before.
  bool same(uint32_t t0, uint32_t n) const {
    if (!sameBytes(now + 3 * size_t(t0), before.triangles.data() + 3 * size_t(t0), 12 * size_t(n))) return false;
    for (const Column& c : columns)
      if (!sameBytes(c.now + size_t(t0) * c.stride, c.was + size_t(t0) * c.stride, c.stride * n)) return false;
    return true;
  }
  // Triangle t as it was: its id and corners into `ids` and `corners` (L's removed or changed
  // lists), its attribute bytes after those logged so far, its area into areaRemoved. False:
  // out of memory.
  bool logBefore(uint32_t t, Array<uint32_t>& ids, Array<uint32_t>& corners, RepairStepLog& L) const {
    if (!ids.push_back(t) || !append(corners, before.triangles.data() + 3 * size_t(t), 3)) return false;
    for (size_t a = 0; a < lay.names.size(); ++a)
      if (!append(L.attributeBefore[a], meshAttr(before, lay.names[a], t), lay.strides[a])) return false;
    L.areaRemoved += meshTriangleArea(before, t);
    return true;
  }
};

// What the step changed: `before` is the mesh as the step found it (em then held exactly
// it), em the mesh after the step (slots: survivors keep ids, removed ones dead, new ones
// appended), `maps` and `after` toMesh's compaction of em.
Status diffStepIn(const Mesh& before, const EditableMesh& em, const CompactMaps& maps, const Mesh& after,
                  RepairStepLog& L) {
  const uint32_t nTb = before.nTriangles(), nVb = before.nVertices();
  L.trianglesBefore = nTb;
  L.verticesBefore = nVb;
  L.trianglesAfter = after.nTriangles();
  L.verticesAfter = after.nVertices();
  const TriangleDiff d(before, em, L);
  const Array<float>& P = em.positions();
  auto oom = [] { return detail::oom(kRepairArrays); };
  // Triangles: removed first, then changed, attribute bytes in the same order.
  for (uint32_t t = 0; t < nTb; ++t)
    if (maps.triangles[t] == kInvalid && !d.logBefore(t, L.removedTriangles, L.removedCorners, L)) return oom();
  // A block of triangles whose corners and attribute bytes are all as before has no changed
  // triangle (a removed one has kInvalid corners): most blocks, skipped whole.
  constexpr uint32_t kBlock = 64;
  for (uint32_t t = 0; t < nTb; ++t) {
    if (t % kBlock == 0 && d.same(t, std::min(kBlock, nTb - t))) {
      t += std::min(kBlock, nTb - t) - 1;
      continue;
    }
    uint32_t w = maps.triangles[t];
    if (w == kInvalid || d.same(t, 1)) continue;
    if (!d.logBefore(t, L.changedTriangles, L.changedCorners, L)) return oom();
    L.areaAdded += meshTriangleArea(after, w);
  }
  for (uint32_t t = nTb; t < em.nTriangles(); ++t)
    if (maps.triangles[t] != kInvalid) {
      ++L.addedTriangles;
      L.areaAdded += meshTriangleArea(after, maps.triangles[t]);
    }
  // Likewise a block of vertices that all stay, at the same positions.
  auto sameVertices = [&](uint32_t v0, uint32_t n) {
    for (uint32_t i = 0; i < n; ++i)
      if (maps.vertices[v0 + i] == kInvalid) return false;
    return sameBytes(P.data() + 3 * size_t(v0), before.positions.data() + 3 * size_t(v0), 12 * size_t(n));
  };
  for (uint32_t v = 0; v < nVb; ++v) {
    if (v % kBlock == 0 && sameVertices(v, std::min(kBlock, nVb - v))) {
      v += std::min(kBlock, nVb - v) - 1;
      continue;
    }
    const float* b = before.positions.data() + 3 * size_t(v);
    if (maps.vertices[v] == kInvalid) {
      if (!L.removedVertices.push_back(v) || !append(L.removedPositions, b, 3)) return oom();
      continue;
    }
    const float* p = P.data() + 3 * size_t(v);
    if (!sameBytes(p, b, 12)) {
      if (!L.changedVertices.push_back(v) || !append(L.changedPositions, b, 3)) return oom();
      L.maxMoved = std::max(L.maxMoved, repair_detail::distance(p, b));
    }
  }
  for (uint32_t v = nVb; v < em.nVertices(); ++v)
    if (maps.vertices[v] != kInvalid) ++L.addedVertices;
  STLTOPO_TRY { L.solidsBefore = before.solids; }
  STLTOPO_CATCH { return oom(); }
  return Status{};
}

// diffStepIn, with its std containers (the attribute layout) failing as out of memory.
Status diffStep(const Mesh& before, const EditableMesh& em, const CompactMaps& maps, const Mesh& after,
                RepairStepLog& L) {
  STLTOPO_TRY { return diffStepIn(before, em, maps, after, L); }
  STLTOPO_CATCH { return detail::oom(kRepairArrays); }
}

// For a step that only reversed the triangles in `ids` (StepContext::reversed: em's slots
// are cur's ids, and nothing else changed), makes cur the mesh after the step in place and
// fills L (when not null) as diffStep would: what em.toMesh(after, nullptr, nullptr, false,
// false) and diffStep(cur, em, identity maps, after, L) give, with only the listed
// triangles compared instead of the whole mesh. `ids` is sorted here. Out of memory leaves
// cur as it was (L is filled before cur changes).
Status patchReversedIn(Mesh& cur, const EditableMesh& em, Array<uint32_t>& ids, RepairStepLog* L) {
  std::sort(ids.begin(), ids.end());
  const uint32_t nT = cur.nTriangles(), nV = cur.nVertices();
  if (em.nTriangles() != nT || em.nVertices() != nV)
    return Status::error(Code::Invalid, "repair: the reversed triangles do not fit the mesh");
  for (size_t i = 0; i < ids.size(); ++i)
    if (ids[i] >= nT || (i > 0 && ids[i] == ids[i - 1]))
      return Status::error(Code::Invalid, "repair: the reversed triangles do not fit the mesh");
  const Array<uint32_t>& T = em.triangles();
  // The normals as toMesh writes them (the one attribute a reversal changes).
  const AttributeView* normal = em.attribute(kAttrNormal);
  if (normal && (normal->type != ValueType::F32 || normal->components != 3)) normal = nullptr;
  const bool normals = normal && cur.normals.size() == size_t(nT) * 3;
  if (L) {
    L->trianglesBefore = L->trianglesAfter = nT;
    L->verticesBefore = L->verticesAfter = nV;
    const TriangleDiff d(cur, em, *L);
    for (uint32_t t : ids)
      if (!d.same(t, 1) && !d.logBefore(t, L->changedTriangles, L->changedCorners, *L))
        return detail::oom(kRepairArrays);
    L->solidsBefore = cur.solids;
  }
  // The mesh after the step (nothing allocates from here).
  auto patch = [&](uint32_t t) {
    std::memcpy(cur.triangles.data() + 3 * size_t(t), T.data() + 3 * size_t(t), 12);
    if (normals)
      std::memcpy(cur.normals.data() + 3 * size_t(t), static_cast<const float*>(normal->data) + 3 * size_t(t), 12);
  };
  if (L) {
    for (uint32_t t : L->changedTriangles) {
      patch(t);
      L->areaAdded += meshTriangleArea(cur, t);
    }
  } else {
    for (uint32_t t : ids) patch(t);
  }
  // As toMesh without the figures.
  cur.area = 0;
  cur.volume = 0;
  cur.normalMismatches = 0;
  return Status{};
}

// patchReversedIn, with its std containers failing as out of memory.
Status patchReversed(Mesh& cur, const EditableMesh& em, Array<uint32_t>& ids, RepairStepLog* L) {
  STLTOPO_TRY { return patchReversedIn(cur, em, ids, L); }
  STLTOPO_CATCH { return detail::oom(kRepairArrays); }
}

// The mesh before step L, from the mesh after it. InvalidArgument when they do not fit.
Status meshBeforeIn(const Mesh& after, const RepairStepLog& L, Mesh& b) {
  auto mismatch = [] { return Status::error(Code::InvalidArgument, "the change log does not fit this mesh"); };
  const uint32_t nTb = L.trianglesBefore, nVb = L.verticesBefore;
  if (after.nTriangles() != L.trianglesAfter || after.nVertices() != L.verticesAfter) return mismatch();
  if (L.removedTriangles.size() > nTb || L.removedVertices.size() > nVb ||
      nTb - L.removedTriangles.size() + L.addedTriangles != L.trianglesAfter ||
      nVb - L.removedVertices.size() + L.addedVertices != L.verticesAfter)
    return mismatch();
  b = Mesh{};
  b.format = after.format;
  b.colorConvention = after.colorConvention;
  STLTOPO_TRY {
    b.warnings = after.warnings;
    b.solids = L.solidsBefore;
  }
  STLTOPO_CATCH { return detail::oom(kRepairArrays); }
  Array<uint32_t> afterToBefore;
  if (!b.positions.resize(size_t(nVb) * 3) || !b.triangles.resize(size_t(nTb) * 3) ||
      !afterToBefore.assign(after.nVertices(), kInvalid))
    return detail::oom(kRepairArrays);
  size_t r = 0, c = 0;
  uint32_t k = 0;
  for (uint32_t v = 0; v < nVb; ++v) {
    float* p = b.positions.data() + 3 * size_t(v);
    if (r < L.removedVertices.size() && L.removedVertices[r] == v) {
      std::memcpy(p, L.removedPositions.data() + 3 * r, 12);
      ++r;
      continue;
    }
    afterToBefore[k] = v;
    if (c < L.changedVertices.size() && L.changedVertices[c] == v) {
      std::memcpy(p, L.changedPositions.data() + 3 * c, 12);
      ++c;
    } else {
      std::memcpy(p, after.positions.data() + 3 * size_t(k), 12);
    }
    ++k;
  }
  // The attributes are per triangle: a mesh without triangles (a step removed them all) has
  // none to tell its layout by, and takes the log's.
  AttrLayout lay = layoutOf(after);
  if (after.nTriangles() == 0 && !layoutOfNames(L.attributeNames, lay)) return mismatch();
  if (lay.names != L.attributeNames) return mismatch();
  const size_t nRemoved = L.removedTriangles.size();
  for (size_t a = 0; a < lay.names.size(); ++a) {
    if (L.attributeBefore[a].size() != (nRemoved + L.changedTriangles.size()) * lay.strides[a]) return mismatch();
    if (lay.names[a] == kAttrWord && !b.attributes.resize(nTb)) return detail::oom(kRepairArrays);
    if (lay.names[a] == kAttrColor && !b.colors.resize(size_t(nTb) * 3)) return detail::oom(kRepairArrays);
    if (lay.names[a] == kAttrColorValid && !b.colorValid.resize(nTb)) return detail::oom(kRepairArrays);
    if (lay.names[a] == kAttrNormal && !b.normals.resize(size_t(nTb) * 3)) return detail::oom(kRepairArrays);
  }
  r = c = 0;
  uint32_t j = 0;
  for (uint32_t t = 0; t < nTb; ++t) {
    uint32_t* out = b.triangles.data() + 3 * size_t(t);
    const uint8_t* saved[4] = {nullptr, nullptr, nullptr, nullptr};
    if (r < nRemoved && L.removedTriangles[r] == t) {
      std::memcpy(out, L.removedCorners.data() + 3 * r, 12);
      for (size_t a = 0; a < lay.names.size(); ++a) saved[a] = L.attributeBefore[a].data() + r * lay.strides[a];
      ++r;
    } else {
      if (j >= after.nTriangles()) return mismatch();
      if (c < L.changedTriangles.size() && L.changedTriangles[c] == t) {
        std::memcpy(out, L.changedCorners.data() + 3 * c, 12);
        for (size_t a = 0; a < lay.names.size(); ++a)
          saved[a] = L.attributeBefore[a].data() + (nRemoved + c) * lay.strides[a];
        ++c;
      } else {
        for (int q = 0; q < 3; ++q) {
          uint32_t w = after.triangles[3 * size_t(j) + q];
          if (afterToBefore[w] == kInvalid) return mismatch();
          out[q] = afterToBefore[w];
        }
        for (size_t a = 0; a < lay.names.size(); ++a) saved[a] = meshAttr(after, lay.names[a], j);
      }
      ++j;
    }
    for (int q = 0; q < 3; ++q)
      if (out[q] >= nVb) return mismatch();
    for (size_t a = 0; a < lay.names.size(); ++a) std::memcpy(meshAttrW(b, lay.names[a], t), saved[a], lay.strides[a]);
  }
  if (r != nRemoved || c != L.changedTriangles.size()) return mismatch();
  return Status{};
}

// meshBeforeIn, with its std containers (the attribute layout) failing as out of memory.
Status meshBefore(const Mesh& after, const RepairStepLog& L, Mesh& b) {
  STLTOPO_TRY { return meshBeforeIn(after, L, b); }
  STLTOPO_CATCH { return detail::oom(kRepairArrays); }
}

// Runs the chosen steps on em: the plan into `plan`, the change log into `log` (a plan
// that keeps its result makes both). For apply, `made` is the plan: its fingerprint is
// checked before anything changes, and the figures it knows are those of the same meshes
// (the input, and the result when the result has its predicted fingerprint). `inputKey`:
// meshKey of the input as run() finds it.
// `given`: the topology of em's compacted mesh (with triangleShell when o.intersections),
// when the caller built it already (planRepair, from a mesh that toMesh gives back as it
// is); run() takes it. `source`: the mesh em was just made from (init(source, *given)).
// `result`: for a run whose em is not used afterwards as it is (the plan's scratch copy):
// when the last step changed the mesh, em is left as the step's edits left it instead of
// being made again from the result, and the result goes to *result (RunResult). On an
// error, em is to be dropped.
Status run(EditableMesh& em, const RepairOptions& o, RepairPlan* plan, RepairLog* log, const RepairPlan* made = nullptr,
           uint64_t* inputKey = nullptr, Topology* given = nullptr, const Mesh* source = nullptr,
           RunResult* result = nullptr) {
  // Room for every step's entry first: a step's changes and its entry in the log go together
  // (an entry that could not be added after its step had changed the mesh would leave a
  // change the log cannot undo).
  {
    size_t nSteps = 0;
    for (int k = 0; k < kRepairStepCount; ++k) nSteps += (o.steps >> k) & 1u;
    STLTOPO_TRY {
      if (plan) plan->steps.reserve(nSteps);
      if (log) log->steps.reserve(log->steps.size() + nSteps);
    }
    STLTOPO_CATCH { return detail::oom(kRepairArrays); }
  }
  Mesh cur;
  Topology topo;
  // em as init() makes it from cur. A failed init leaves em empty: it is then made from cur
  // again (the memory the failed init freed is what it needs; if even that fails, the error
  // says so), so that em is as it was, compacted.
  auto reinit = [&]() -> Status {
    Status r = em.init(cur, topo);
    if (r.ok()) return r;
    Status back = em.init(cur, topo);
    return back.ok() ? r : back;
  };
  // With the intersection pass, the topologies the figures are computed on carry
  // triangleShell (figuresOf): this one, and the rebuild after the last step.
  Status s = given ? em.toMesh(cur, nullptr, nullptr) : em.toMesh(cur, &topo, nullptr, o.intersections);
  if (!s.ok()) return s;
  if (given) topo = std::move(*given);
  // The fingerprint's state after cur's positions (fingerprintOf), for a step that keeps them.
  uint64_t curPositionsState = 0;
  const uint64_t fingerprint = fingerprintOf(cur, &curPositionsState);
  if (inputKey) *inputKey = meshKey(cur, fingerprint);
  if (made && fingerprint != made->fingerprint)
    return Status::error(Code::InvalidArgument, "the plan was made for another mesh (its fingerprint differs)");
  // Compacted: the steps see dense ids, and the state is init()'s of `cur`, which is what a
  // failed step restores and what undo rebuilds.
  // (em holds that state already when it was just made from a mesh with cur's content.)
  if (!(given && source && sameContent(cur, *source))) {
    s = reinit();
    if (!s.ok()) return s;
  }
  // The fingerprint of cur, for the log (a plan needs only the first).
  uint64_t curFingerprint = fingerprint;
  // Each changing step rebuilds into these (toMesh keeps their memory), then swaps them with cur.
  Mesh next;
  Topology nextTopo;
  CompactMaps maps;
  RepairFigures before;
  // The pairs of the mesh as it is, carried through the steps for the plan's last figures.
  KnownPairs known;
  // The triangle checks of `cur`, when the figures of cur made them (for its report).
  TriangleChecks curChecks;
  bool curChecksKnown = false;
  // cur's report into `out` (a std::string: out of memory as a status).
  auto curReport = [&](std::string& out) -> Status {
    return reportOf(cur, topo, curChecksKnown ? &curChecks : nullptr, o.threads, out);
  };
  // After a step that only reversed triangles (orient, not last), em keeps its edits
  // instead of being made again from the rebuilt mesh: `cur` is then toMesh's plain mesh of
  // em, but `topo` is the one before the step (stale) and em is not init()'s state of cur
  // (its half-edge ids are the edits'; its triangle and vertex ids, loops and counts are a
  // fresh build's). fill-holes reads only em and runs so; anything else that reads topo or
  // needs init()'s state refreshes first (one rebuild, as the runner would have made).
  bool stale = false;
  // (A failed toMesh leaves em as it was, and a failed init is undone by reinit: the mesh
  // stays as the log says.)
  auto refresh = [&]() -> Status {
    if (!stale) return Status{};
    curChecksKnown = false;
    Status r = em.toMesh(cur, &topo, nullptr, o.intersections);
    if (r.ok()) r = reinit();
    if (r.ok()) stale = false;
    return r;
  };
  // The identity maps of a step that kept every slot (reversal only), for diffStep.
  auto identity = [&](uint32_t nt, uint32_t nv) -> Status {
    if (!maps.triangles.resize(nt) || !maps.vertices.resize(nv)) return detail::oom(kRepairArrays);
    maps.halfedges = Array<uint32_t>{};
    for (uint32_t t = 0; t < nt; ++t) maps.triangles[t] = t;
    for (uint32_t v = 0; v < nv; ++v) maps.vertices[v] = v;
    return Status{};
  };
  if (made && made->beforeKnown) {
    before = made->before;  // the same mesh (same fingerprint): the same figures
  } else {
    s = figuresOf(cur, topo, o, true, before, plan && o.intersections ? &known.found : nullptr, nullptr, &curChecks);
    if (!s.ok()) return s;
    curChecksKnown = true;
    known.valid = plan && o.intersections;
  }
  RepairFigures figures = before;  // of `cur`
  bool changed = false;
  if (plan) {
    plan->before = before;
    plan->beforeKnown = true;
    plan->fingerprint = fingerprint;
  }
  if (log) {
    log->before = before;
    log->fingerprintBefore = fingerprint;
    // what em.infoJson gives: cur is its toMesh
    s = curReport(log->beforeReport);
    if (!s.ok()) return s;
  }
  int lastStep = -1;
  for (int k = 0; k < kRepairStepCount; ++k)
    if (o.steps & (1u << k)) lastStep = k;
  for (int k = 0; k < kRepairStepCount; ++k) {
    if (!(o.steps & (1u << k))) continue;
    RepairStepPlan sp;
    sp.kind = RepairStepKind(k);
    if (sp.kind != RepairStepKind::FillHoles) s = refresh();
    if (!s.ok()) return s;
    repair_detail::StepContext ctx{em, o, sp, stale ? nullptr : &cur, stale ? nullptr : &topo, &next, &nextTopo, &maps};
    ctx.checks = curChecksKnown ? &curChecks : nullptr;
    if (o.onStep) o.onStep(o.user, sp.kind, false);
    s = runStep(sp.kind, ctx);
    RepairStepLog L;
    L.kind = sp.kind;
    L.trianglesBefore = L.trianglesAfter = cur.nTriangles();
    L.verticesBefore = L.verticesAfter = cur.nVertices();
    L.fingerprintAfter = curFingerprint;
    if (s.ok()) {
      L.itemsDone = sp.nDone();
      L.itemsSkipped = sp.nSkipped();
      for (const RepairItem& it : sp.items)
        if (!it.skipped) L.maxMoved = std::max(L.maxMoved, it.moved);
    }
    // Orient, not the last step, that kept its edits unbuilt (its shells needed no rebuild)
    // and every slot: the mesh is toMesh's plain one, em stays as the edits left it (see
    // `stale`), and the figures the plan needs of it are the editor's counts and the
    // triangle checks' counts, which reversing triangles keeps (zero-area and duplicate
    // triangles do not depend on the orientation).
    const bool reversedOnly = s.ok() && L.itemsDone > 0 && sp.kind == RepairStepKind::Orient && k != lastStep &&
                              !ctx.rebuilt && em.nTriangles() == cur.nTriangles() &&
                              em.nVertices() == cur.nVertices() && em.nLiveTriangles() == cur.nTriangles() &&
                              em.nLiveVertices() == cur.nVertices();
    if (reversedOnly) {
      // Without the figures (area, volume, normal mismatches): a stale cur is refreshed
      // (toMesh with them) before anything reports it or computes figures of it. When the
      // step listed its reversals, cur is patched at them (the same mesh and log, without a
      // copy of the mesh and a comparison of all of it).
      if (ctx.reversedListed) {
        s = patchReversed(cur, em, ctx.reversed, log ? &L : nullptr);
      } else {
        s = em.toMesh(next, nullptr, nullptr, false, false);
        if (s.ok() && log) s = identity(cur.nTriangles(), cur.nVertices());
        if (s.ok() && log) s = diffStep(cur, em, maps, next, L);
        if (s.ok()) std::swap(cur, next);
      }
      if (s.ok()) {
        stale = true;
        curChecksKnown = false;
        // Reversing triangles keeps the counts and positions: the hash resumes after them.
        if (log)
          curFingerprint = L.changedVertices.empty() && L.removedVertices.empty() && L.addedVertices == 0
                               ? fingerprintAfterPositions(curPositionsState, cur)
                               : fingerprintOf(cur, &curPositionsState);
        L.fingerprintAfter = curFingerprint;
        changed = true;
        if (plan) {
          // (The carried pairs keep their ids: every triangle keeps its slot.)
          RepairFigures f;
          f.stats = em.stats();
          f.zeroAreaTriangles = figures.zeroAreaTriangles;
          f.duplicateTriangles = figures.duplicateTriangles;
          figures = f;
        }
      }
    } else if (s.ok() && L.itemsDone > 0) {
      // A step that did no item changed nothing (a skipped item changes nothing): no rebuild.
      const bool shells = o.intersections && k == lastStep;
      if (!ctx.rebuilt)
        s = em.toMesh(next, &nextTopo, &maps, shells);
      else if (!shells)
        nextTopo.triangleShell = Array<uint32_t>{};  // the step made this rebuild with it: as toMesh without it
      if (s.ok() && log) s = diffStep(cur, em, maps, next, L);
      // The last step's result is made into em only when em is used afterwards.
      const bool keepEdits = result && k == lastStep;
      if (s.ok() && !keepEdits) s = em.init(next, nextTopo);
      if (s.ok()) {
        if (result) result->pending = keepEdits;
        // The state before the step becomes the memory of the next step's rebuild.
        std::swap(cur, next);
        std::swap(topo, nextTopo);
        stale = false;
        curChecksKnown = false;
        if (log) curFingerprint = fingerprintOf(cur, &curPositionsState);
        L.fingerprintAfter = curFingerprint;
        changed = true;
        // The figures after each step are the plan's; the log needs only the last ones.
        if (plan) s = known.follow(sp.kind, maps, cur.nTriangles());
        if (s.ok() && plan) {
          s = figuresOf(cur, topo, o, k == lastStep, figures, nullptr, &known, &curChecks);
          curChecksKnown = s.ok();
        }
      }
    } else if (s.ok() && plan && k == lastStep && figures.selfIntersections == kInvalid && o.intersections) {
      s = refresh();
      if (s.ok()) s = figuresOf(cur, topo, o, true, figures, nullptr, &known, &curChecks);
      curChecksKnown = s.ok();
    }
    if (!s.ok()) {
      // Back to the mesh as the step found it (init of a mesh already held cannot need more
      // memory than it had; if even that fails, the error says so). With a stale topology,
      // init builds cur's.
      Status r = stale ? em.init(cur) : em.init(cur, topo);
      if (log) {
        L.status = s;
        L.trianglesAfter = L.trianglesBefore;
        L.verticesAfter = L.verticesBefore;
        L.fingerprintAfter = fingerprintOf(cur);
        STLTOPO_TRY { log->steps.push_back(std::move(L)); }
        STLTOPO_CATCH {}
      }
      return r.ok() ? s : r;
    }
    sp.after = figures;
    if (o.onStep) o.onStep(o.user, sp.kind, true);
    STLTOPO_TRY {
      if (plan) plan->steps.push_back(std::move(sp));
      if (log) log->steps.push_back(std::move(L));
    }
    STLTOPO_CATCH { return detail::oom(kRepairArrays); }
  }
  // The result as init() makes it, with its topology (for its report and figures).
  s = refresh();
  if (!s.ok()) return s;
  RepairFigures after = before;
  if (plan && lastStep >= 0) {
    after = plan->steps.back().after;
  } else if (log && changed) {
    // A fresh build of the result. The intersection pass's figures are the plan's when the
    // result is the mesh the plan predicted (same fingerprint, same pass options).
    const bool predicted = made && made->afterKnown && curFingerprint == made->fingerprintAfter &&
                           made->after.selfIntersections != kInvalid;
    s = figuresOf(cur, topo, o, !predicted, after, nullptr, nullptr, &curChecks);
    if (!s.ok()) return s;
    curChecksKnown = true;
    if (predicted && o.intersections) {
      after.selfIntersections = made->after.selfIntersections;
      after.solid = made->after.solid;
    }
  }
  if (plan) {
    plan->afterKnown = true;
    plan->fingerprintAfter = !changed ? fingerprint : log ? curFingerprint : fingerprintOf(cur);
    plan->after = after;
    s = curReport(plan->afterReport);
    if (!s.ok()) return s;
    if (o.intersections && after.selfIntersections != kInvalid && after.selfIntersections > 0) {
      STLTOPO_TRY {
        plan->remaining = repair_detail::text(
            "%u self-intersecting triangle pairs remain: repair does not change them. Where closed shells overlap, "
            "merge them with a boolean union (for example manifold-3d's Manifold.union).",
            after.selfIntersections);
      }
      STLTOPO_CATCH { return detail::oom(kRepairArrays); }
    }
  }
  if (log) {
    log->after = after;
    log->fingerprintAfter = curFingerprint;
    STLTOPO_TRY {
      if (!changed)
        log->afterReport = log->beforeReport;
      else if (plan)
        log->afterReport = plan->afterReport;
      else
        s = curReport(log->afterReport);
    }
    STLTOPO_CATCH { s = detail::oom(kRepairArrays); }
    if (!s.ok()) return s;
  }
  if (result && result->pending) {
    result->mesh = std::move(cur);
    result->topo = std::move(topo);
  }
  return Status{};
}

void figuresJson(detail::Json& j, const RepairFigures& f) {
  const EditStats& s = f.stats;
  j.open('{');
  j.key("triangles");
  j.u(s.triangles);
  j.key("vertices");
  j.u(s.vertices);
  j.key("degenerateTriangles");
  j.u(s.degenerate);
  j.key("zeroAreaTriangles");
  j.u(f.zeroAreaTriangles);
  j.key("duplicateTriangles");
  j.u(f.duplicateTriangles);
#define STLTOPO_COUNT_KEY(count, name, doc) \
  j.key(#name);                             \
  j.u(s.name);
  STLTOPO_COUNTS(STLTOPO_COUNT_KEY)
#undef STLTOPO_COUNT_KEY
  j.key("eulerCharacteristic");
  j.i(s.eulerCharacteristic);
  j.key("watertight");
  j.b(s.watertight);
  j.key("manifold");
  j.b(s.manifold);
  j.key("selfIntersections");
  if (f.selfIntersections == kInvalid)
    j.null();
  else
    j.u(f.selfIntersections);
  j.key("solid");
  if (f.selfIntersections == kInvalid)
    j.null();
  else
    j.b(f.solid);
  j.close('}');
}

template <class C>
void idList(detail::Json& j, const char* k, const C& ids) {
  j.key(k);
  j.open('[');
  for (uint32_t x : ids) {
    j.sep();
    j.u(x);
  }
  j.close(']');
}

}  // namespace

const char* repairStepName(RepairStepKind k) { return int(k) < kRepairStepCount ? kStepNames[int(k)] : "unknown"; }

bool repairStepFromName(const std::string& name, RepairStepKind& out) {
  for (int k = 0; k < kRepairStepCount; ++k)
    if (name == kStepNames[k]) {
      out = RepairStepKind(k);
      return true;
    }
  return false;
}

uint32_t RepairStepPlan::nDone() const {
  uint32_t n = 0;
  for (const RepairItem& i : items) n += !i.skipped;
  return n;
}
uint32_t RepairStepPlan::nSkipped() const { return uint32_t(items.size()) - nDone(); }

uint64_t repairFingerprint(const EditableMesh& em) {
  Mesh m;
  if (!em.toMesh(m, nullptr, nullptr, false, false).ok()) return 0;  // (the arrays only)
  return fingerprintOf(m);
}

Status planRepair(const Mesh& mesh, const RepairOptions& options, RepairPlan& out) {
  return planRepair(mesh, nullptr, options, out);
}

namespace {
// planRepair of `mesh`: with `fresh`, a topology of it as buildTopology gives it (prevAndFace,
// and triangleShell when options.intersections), which the run may take; else with `topo`
// (the caller's, for the scratch copy only), else with a topology built here.
Status planWith(const Mesh& mesh, const Topology* topo, Topology* fresh, const RepairOptions& options,
                RepairPlan& out) {
  out = RepairPlan{};
  Status s = checkOptions(options);
  if (!s.ok()) return s;
  STLTOPO_TRY { out.options = options; }
  STLTOPO_CATCH { return detail::oom(kRepairArrays); }
  EditableMesh scratch;
  // Without the caller's topology, a fresh one serves both the scratch copy and the run:
  // when every vertex is used, toMesh() gives the mesh back as it is, and its topology is
  // this one (the editable mesh's contract), so run() does not build it again.
  Topology own;
  Topology& built = fresh ? *fresh : own;
  bool reuse = false;
  if (topo && !fresh) {
    s = scratch.init(mesh, *topo);
  } else {
    if (!fresh) {
      TopologyOptions to;
      to.threads = options.threads;
      to.prevAndFace = true;
      to.triangleShell = options.intersections;
      s = buildTopology(mesh, built, to);
    }
    if (s.ok()) s = scratch.init(mesh, built);
    reuse = s.ok() && built.nUsedVertices == mesh.nVertices();
  }
  if (!s.ok()) return s;
  std::shared_ptr<RepairResult> kept;
  if (options.keepResult) {
    STLTOPO_TRY {
      kept = std::make_shared<RepairResult>();
      kept->options = options;
    }
    STLTOPO_CATCH { return detail::oom(kRepairArrays); }
    kept->options.onStep = nullptr;
    kept->options.user = nullptr;
  }
  // The scratch copy is dropped or kept as the result: the result need not be made into it.
  RunResult dropped;
  s = run(scratch, options, &out, kept ? &kept->log : nullptr, nullptr, kept ? &kept->inputKey : nullptr,
          reuse ? &built : nullptr, reuse ? &mesh : nullptr, kept ? &kept->made : &dropped);
  if (!s.ok()) {
    RepairPlan empty;
    out = std::move(empty);
    return s;
  }
  if (kept) {
    if (!kept->made.pending) kept->em = std::move(scratch);
    out.result = std::move(kept);
  }
  return s;
}
}  // namespace

Status planRepair(const Mesh& mesh, const Topology* topo, const RepairOptions& options, RepairPlan& out) {
  return planWith(mesh, topo, nullptr, options, out);
}

Status planRepair(const EditableMesh& em, const RepairOptions& options, RepairPlan& out) {
  out = RepairPlan{};
  // The compacted mesh with its topology (a fresh build's, triangleShell included when the
  // pass runs): the scratch copy is made from them, and the run takes the topology.
  Mesh m;
  Topology t;
  Status s = em.toMesh(m, &t, nullptr, options.intersections);
  if (!s.ok()) return s;
  return planWith(m, nullptr, &t, options, out);
}

namespace {
// Whether r (held locked) may still be taken for `plan`: not taken yet, and made with the
// plan's options for the plan's input.
bool resultFits(const RepairResult& r, const RepairPlan& plan) {
  return !r.taken && sameRepair(r.options, plan.options) && r.log.fingerprintBefore == plan.fingerprint;
}
// onStep of the plan for each step of `log`, as a run would call it.
void replaySteps(const RepairPlan& plan, const RepairLog& log) {
  if (plan.options.onStep)
    for (const RepairStepLog& L : log.steps) {
      plan.options.onStep(plan.options.user, L.kind, false);
      plan.options.onStep(plan.options.user, L.kind, true);
    }
}
// em and log take r's mesh and log (r held locked); onStep is called for each step. A
// pending result is made into an EditableMesh first: when that fails (out of memory),
// nothing is taken and nothing changes.
Status take(RepairResult& r, const RepairPlan& plan, EditableMesh& em, RepairLog& log) {
  if (r.made.pending) {
    EditableMesh made;
    Status s = made.init(r.made.mesh, r.made.topo);
    if (!s.ok()) return s;
    em = std::move(made);
    r.made = RunResult{};
  } else {
    em = std::move(r.em);
  }
  log = std::move(r.log);
  r.taken = true;
  replaySteps(plan, log);
  return Status{};
}
// The same for a caller that wants the repaired mesh as a Mesh (what toMesh gives of the
// EditableMesh take() makes: the result is compacted, so it is that mesh as it is).
Status take(RepairResult& r, const RepairPlan& plan, Mesh& out, RepairLog& log) {
  if (r.made.pending) {
    out = std::move(r.made.mesh);
    r.made = RunResult{};
  } else {
    Status s = r.em.toMesh(out, nullptr, nullptr);
    if (!s.ok()) return s;
    r.em = EditableMesh{};
  }
  log = std::move(r.log);
  r.taken = true;
  replaySteps(plan, log);
  return Status{};
}

// applyRepair with the plan's result (RepairPlan::result): em takes the repaired mesh and
// `log` the change log when em holds the plan's input and the options are the result's.
// `taken` says whether it did; nothing changes otherwise.
Status takeResult(EditableMesh& em, const RepairPlan& plan, RepairLog& log, bool& taken) {
  taken = false;
  RepairResult& r = *plan.result;
  std::lock_guard<std::mutex> hold(r.lock);
  if (!resultFits(r, plan)) return Status{};
  Mesh m;
  Status s = em.toMesh(m, nullptr, nullptr, false, false);  // the key needs no figures
  if (!s.ok()) return s;
  if (meshKey(m, fingerprintOf(m)) != r.inputKey) return Status{};
  s = take(r, plan, em, log);
  taken = s.ok();
  return s;
}
}  // namespace

bool RepairPlan::resultTaken() const {
  if (!result) return false;
  std::lock_guard<std::mutex> hold(result->lock);
  return result->taken;
}

Status applyRepair(EditableMesh& em, const RepairPlan& plan, RepairLog& log) {
  log = RepairLog{};
  Status s = checkOptions(plan.options);
  if (!s.ok()) return s;
  s = checkAttributes(em);
  if (!s.ok()) return s;
  if (plan.result) {
    bool taken = false;
    s = takeResult(em, plan, log, taken);
    if (!s.ok() || taken) return s;
  }
  return run(em, plan.options, nullptr, &log, &plan);
}

namespace {
// applyRepair(mesh, plan, ...)'s check that it may take the plan's result: the plan's input
// is `mesh` as init() and toMesh() give it back (every vertex used, the exact weld): then an
// EditableMesh made from mesh would hold it, and takeResult would take the result. Its key
// says so without making that mesh. (With a tolerance weld the EditableMesh may hold
// another mesh: applyRepair builds it, and runs as it finds it.) `act(r)` takes it (r held
// locked); `taken` says whether it ran.
template <class Act>
Status takeFor(const Mesh& mesh, const RepairPlan& plan, const TopologyOptions& topologyOptions, bool& taken,
               Act&& act) {
  taken = false;
  if (!plan.result || topologyOptions.tolerance > 0) return Status{};
  RepairResult& r = *plan.result;
  std::lock_guard<std::mutex> hold(r.lock);
  if (!resultFits(r, plan) || meshKey(mesh, fingerprintOf(mesh)) != r.inputKey) return Status{};
  taken = true;
  return act(r);
}
// applyRepair(mesh, ...) without the plan's result: em.init(mesh) and the steps.
Status applyBuilt(const Mesh& mesh, const RepairPlan& plan, EditableMesh& em, RepairLog& log,
                  const TopologyOptions& topologyOptions) {
  EditableMesh built;
  Status s = built.init(mesh, topologyOptions);
  if (!s.ok()) return s;
  s = applyRepair(built, plan, log);
  em = std::move(built);
  return s;
}
}  // namespace

Status applyRepair(const Mesh& mesh, const RepairPlan& plan, EditableMesh& em, RepairLog& log,
                   const TopologyOptions& topologyOptions) {
  log = RepairLog{};
  Status s = checkOptions(plan.options);
  if (!s.ok()) return s;
  bool taken = false;
  s = takeFor(mesh, plan, topologyOptions, taken, [&](RepairResult& r) { return take(r, plan, em, log); });
  if (taken) return s;
  return applyBuilt(mesh, plan, em, log, topologyOptions);
}

Status applyRepair(const Mesh& mesh, const RepairPlan& plan, Mesh& out, RepairLog& log,
                   const TopologyOptions& topologyOptions) {
  log = RepairLog{};
  Status s = checkOptions(plan.options);
  if (!s.ok()) return s;
  Mesh result;
  bool taken = false;
  s = takeFor(mesh, plan, topologyOptions, taken, [&](RepairResult& r) { return take(r, plan, result, log); });
  if (!taken) {
    EditableMesh em;
    s = applyBuilt(mesh, plan, em, log, topologyOptions);
    if (s.ok()) s = em.toMesh(result, nullptr, nullptr);
  }
  if (s.ok()) out = std::move(result);
  return s;
}

Status undoRepairStep(EditableMesh& em, RepairLog& log) {
  if (log.steps.empty()) return Status::error(Code::InvalidArgument, "the change log has no step to undo");
  const RepairStepLog& L = log.steps.back();
  Mesh after;  // (its arrays: the mesh before is made from them and the log, and em from that)
  Status s = em.toMesh(after, nullptr, nullptr, false, false);
  if (!s.ok()) return s;
  if (fingerprintOf(after) != L.fingerprintAfter)
    return Status::error(Code::InvalidArgument, "the mesh is not in the state the step's log left (it changed since)");
  s = checkAttributes(em);
  if (!s.ok()) return s;
  Mesh b;
  if (L.status.ok() && L.itemsDone > 0) {
    s = meshBefore(after, L, b);
    if (!s.ok()) return s;
  } else {
    // A failed step left the mesh as before it, and a step that did no item changed
    // nothing: nothing to undo but the entry.
    log.steps.pop_back();
    return Status{};
  }
  const uint64_t want =
      log.steps.size() >= 2 ? log.steps[log.steps.size() - 2].fingerprintAfter : log.fingerprintBefore;
  if (fingerprintOf(b) != want) return Status::error(Code::InvalidArgument, "the change log does not fit this mesh");
  s = em.init(b);
  if (!s.ok()) {
    // Back to the state it had (the same size as before the failed init).
    Status r = em.init(after);
    return r.ok() ? s : r;
  }
  log.steps.pop_back();
  return Status{};
}

Status undoRepair(EditableMesh& em, RepairLog& log) {
  while (!log.steps.empty()) {
    Status s = undoRepairStep(em, log);
    if (!s.ok()) return s;
  }
  return Status{};
}

std::string repairPlanJson(const RepairPlan& plan) {
  detail::Json j;
  j.open('{');
  j.key("fingerprint");
  j.str(detail::format("%016llx", (unsigned long long)plan.fingerprint));
  j.key("before");
  figuresJson(j, plan.before);
  j.key("steps");
  j.open('[');
  for (const RepairStepPlan& sp : plan.steps) {
    j.sep();
    j.open('{');
    j.key("step");
    j.str(repairStepName(sp.kind));
    j.key("note");
    j.str(sp.note);
    j.key("done");
    j.u(sp.nDone());
    j.key("skipped");
    j.u(sp.nSkipped());
    j.key("items");
    j.open('[');
    for (const RepairItem& it : sp.items) {
      j.sep();
      j.open('{');
      j.key("action");
      j.str(it.action);
      j.key("skipped");
      j.b(it.skipped);
      if (it.skipped) {
        j.key("reason");
        j.str(it.reason);
      }
      idList(j, "triangles", it.triangles);
      idList(j, "vertices", it.vertices);
      idList(j, "loops", it.loops);
      j.key("bbox");
      j.bbox(it.bbox, it.bbox + 3);
      j.key("moved");
      j.f64(it.moved);
      j.close('}');
    }
    j.close(']');
    j.key("after");
    figuresJson(j, sp.after);
    j.close('}');
  }
  j.close(']');
  j.key("after");
  figuresJson(j, plan.steps.empty() ? plan.before : plan.steps.back().after);
  j.key("remaining");
  j.str(plan.remaining);
  j.close('}');
  return std::move(j.s);
}

std::string repairLogJson(const RepairLog& log) {
  detail::Json j;
  j.open('{');
  j.key("before");
  figuresJson(j, log.before);
  j.key("after");
  figuresJson(j, log.after);
  j.key("steps");
  j.open('[');
  for (const RepairStepLog& L : log.steps) {
    j.sep();
    j.open('{');
    j.key("step");
    j.str(repairStepName(L.kind));
    j.key("status");
    j.str(L.status.ok() ? "ok" : codeName(L.status.code));
    if (!L.status.ok()) {
      j.key("message");
      j.str(L.status.message);
    }
    j.key("done");
    j.u(L.itemsDone);
    j.key("skipped");
    j.u(L.itemsSkipped);
    idList(j, "removedTriangles", L.removedTriangles);
    idList(j, "changedTriangles", L.changedTriangles);
    j.key("addedTriangles");
    j.u(L.addedTriangles);
    idList(j, "removedVertices", L.removedVertices);
    idList(j, "changedVertices", L.changedVertices);
    j.key("addedVertices");
    j.u(L.addedVertices);
    j.key("maxMoved");
    j.f64(L.maxMoved);
    j.key("areaRemoved");
    j.f64(L.areaRemoved);
    j.key("areaAdded");
    j.f64(L.areaAdded);
    j.close('}');
  }
  j.close(']');
  j.key("beforeReport");
  j.s += log.beforeReport.empty() ? "null" : log.beforeReport;
  j.first = false;
  j.key("afterReport");
  j.s += log.afterReport.empty() ? "null" : log.afterReport;
  j.first = false;
  j.close('}');
  return std::move(j.s);
}

}  // namespace stltopo
