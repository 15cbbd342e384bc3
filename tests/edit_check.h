// Test helper for the EditableMesh: compares an edited mesh with a fresh buildTopology of
// its compacted form, array by array. Shared by test_edit.cpp and the fuzz target.
#pragma once

#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "stl_gen.h"
#include "stltopo/edit.h"

namespace editcheck {

// "" when the edited mesh is consistent: its own validate() holds, toMesh()'s topology
// equals buildTopology(toMesh()'s mesh) in every array and count, and stats() and loops()
// agree with that build. Else the first difference.
inline std::string differenceFromRebuild(stltopo::EditableMesh& em) {
  using namespace stltopo;
  Status s = em.validate();
  if (!s.ok()) return "validate: " + s.message;
  Mesh m;
  Topology t;
  s = em.toMesh(m, &t);
  if (!s.ok()) return "toMesh: " + s.message;
  Topology f;
  s = buildTopology(m, f);
  if (!s.ok()) return "buildTopology: " + s.message;
#define EDITCHECK_SAME(x) \
  if (!gen::sameArray(t.x, f.x)) return "array " #x " differs from a fresh build";
  EDITCHECK_SAME(next)
  EDITCHECK_SAME(prev)
  EDITCHECK_SAME(vert) EDITCHECK_SAME(face) EDITCHECK_SAME(pairKind) EDITCHECK_SAME(triangleHalfedge)
      EDITCHECK_SAME(vertexHalfedge) EDITCHECK_SAME(vertexWeld) EDITCHECK_SAME(loopHalfedge) EDITCHECK_SAME(loopOffsets)
          EDITCHECK_SAME(loopHalfedges) EDITCHECK_SAME(loopIsSeam) EDITCHECK_SAME(loopPerimeter) EDITCHECK_SAME(
              triangleDegenerate) EDITCHECK_SAME(vertexNonManifold)
#undef EDITCHECK_SAME
#define EDITCHECK_COUNT(x) \
  if (t.x != f.x)          \
    return "count " #x " differs from a fresh build: " + std::to_string(t.x) + " vs " + std::to_string(f.x);
#define EDITCHECK_LISTED(count, name, doc) EDITCHECK_COUNT(count)
              EDITCHECK_COUNT(nTriangles) EDITCHECK_COUNT(nVertices) EDITCHECK_COUNT(nWeldedVertices)
                  STLTOPO_COUNTS(EDITCHECK_LISTED) STLTOPO_OTHER_COUNTS(EDITCHECK_LISTED)
#undef EDITCHECK_LISTED
#undef EDITCHECK_COUNT
                      if (infoJson("f", m, &t) != infoJson("f", m, &f)) return "infoJson differs from a fresh build";
  if (em.infoJson("f") != infoJson("f", m, &f)) return "EditableMesh::infoJson differs from a fresh build";
  const EditStats& st = em.stats();
  if (st.triangles != f.nTriangles || st.vertices != f.nVertices || st.eulerCharacteristic != f.eulerCharacteristic() ||
      st.watertight != f.watertight() || st.manifold != f.manifold())
    return "stats() differ from a fresh build";
#define EDITCHECK_STAT(count, name, doc) \
  if (st.name != f.count) return "stats()." #name " differs from a fresh build";
  STLTOPO_COUNTS(EDITCHECK_STAT)
  STLTOPO_OTHER_COUNTS(EDITCHECK_STAT)
#undef EDITCHECK_STAT
  const EditLoops& l = em.loops();
  if (!gen::sameArray(l.loopOffsets, f.loopOffsets) || !gen::sameArray(l.loopIsSeam, f.loopIsSeam) ||
      !gen::sameArray(l.loopPerimeter, f.loopPerimeter))
    return "loops() differ from a fresh build";
  for (uint32_t h = 0; h < l.nLoops(); ++h)
    for (uint32_t i = l.loopOffsets[h]; i < l.loopOffsets[h + 1]; ++i) {
      uint32_t e = l.loopHalfedges[i];
      if (em.face(e) != em.nTriangles() + h) return "face of a loop half-edge is not its loop";
    }
  // toMesh with triangleShell: the shells as TopologyOptions::triangleShell numbers them.
  Mesh ms;
  Topology ts, fs;
  s = em.toMesh(ms, &ts, nullptr, true);
  if (!s.ok()) return "toMesh with triangleShell: " + s.message;
  TopologyOptions so;
  so.triangleShell = true;
  s = buildTopology(m, fs, so);
  if (!s.ok()) return "buildTopology with triangleShell: " + s.message;
  if (!gen::sameArray(ts.triangleShell, fs.triangleShell) || ts.triangleShell.size() != m.nTriangles())
    return "triangleShell differs from a fresh build";
  if (ts.nShells != fs.nShells || ts.nShells != t.nShells) return "nShells with triangleShell differs from a fresh build";
  if (!gen::sameArray(ts.next, t.next) || !gen::sameArray(ts.face, t.face)) return "toMesh with triangleShell: arrays differ";
  return "";
}

// A copy of every array and attribute and the stats, to show that a refused edit
// changed nothing.
struct Snapshot {
  std::vector<std::vector<uint8_t>> arrays;
  template <class T>
  void add(const stltopo::Array<T>& a) {
    const uint8_t* p = reinterpret_cast<const uint8_t*>(a.data());
    arrays.emplace_back(p, p + a.size() * sizeof(T));
  }
  explicit Snapshot(stltopo::EditableMesh& em) {
    const stltopo::EditStats& st = em.stats();  // first: reading the stats numbers the loops
    add(em.positions());
    add(em.triangles());
    add(em.next());
    add(em.prev());
    add(em.vert());
    add(em.faceWords());
    add(em.pairKind());
    add(em.triangleHalfedge());
    add(em.vertexHalfedge());
    for (const std::string& n : em.attributeNames()) {
      const stltopo::AttributeView* v = em.attribute(n);
      const uint8_t* p = static_cast<const uint8_t*>(v->data);
      arrays.emplace_back(p, p + v->count * v->components * stltopo::valueTypeSize(v->type));
    }
    const int64_t counts[] = {st.triangles,
                              st.vertices,
                              st.degenerate,
                              st.edges,
                              st.boundaryEdges,
                              st.nonManifoldEdges,
                              st.inconsistentEdges,
                              st.nonManifoldVertices,
                              st.usedVertices,
                              st.holes,
                              st.seams,
                              st.shells,
                              st.eulerCharacteristic,
                              st.watertight,
                              st.manifold};
    const uint8_t* p = reinterpret_cast<const uint8_t*>(counts);
    arrays.emplace_back(p, p + sizeof counts);
  }
  bool operator==(const Snapshot& o) const { return arrays == o.arrays; }
};

// Random edits driven by a chooser: pick(n) returns a number in [0, n) (from a PRNG in the
// tests, from the input bytes in the fuzz target).
template <class Pick>
class RandomEditor {
 public:
  RandomEditor(stltopo::EditableMesh& em, Pick& pick) : em_(em), pick_(pick) {}

  // One edit; "" when it (or its refusal) checks out, else what went wrong. `what` says
  // which edit it was.
  std::string step(std::string& what, bool checkEachEdit = true) {
    using namespace stltopo;
    const uint32_t op = pick_(20);
    const EditStats before = em_.stats();
    Status s;
    std::vector<uint8_t> dummy;
    Snapshot* snap = nullptr;
    Snapshot snapshot = checkEachEdit ? Snapshot(em_) : emptySnapshot();
    if (checkEachEdit) snap = &snapshot;
    char buf[160];
    switch (op) {
      case 0:
      case 1: {
        uint32_t t = liveTriangle();
        if (t == kInvalid) {
          what = "remove (no triangle)";
          return "";
        }
        std::snprintf(buf, sizeof buf, "removeTriangle(%u)", t);
        s = em_.removeTriangle(t);
        break;
      }
      case 2:
      case 3: {  // a triangle that closes an ear of a boundary loop
        uint32_t b = boundaryHalfedge();
        if (b == kInvalid) {
          what = "add (no boundary)";
          return "";
        }
        uint32_t u = em_.vert()[b], v = em_.vert()[b ^ 1u], w = em_.vert()[em_.next()[b] ^ 1u];
        std::snprintf(buf, sizeof buf, "addTriangle(%u, %u, %u) on loop", u, v, w);
        s = em_.addTriangle(u, v, w);
        break;
      }
      case 4: {  // a triangle on a boundary edge to a new vertex
        uint32_t b = boundaryHalfedge();
        if (b == kInvalid) {
          what = "add (no boundary)";
          return "";
        }
        uint32_t u = em_.vert()[b], v = em_.vert()[b ^ 1u], w;
        const float* p = em_.positions().data();
        s = em_.addVertex(p[3 * u] + 0.25f, p[3 * u + 1] - 0.5f, p[3 * v + 2] + 0.125f, &w);
        if (!s.ok()) return "addVertex: " + s.message;
        snapshot = checkEachEdit ? Snapshot(em_) : emptySnapshot();
        std::snprintf(buf, sizeof buf, "addTriangle(%u, %u, new %u)", u, v, w);
        s = em_.addTriangle(u, v, w);
        break;
      }
      case 5: {
        uint32_t n = em_.nVertices();
        if (n == 0) {
          what = "add (no vertex)";
          return "";
        }
        uint32_t a = pick_(n), b = pick_(n), c = pick_(n);
        bool nm = pick_(2) == 1;
        std::snprintf(buf, sizeof buf, "addTriangle(%u, %u, %u, nonManifold %d)", a, b, c, nm);
        s = em_.addTriangle(a, b, c, nullptr, nm);
        break;
      }
      case 6:
      case 7: {
        uint32_t e = liveHalfedge();
        if (e == kInvalid) {
          what = "flip (none)";
          return "";
        }
        std::snprintf(buf, sizeof buf, "flipEdge(%u)", e);
        s = em_.flipEdge(e);
        break;
      }
      case 8:
      case 9: {
        uint32_t e = liveHalfedge();
        if (e == kInvalid) {
          what = "split (none)";
          return "";
        }
        double t = (1 + pick_(7)) / 8.0;
        std::snprintf(buf, sizeof buf, "splitEdge(%u, %g)", e, t);
        s = em_.splitEdge(e, t);
        break;
      }
      case 10:
      case 11: {
        uint32_t e = liveHalfedge();
        if (e == kInvalid) {
          what = "collapse (none)";
          return "";
        }
        double t = pick_(3) / 2.0;
        std::snprintf(buf, sizeof buf, "collapseEdge(%u, %g)", e, t);
        s = em_.collapseEdge(e, t);
        break;
      }
      case 12: {
        uint32_t t = liveTriangle();
        if (t == kInvalid) {
          what = "reverse (none)";
          return "";
        }
        std::snprintf(buf, sizeof buf, "reverseTriangle(%u)", t);
        s = em_.reverseTriangle(t);
        break;
      }
      case 13: {
        uint32_t t = liveTriangle();
        if (t == kInvalid) {
          what = "reverseShell (none)";
          return "";
        }
        std::snprintf(buf, sizeof buf, "reverseShell(%u)", t);
        s = em_.reverseShell(t);
        break;
      }
      case 14: {
        uint32_t b = boundaryHalfedge();
        if (b == kInvalid) {
          what = "fill (no boundary)";
          return "";
        }
        FillMethod m = pick_(2) ? FillMethod::Ear : FillMethod::Fan;
        std::snprintf(buf, sizeof buf, "fillHole(%u, %s)", b, m == FillMethod::Ear ? "ear" : "fan");
        Array<uint32_t> added;
        s = em_.fillHole(b, m, &added);
        break;
      }
      case 15: {  // merge a boundary vertex into another, or two consecutive ones of two loops
        uint32_t b1 = boundaryHalfedge(), b2 = boundaryHalfedge();
        if (b1 == kInvalid) {
          what = "merge (no boundary)";
          return "";
        }
        const bool allow = pick_(2) == 1;
        uint32_t keep[2] = {em_.vert()[b1], em_.vert()[em_.next()[b1]]};
        uint32_t gone[2] = {em_.vert()[b2 ^ 1u], em_.vert()[b2]};  // b2 runs the other way
        const uint32_t n = 1 + pick_(2);
        std::snprintf(buf, sizeof buf, "mergeVertices(%u <- %u%s, allow %d)", keep[0], gone[0],
                      n == 2 ? (", " + std::to_string(keep[1]) + " <- " + std::to_string(gone[1])).c_str() : "", allow);
        s = em_.mergeVertices(keep, gone, n, allow);
        break;
      }
      case 16: {  // split a boundary edge at a vertex
        uint32_t b = boundaryHalfedge();
        if (b == kInvalid || em_.nVertices() == 0) {
          what = "splitEdgeAt (no boundary)";
          return "";
        }
        uint32_t v = pick_(2) ? em_.vert()[em_.next()[em_.next()[b]]] : pick_(em_.nVertices());
        const bool allow = pick_(2) == 1;
        std::snprintf(buf, sizeof buf, "splitEdgeAt(%u, %u, allow %d)", b, v, allow);
        s = em_.splitEdgeAt(b, v, allow);
        break;
      }
      case 17: {  // split a vertex into its fans (a non-manifold one when there is one)
        uint32_t n = em_.nVertices();
        if (n == 0) {
          what = "splitVertex (no vertex)";
          return "";
        }
        uint32_t v = pick_(n);
        for (uint32_t i = 0; i < n && pick_(2) == 1; ++i)
          if (em_.vertexAlive((v + i) % n) && em_.vertexNonManifold((v + i) % n)) {
            v = (v + i) % n;
            break;
          }
        std::snprintf(buf, sizeof buf, "splitVertex(%u)", v);
        s = em_.splitVertex(v);
        break;
      }
      case 18: {  // reverse a few triangles as one edit (sometimes one of them listed twice)
        uint32_t ids[5];
        uint32_t k = 1 + pick_(4);
        for (uint32_t i = 0; i < k; ++i) ids[i] = liveTriangle();
        if (ids[0] == kInvalid) {
          what = "reverseTriangles (none)";
          return "";
        }
        if (pick_(6) == 0) ids[k++] = ids[0];
        std::snprintf(buf, sizeof buf, "reverseTriangles(%u ids, first %u)", k, ids[0]);
        s = em_.reverseTriangles(ids, k);
        break;
      }
      default: {
        const uint32_t which = pick_(4);
        if (which == 1) {  // move a vertex (perhaps a dead one, perhaps to a non-finite place)
          uint32_t n = em_.nVertices();
          if (n == 0) {
            what = "setPosition (no vertex)";
            return "";
          }
          uint32_t v = pick_(n), w = pick_(n);
          const float* p = em_.positions().data();
          float x = p[3 * w] + 0.25f * float(pick_(5)), y = p[3 * w + 1] - 0.125f, z = p[3 * v + 2];
          if (pick_(8) == 0) y = std::numeric_limits<float>::infinity();
          std::snprintf(buf, sizeof buf, "setPosition(%u, %g, %g, %g)", v, x, y, z);
          s = em_.setPosition(v, x, y, z);
          if (s.ok() &&
              (em_.positions()[3 * v] != x || em_.positions()[3 * v + 1] != y || em_.positions()[3 * v + 2] != z))
            return std::string(buf) + " did not move the vertex there";
          break;
        }
        if (which != 0) {
          what = "nothing";
          return "";
        }
        std::snprintf(buf, sizeof buf, "compact()");
        const std::string json = em_.infoJson("f");
        s = em_.compact();
        if (s.ok() && em_.infoJson("f") != json) return std::string(buf) + " changed the report";
        break;
      }
    }
    what = buf;
    if (!s.ok()) {
      if (s.code != Code::EditRefused && s.code != Code::InvalidArgument) return what + ": unexpected " + s.message;
      if (s.message.compare(0, std::strlen(codeName(s.code)) + 2, std::string(codeName(s.code)) + ": ") != 0)
        return what + ": message without its code: " + s.message;
      if (snap && !(Snapshot(em_) == *snap)) return what + " was refused (" + s.message + ") but changed the mesh";
      return "";
    }
    ++done_;
    const EditStats& after = em_.stats();
    // Collapse and flip keep the topology of the surface, and so does a split, unless two
    // triangles on the edge share their third vertex (the new edges to it become one, with
    // four sides: non-manifold).
    const bool splitMadeNonManifold = (op == 8 || op == 9) && after.nonManifoldEdges > before.nonManifoldEdges;
    if (op >= 6 && op <= 11 && !splitMadeNonManifold &&
        (after.eulerCharacteristic != before.eulerCharacteristic || after.shells != before.shells))
      return what + " changed the Euler characteristic or the shells";
    if (op >= 10 && op <= 11 &&
        (after.nonManifoldEdges > before.nonManifoldEdges || after.nonManifoldVertices > before.nonManifoldVertices ||
         after.inconsistentEdges > before.inconsistentEdges))
      return what + " made the mesh less manifold";
    // The joins never make a figure worse (unless non-manifold vertices were allowed).
    const bool joinChecked = op == 15 || op == 16;
    if (joinChecked &&
        (after.boundaryEdges + after.nonManifoldEdges + after.inconsistentEdges >
             before.boundaryEdges + before.nonManifoldEdges + before.inconsistentEdges ||
         after.nonManifoldEdges > before.nonManifoldEdges || after.inconsistentEdges > before.inconsistentEdges))
      return what + " made the edges worse";
    if (joinChecked && what.find("allow 0") != std::string::npos &&
        after.nonManifoldVertices > before.nonManifoldVertices)
      return what + " made a vertex non-manifold";
    // A split never adds a non-manifold edge (the non-manifold vertices may grow: fans
    // joined through an inconsistent edge stay non-manifold in each part, and a pair kept at
    // one end may be cut at the other end until that end is split too).
    if (op == 17 && after.nonManifoldEdges > before.nonManifoldEdges) return what + " added a non-manifold edge";
    if (what.compare(0, 12, "setPosition(") == 0 &&  // by name: the op numbers change as edits are added
        (after.triangles != before.triangles || after.vertices != before.vertices || after.edges != before.edges ||
         after.boundaryEdges != before.boundaryEdges || after.nonManifoldEdges != before.nonManifoldEdges ||
         after.inconsistentEdges != before.inconsistentEdges || after.holes != before.holes ||
         after.seams != before.seams || after.shells != before.shells || after.degenerate != before.degenerate))
      return what + " changed the topology's counts";
    if (!checkEachEdit) return "";
    std::string d = differenceFromRebuild(em_);
    return d.empty() ? "" : what + ": " + d;
  }
  uint32_t done() const { return done_; }

 private:
  static Snapshot emptySnapshot() {
    static stltopo::EditableMesh empty;
    return Snapshot(empty);
  }
  uint32_t liveTriangle() {
    uint32_t n = em_.nTriangles();
    if (em_.nLiveTriangles() == 0) return stltopo::kInvalid;
    uint32_t t = pick_(n);
    while (!em_.triangleAlive(t)) t = (t + 1) % n;
    return t;
  }
  uint32_t liveHalfedge() {
    uint32_t n = em_.nHalfedges();
    if (em_.nLiveHalfedges() == 0) return stltopo::kInvalid;
    uint32_t e = pick_(n);
    while (!em_.halfedgeAlive(e)) e = (e + 1) % n;
    return e;
  }
  uint32_t boundaryHalfedge() {
    const stltopo::EditLoops& l = em_.loops();
    if (l.nLoops() == 0) return stltopo::kInvalid;
    uint32_t h = pick_(l.nLoops());
    uint32_t len = l.loopOffsets[h + 1] - l.loopOffsets[h];
    return l.loopHalfedges[l.loopOffsets[h] + pick_(len)];
  }
  stltopo::EditableMesh& em_;
  Pick& pick_;
  uint32_t done_ = 0;
};

}  // namespace editcheck
