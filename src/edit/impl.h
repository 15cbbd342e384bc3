// The EditableMesh's private state and its machinery, shared by the files of src/edit/:
//   topology_ops.cpp  the topology engine: corner lists, the change (reserve, apply, repair,
//                     refan), the loop numbering and the shell count
//   attributes.cpp    the attribute engine (rules, pending writes) and the attribute API
//   operations.cpp    init and the edits (add, remove, flip, split, collapse, reverse, fill)
//   output.cpp        reading (loops, stats, infoJson), toMesh, compact and validate
//   editable_mesh.cpp the public class: it holds an Impl* and forwards to it
// Every operation is written as a change (triangles removed, triangles whose corners change,
// triangles added) that apply() carries out on the arrays. apply() re-pairs exactly the edges
// whose sides changed, by the rule buildTopology uses, and re-links the boundary next
// pointers by the fan rule at exactly the vertices whose triangles changed, so that the
// result is the topology buildTopology would give for the new triangles (up to the
// numbering, which toMesh() makes equal). Operations check everything that can refuse them
// and reserve every array they may grow before apply() starts, so apply() cannot fail
// half-way. Private (not installed).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "stltopo/edit.h"
#include "text_format.h"
#include "try_alloc.h"

namespace stltopo {
namespace edit_detail {

inline uint32_t nextCorner(uint32_t c) { return c == 2 ? 0 : c + 1; }
inline uint32_t prevCorner(uint32_t c) { return c == 0 ? 2 : c - 1; }
inline uint64_t edgeKey(uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a; }
inline Status refused(const std::string& why) { return Status::error(Code::EditRefused, why); }
inline Status badArgument(const std::string& why) { return Status::error(Code::InvalidArgument, why); }
// What out-of-memory says could not be allocated (detail::oom).
inline constexpr const char* kEditArrays = "the editable mesh's arrays";

// `a` emptied, keeping its memory: init() and toMesh() rebuild into the arrays they had, so a
// caller that rebuilds again and again (the repair runner, after every step) writes pages it
// already has instead of fresh ones, which the kernel must zero first.
template <class T>
Array<T> emptied(Array<T>& a) {
  Array<T> r = std::move(a);
  r.clear();
  return r;
}

// Capacity for n elements, growing geometrically (so that appends are amortized O(1)).
template <class T>
inline bool growTo(Array<T>& a, size_t n) {
  if (n <= a.capacity()) return true;
  size_t c = std::max<size_t>(std::max(n, a.capacity() * 2), 16);
  return a.reserve(c) || a.reserve(n);
}

// What an undirected edge is, from how many sides it has and how many run low -> high.
enum class EdgeClass : uint8_t { None, Interior, Boundary, Inconsistent, NonManifold };
inline EdgeClass classify(uint32_t m, uint32_t lowToHigh) {
  if (m == 0) return EdgeClass::None;
  if (m == 1) return EdgeClass::Boundary;
  if (m == 2) return lowToHigh == 1 ? EdgeClass::Interior : EdgeClass::Inconsistent;
  return EdgeClass::NonManifold;
}

}  // namespace edit_detail
// impl.h is included only by src/edit/*.cpp.
using namespace edit_detail;

struct EditableMesh::Impl {
  using M = Impl;

  // --- The public API (EditableMesh forwards every call here; contracts in edit.h) -------
  Status init(const Mesh& mesh, const Topology& topo);
  Status init(const Mesh& mesh, const TopologyOptions& options = {});
  uint32_t nVertices() const { return uint32_t(positions_.size() / 3); }
  uint32_t nTriangles() const { return uint32_t(triangles_.size() / 3); }
  uint32_t nHalfedges() const { return uint32_t(next_.size()); }
  bool vertexAlive(uint32_t v) const { return v < nVertices() && !vertexDead_[v]; }
  bool triangleAlive(uint32_t t) const { return t < nTriangles() && triangles_[3 * size_t(t)] != kInvalid; }
  bool halfedgeAlive(uint32_t e) const { return e < nHalfedges() && vert_[e] != kInvalid; }
  bool isBoundary(uint32_t e) const { return (face_[e] & kLoopFaceBit) != 0 && face_[e] != kInvalid; }
  uint32_t face(uint32_t e);
  const EditLoops& loops();
  const EditStats& stats();
  std::string infoJson(const std::string& file);
  Status reserve(uint32_t vertices, uint32_t triangles);
  Status addVertex(float x, float y, float z, uint32_t* out = nullptr);
  Status setPosition(uint32_t v, float x, float y, float z);
  Status removeTriangle(uint32_t t);
  Status addTriangle(uint32_t a, uint32_t b, uint32_t c, uint32_t* out = nullptr, bool allowNonManifold = false);
  Status flipEdge(uint32_t e);
  Status splitEdge(uint32_t e, double t = 0.5, uint32_t* newVertex = nullptr);
  Status collapseEdge(uint32_t e, double t = 0.5, uint32_t* remaining = nullptr);
  Status reverseTriangle(uint32_t t);
  Status reverseTriangles(const uint32_t* ids, uint32_t n);
  Status reverseShell(uint32_t t);
  Status fillHole(uint32_t e, FillMethod method, Array<uint32_t>* out = nullptr);
  Status fillLoop(uint32_t h, FillMethod method, Array<uint32_t>* out = nullptr);
  Status mergeVertices(const uint32_t* keep, const uint32_t* gone, uint32_t n, bool allowNonManifold = false);
  Status splitEdgeAt(uint32_t e, uint32_t v, bool allowNonManifold = false);
  Status stitch(const uint32_t* keep, const uint32_t* gone, uint32_t n, const uint32_t* edges, const uint32_t* vertices,
                uint32_t nSplits, bool allowNonManifold = false);
  Status splitVertex(uint32_t v, uint32_t* firstNew = nullptr, uint32_t* newCount = nullptr);
  Status addAttribute(const std::string& name, Element element, ValueType type, uint32_t components, const void* values,
                      const AttributeRules& rules = {}, const double* defaultValue = nullptr);
  const AttributeView* attribute(const std::string& name) const;
  bool removeAttribute(const std::string& name);
  std::vector<std::string> attributeNames() const;
  Status toMesh(Mesh& out, Topology* topo = nullptr, CompactMaps* maps = nullptr, bool triangleShell = false,
                bool figures = true) const;
  Status compact(CompactMaps* maps = nullptr);
  Status validate() const;

  // --- State --------------------------------------------------------------------------
  // Mesh.
  Array<float> positions_;
  Array<uint32_t> triangles_;
  Array<uint8_t> vertexDead_;
  Array<uint8_t> degenerate_;
  // Corner lists: corner 3t + c is in the doubly linked list of the vertex it uses.
  Array<uint32_t> cornerNext_, cornerPrev_, vertexCorner_, vertexCornerCount_;
  // Half-edges.
  Array<uint32_t> sideHalfedge_;  // per side 3t + c (corner c -> c + 1): its half-edge
  Array<uint32_t> next_, prev_, vert_, face_;
  Array<uint8_t> pairKind_;
  Array<uint32_t> freePairs_;
  Array<uint32_t> triangleHalfedge_, vertexHalfedge_;
  Array<uint8_t> vertexNonManifold_;
  // Counts kept up to date by every edit.
  uint32_t nLiveTriangles_ = 0, nLiveVertices_ = 0, nLivePairs_ = 0, nDegenerate_ = 0;
  uint32_t nEdges_ = 0, nBoundaryEdges_ = 0, nNonManifoldEdges_ = 0, nInconsistentEdges_ = 0;
  uint32_t nNonManifoldVertices_ = 0;
  // Computed when read.
  bool loopsStale_ = true, statsStale_ = true;
  // The shell count of the topology init() was given (its nShells), until the first change
  // that can change it (whatever makes the stats stale forgets it, but reversing triangles,
  // which keeps every shared edge): stats() then needs no shell pass.
  uint32_t knownShells_ = kInvalid;
  EditLoops loops_;
  EditStats stats_;
  // File-level data carried to toMesh().
  Format format_ = Format::Unknown;
  ColorConvention colorConvention_ = ColorConvention::None;
  std::vector<Solid> solids_;  // names; firstTriangle of the original ranges
  std::vector<Status> warnings_;
  // Attributes.
  struct Attribute {
    std::string name;
    AttributeView view;
    Array<uint8_t> bytes;
    AttributeRules rules;
    std::vector<double> defaultValue;
  };
  std::vector<Attribute> attributes_;
  // Scratch for edits, kept between edits so that an edit does not allocate.
  Array<uint32_t> stamp_;  // per vertex: == epoch_ when in the current set
  uint32_t epoch_ = 0;
  Array<uint32_t> triStamp_;  // per triangle: == triEpoch_ when in the current set
  uint32_t triEpoch_ = 0;
  Array<uint32_t> chRemoved_, chRewritten_, chRewrittenCorners_, chAdded_;  // the change
  Array<uint32_t> touchedVertices_, dirtyTriangles_, sides_, oldSlots_, pairs_, claimed_;
  Array<uint64_t> touchedEdges_;
  struct Detached {
    uint64_t edge;  // lo << 32 | hi
    uint32_t he;
    uint32_t lowToHigh;
  };
  Array<Detached> detached_;

  // --- Machinery ------------------------------------------------------------------------

  static size_t elementCount(const M& m, Element e) {
    switch (e) {
      case Element::Vertex: return m.nVertices();
      case Element::Triangle: return m.nTriangles();
      case Element::Edge: return m.pairKind_.size();
    }
    return 0;
  }
  static size_t stride(const Attribute& a) { return valueTypeSize(a.view.type) * a.view.components; }
  static uint8_t* at(Attribute& a, size_t i) { return a.bytes.data() + i * stride(a); }

  // Grows element kind `e`'s attributes to n slots (capacity only).
  static bool reserveAttributes(M& m, Element e, size_t n);
  // Appends one slot with the default value to every attribute of kind e (capacity reserved).
  static void appendDefaults(M& m, Element e);
  static void writeDefault(const Attribute& a, uint8_t* p);
  static void resetDefault(M& m, Element e, size_t i);
  static void copySlot(M& m, Element e, size_t from, size_t to);
  // Applies a rule to the values x and y (b's weight t) of attribute a into out. false: the
  // rule refuses.
  static bool evalRule(const Attribute& a, bool merge, const uint8_t* x, const uint8_t* y, double t, uint8_t* out);

  // Values computed before an edit and written after it: (attribute, element id or edge,
  // bytes). Kept in a small list; an edit makes a handful.
  struct Pending {
    size_t attr;
    uint32_t id;    // vertex or triangle id; for edges kInvalid
    uint32_t u, v;  // the edge (for Element::Edge)
    size_t offset;  // into bytes
  };
  struct PendingWrites {
    std::vector<Pending> list;
    Array<uint8_t> bytes;
    std::string refusal;
    bool oom = false;
    // Evaluates the rule of attribute ai on x, y; false when refused or out of memory.
    bool add(const M& m, size_t ai, bool merge, const uint8_t* x, const uint8_t* y, double t, uint32_t id,
             uint32_t u = kInvalid, uint32_t v = kInvalid) {
      const Attribute& a = m.attributes_[ai];
      size_t s = stride(a), off = bytes.size();
      if (!growTo(bytes, off + s) || !bytes.resize(off + s)) {
        oom = true;
        return false;
      }
      if (!evalRule(a, merge, x, y, t, bytes.data() + off)) {
        refusal =
            detail::format("attribute \"%s\" refuses to %s the values", a.name.c_str(), merge ? "merge" : "split");
        return false;
      }
      STLTOPO_TRY { list.push_back(Pending{ai, id, u, v, off}); }
      STLTOPO_CATCH {
        oom = true;
        return false;
      }
      return true;
    }
    Status status() const { return oom ? detail::oom(kEditArrays) : refused(refusal); }
  };
  static void writePending(M& m, const PendingWrites& pw);

  // ------------------------------------------------------------------------ corner lists
  static void link(M& m, uint32_t q) {
    uint32_t v = m.triangles_[q], h = m.vertexCorner_[v];
    m.cornerNext_[q] = h;
    m.cornerPrev_[q] = kInvalid;
    if (h != kInvalid) m.cornerPrev_[h] = q;
    m.vertexCorner_[v] = q;
    ++m.vertexCornerCount_[v];
  }
  static void unlink(M& m, uint32_t q) {
    uint32_t v = m.triangles_[q], n = m.cornerNext_[q], p = m.cornerPrev_[q];
    if (p != kInvalid)
      m.cornerNext_[p] = n;
    else
      m.vertexCorner_[v] = n;
    if (n != kInvalid) m.cornerPrev_[n] = p;
    m.cornerNext_[q] = m.cornerPrev_[q] = kInvalid;
    --m.vertexCornerCount_[v];
  }
  template <class F>
  static void forEachCorner(const M& m, uint32_t v, F&& f) {
    for (uint32_t q = m.vertexCorner_[v]; q != kInvalid; q = m.cornerNext_[q]) f(q);
  }
  // The sides (3t + c, corner c -> c + 1) of live non-degenerate triangles between u and v,
  // in no particular order. O(corners of the endpoint with fewer).
  template <class F>
  static void forEachEdgeSide(const M& m, uint32_t u, uint32_t v, F&& f) {
    if (m.vertexCornerCount_[v] < m.vertexCornerCount_[u]) std::swap(u, v);
    forEachCorner(m, u, [&](uint32_t q) {
      uint32_t t = q / 3, c = q % 3;
      if (m.degenerate_[t]) return;
      if (m.triangles_[3 * t + nextCorner(c)] == v) f(q);
      if (m.triangles_[3 * t + prevCorner(c)] == v) f(3 * t + prevCorner(c));
    });
  }
  static bool edgeExists(const M& m, uint32_t u, uint32_t v) {
    bool found = false;
    forEachEdgeSide(m, u, v, [&](uint32_t) { found = true; });
    return found;
  }
  static uint32_t sideDst(const M& m, uint32_t s) { return m.triangles_[3 * (s / 3) + nextCorner(s % 3)]; }
  static bool boundaryFace(uint32_t f) { return (f & kLoopFaceBit) != 0 && f != kInvalid; }

  // ------------------------------------------------------------------------ reservation
  // Capacity for a change of the current chRemoved_/chRewritten_/chAdded_ and for
  // `newVertices` vertices more, so that apply() cannot fail.
  static bool reserveChange(M& m, uint32_t newVertices);
  static void clearChange(M& m) {
    m.chRemoved_.clear();
    m.chRewritten_.clear();
    m.chRewrittenCorners_.clear();
    m.chAdded_.clear();
  }
  // Appends a vertex (capacity reserved).
  static uint32_t appendVertex(M& m, const float* p);
  static uint32_t newPairSlot(M& m);
  static void freePairSlot(M& m, uint32_t k);

  static void countEdge(M& m, EdgeClass c, int d) {
    uint32_t u = uint32_t(d);
    switch (c) {
      case EdgeClass::None: return;
      case EdgeClass::Interior: break;
      case EdgeClass::Boundary: m.nBoundaryEdges_ += u; break;
      case EdgeClass::Inconsistent: m.nInconsistentEdges_ += u; break;
      case EdgeClass::NonManifold: m.nNonManifoldEdges_ += u; break;
    }
    m.nEdges_ += u;
  }

  // ------------------------------------------------------------------------ apply
  static void newEpoch(M& m) {
    if (++m.epoch_ == 0) {
      for (uint32_t v = 0; v < m.nVertices(); ++v) m.stamp_[v] = 0;
      m.epoch_ = 1;
    }
  }
  static void newTriangleEpoch(M& m) {
    if (++m.triEpoch_ == 0) {
      for (uint32_t t = 0; t < m.nTriangles(); ++t) m.triStamp_[t] = 0;
      m.triEpoch_ = 1;
    }
  }
  static void touch(M& m, uint32_t v) {
    if (m.stamp_[v] == m.epoch_) return;
    m.stamp_[v] = m.epoch_;
    (void)m.touchedVertices_.push_back(v);
  }

  // Carries out the change (capacity reserved by reserveChange()). Returns the id of the first
  // added triangle (the others follow).
  static uint32_t apply(M& m);

  // Pairs the sides of edge (lo, hi) by buildTopology's rule; [d0, d1) are the edge's
  // detached sides (their old half-edges).
  static void repair(M& m, uint32_t lo, uint32_t hi, size_t d0, size_t d1);

  // The boundary next pointers into u by the fan rule, u's outgoing half-edge (the
  // lowest-id boundary one, else the lowest-id one) and its non-manifold flag.
  static void refan(M& m, uint32_t u);

  // ------------------------------------------------------------------------ loops, shells
  // Numbers the boundary loops as buildTopology would on the compacted mesh: in order of
  // their earliest triangle side, each from the twin of that side. faceOut (nullable)
  // receives kLoopFaceBit | loop for each boundary half-edge.
  static bool labelLoops(const M& m, EditLoops& out, uint32_t* faceOut);
  // The perimeter of the loop through boundary half-edge e, summed in next order from e as
  // labelLoops sums it (so that, from the loop's first half-edge, it equals a fresh build's).
  static double loopPerimeter(const M& m, uint32_t e);

  // Edge-connected components of the live non-degenerate triangles (every shared edge
  // counts, paired or cut). kInvalid on allocation failure.
  static uint32_t countShells(const M& m);
  // The same components as Topology::triangleShell of the compacted mesh (`compacted`:
  // slot -> compacted triangle id, kInvalid for a dead slot): numbered in the order of
  // their lowest triangle, kInvalid for a degenerate triangle; nShells their number.
  // False on allocation failure.
  static bool labelShells(const M& m, const Array<uint32_t>& compacted, Array<uint32_t>& triangleShell,
                          uint32_t& nShells);
  // countShells' union-find: parent[t] is the lowest slot of t's component (t itself for a
  // dead or degenerate slot, never united). False on allocation failure.
  static bool uniteShells(const M& m, Array<uint32_t>& parent);

  // ------------------------------------------------------------------------ checks
  static Status checkTriangle(const M& m, uint32_t t) {
    if (t >= m.nTriangles()) return badArgument(detail::format("triangle %u is out of range", t));
    if (!m.triangleAlive(t)) return badArgument(detail::format("triangle %u was removed", t));
    return Status{};
  }
  static Status checkHalfedge(const M& m, uint32_t e) {
    if (e >= m.nHalfedges()) return badArgument(detail::format("half-edge %u is out of range", e));
    if (!m.halfedgeAlive(e)) return badArgument(detail::format("half-edge %u was removed", e));
    return Status{};
  }
  static Status checkVertex(const M& m, uint32_t v) {
    if (v >= m.nVertices()) return badArgument(detail::format("vertex %u is out of range", v));
    if (m.vertexDead_[v]) return badArgument(detail::format("vertex %u was removed", v));
    return Status{};
  }
  static void position(const M& m, uint32_t v, double* p) {
    for (int k = 0; k < 3; ++k) p[k] = m.positions_[3 * size_t(v) + k];
  }
  // The triangle side of the pair of e between its two vertices, running org(e) -> dst(e)
  // when there is one, else the other way.
  static uint32_t triangleSide(const M& m, uint32_t e, uint32_t& t) {
    uint32_t f = m.face_[e];
    if (boundaryFace(f)) {
      e ^= 1u;
      f = m.face_[e];
    }
    t = f;
    for (uint32_t c = 0; c < 3; ++c)
      if (m.sideHalfedge_[3 * t + c] == e) return 3 * t + c;
    return kInvalid;
  }
  static uint32_t thirdCorner(const M& m, uint32_t s) { return m.triangles_[3 * (s / 3) + prevCorner(s % 3)]; }

  // The change of chRewritten_/chAdded_ (nothing removed) joins vertices or edges
  // (mergeVertices, splitEdgeAt): refused when a changed triangle gets a repeated corner,
  // when an edge that gains sides from another ends non-manifold or inconsistent, when the
  // boundary, non-manifold or inconsistent edges would grow, and unless allowNonManifold
  // when the non-manifold vertices would grow. Reads only (scratch: its own arrays).
  static Status checkJoin(M& m, bool allowNonManifold);
  // The fans of vertex v as splitVertex defines them: fanOf[i] for the i-th corner of v
  // in corner-list order (degenerate triangles: fan 0), fans numbered by lowest triangle.
  static Status vertexFans(const M& m, uint32_t v, Array<uint32_t>& corners, Array<uint32_t>& fanOf, uint32_t& nFans);

  // A triangle attribute's bytes of triangle t / vertex v / pair k.
  static const uint8_t* valueOf(const M& m, size_t ai, uint32_t id) {
    const Attribute& a = m.attributes_[ai];
    return a.bytes.data() + size_t(id) * stride(a);
  }
};

}  // namespace stltopo
