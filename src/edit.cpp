// EditableMesh: the edit machinery. Every operation is written as a change (triangles
// removed, triangles whose corners change, triangles added) that apply() carries out on
// the arrays. apply() re-pairs exactly the edges whose sides changed, by the rule
// buildTopology uses, and re-links the boundary next pointers by the fan rule at exactly
// the vertices whose triangles changed, so that the result is the topology buildTopology
// would give for the new triangles (up to the numbering, which toMesh() makes equal).
// Operations check everything that can refuse them and reserve every array they may grow
// before apply() starts, so apply() cannot fail half-way.
#include "stltopo/edit.h"

#include <algorithm>
#include <cmath>

#include "stltopo/report.h"
#include "text_format.h"
#include "triangle_figures.h"
#include "try_alloc.h"

// Allocation failure of the std containers (names, the attribute list) is caught where
// exceptions exist; the wasm build has none (an allocation failure there aborts, as for
// the rest of the std containers of the core).
#if defined(__cpp_exceptions)
#define STLTOPO_TRY try
#define STLTOPO_CATCH catch (...)
#else
#define STLTOPO_TRY if (true)
#define STLTOPO_CATCH else
#endif

namespace stltopo {
namespace {

inline uint32_t nextCorner(uint32_t c) { return c == 2 ? 0 : c + 1; }
inline uint32_t prevCorner(uint32_t c) { return c == 0 ? 2 : c - 1; }
inline uint64_t edgeKey(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}
Status refused(const std::string& why) { return Status::error(Code::EditRefused, why); }
Status badArgument(const std::string& why) { return Status::error(Code::InvalidArgument, why); }
// What out-of-memory says could not be allocated (detail::oom).
constexpr const char* kEditArrays = "the editable mesh's arrays";

// Capacity for n elements, growing geometrically (so that appends are amortized O(1)).
template <class T>
bool growTo(Array<T>& a, size_t n) {
  if (n <= a.capacity()) return true;
  size_t c = std::max<size_t>(std::max(n, a.capacity() * 2), 16);
  return a.reserve(c) || a.reserve(n);
}

// What an undirected edge is, from how many sides it has and how many run low -> high.
enum class EdgeClass : uint8_t { None, Interior, Boundary, Inconsistent, NonManifold };
EdgeClass classify(uint32_t m, uint32_t lowToHigh) {
  if (m == 0) return EdgeClass::None;
  if (m == 1) return EdgeClass::Boundary;
  if (m == 2) return lowToHigh == 1 ? EdgeClass::Interior : EdgeClass::Inconsistent;
  return EdgeClass::NonManifold;
}

constexpr uint32_t kMaxComponents = 64;

double readValue(ValueType t, const uint8_t* p) {
  switch (t) {
    case ValueType::U8: return *p;
    case ValueType::I8: return int8_t(*p);
    case ValueType::U16: { uint16_t v; std::memcpy(&v, p, 2); return v; }
    case ValueType::I16: { int16_t v; std::memcpy(&v, p, 2); return v; }
    case ValueType::U32: { uint32_t v; std::memcpy(&v, p, 4); return v; }
    case ValueType::I32: { int32_t v; std::memcpy(&v, p, 4); return v; }
    case ValueType::F32: { float v; std::memcpy(&v, p, 4); return v; }
    case ValueType::F64: { double v; std::memcpy(&v, p, 8); return v; }
  }
  return 0;
}

template <class T>
void storeInt(double x, uint8_t* p, double lo, double hi) {
  double r = std::isnan(x) ? 0 : std::min(hi, std::max(lo, std::nearbyint(x)));
  T v = T(r);
  std::memcpy(p, &v, sizeof v);
}

void writeValue(ValueType t, double x, uint8_t* p) {
  switch (t) {
    case ValueType::U8: storeInt<uint8_t>(x, p, 0, 255); break;
    case ValueType::I8: storeInt<int8_t>(x, p, -128, 127); break;
    case ValueType::U16: storeInt<uint16_t>(x, p, 0, 65535); break;
    case ValueType::I16: storeInt<int16_t>(x, p, -32768, 32767); break;
    case ValueType::U32: storeInt<uint32_t>(x, p, 0, 4294967295.0); break;
    case ValueType::I32: storeInt<int32_t>(x, p, -2147483648.0, 2147483647.0); break;
    case ValueType::F32: { float v = float(x); std::memcpy(p, &v, 4); break; }
    case ValueType::F64: std::memcpy(p, &x, 8); break;
  }
}

// Newell normal of triangle (p, q, r), unnormalized, in double.
void triangleNormal(const double* p, const double* q, const double* r, double* n) {
  double ux = q[0] - p[0], uy = q[1] - p[1], uz = q[2] - p[2];
  double wx = r[0] - p[0], wy = r[1] - p[1], wz = r[2] - p[2];
  n[0] = uy * wz - uz * wy;
  n[1] = uz * wx - ux * wz;
  n[2] = ux * wy - uy * wx;
}

}  // namespace

size_t valueTypeSize(ValueType t) {
  switch (t) {
    case ValueType::U8: case ValueType::I8: return 1;
    case ValueType::U16: case ValueType::I16: return 2;
    case ValueType::U32: case ValueType::I32: case ValueType::F32: return 4;
    case ValueType::F64: return 8;
  }
  return 1;
}

struct EditableMesh::Impl {
  using M = EditableMesh;
  using Attribute = M::Attribute;

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
  static bool reserveAttributes(M& m, Element e, size_t n) {
    for (Attribute& a : m.attributes_)
      if (a.view.element == e && !growTo(a.bytes, n * stride(a))) return false;
    return true;
  }
  // Appends one slot with the default value to every attribute of kind e (capacity reserved).
  static void appendDefaults(M& m, Element e) {
    for (Attribute& a : m.attributes_) {
      if (a.view.element != e) continue;
      size_t s = stride(a), n = a.bytes.size();
      (void)a.bytes.resize(n + s);
      writeDefault(a, a.bytes.data() + n);
      a.view.data = a.bytes.data();
      a.view.count = a.bytes.size() / s;
    }
  }
  static void writeDefault(const Attribute& a, uint8_t* p) {
    size_t w = valueTypeSize(a.view.type);
    for (uint32_t k = 0; k < a.view.components; ++k) writeValue(a.view.type, a.defaultValue[k], p + k * w);
  }
  static void resetDefault(M& m, Element e, size_t i) {
    for (Attribute& a : m.attributes_)
      if (a.view.element == e) writeDefault(a, at(a, i));
  }
  static void copySlot(M& m, Element e, size_t from, size_t to) {
    for (Attribute& a : m.attributes_)
      if (a.view.element == e) std::memmove(at(a, to), at(a, from), stride(a));
  }
  // Applies a rule to the values x and y (b's weight t) of attribute a into out. false: the
  // rule refuses.
  static bool evalRule(const Attribute& a, bool merge, const uint8_t* x, const uint8_t* y, double t, uint8_t* out) {
    const Rule r = merge ? a.rules.merge : a.rules.split;
    const size_t w = valueTypeSize(a.view.type), s = w * a.view.components;
    switch (r) {
      case Rule::KeepFirst: std::memmove(out, x, s); return true;
      case Rule::Fail:
        if (std::memcmp(x, y, s) != 0) return false;
        std::memmove(out, x, s);
        return true;
      case Rule::Average:
      case Rule::Custom: {
        double xd[kMaxComponents], yd[kMaxComponents], od[kMaxComponents];
        for (uint32_t k = 0; k < a.view.components; ++k) {
          xd[k] = readValue(a.view.type, x + k * w);
          yd[k] = readValue(a.view.type, y + k * w);
        }
        if (r == Rule::Average) {
          for (uint32_t k = 0; k < a.view.components; ++k) od[k] = (1 - t) * xd[k] + t * yd[k];
        } else {
          const RuleCallback& fn = merge ? a.rules.mergeFn : a.rules.splitFn;
          if (!fn || !fn(xd, yd, t, od, a.view.components)) return false;
        }
        for (uint32_t k = 0; k < a.view.components; ++k) writeValue(a.view.type, od[k], out + k * w);
        return true;
      }
    }
    return false;
  }

  // Values computed before an edit and written after it: (attribute, element id or edge,
  // bytes). Kept in a small list; an edit makes a handful.
  struct Pending {
    size_t attr;
    uint32_t id;       // vertex or triangle id; for edges kInvalid
    uint32_t u, v;     // the edge (for Element::Edge)
    size_t offset;     // into bytes
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
        refusal = detail::format("attribute \"%s\" refuses to %s the values", a.name.c_str(), merge ? "merge" : "split");
        return false;
      }
      STLTOPO_TRY {
        list.push_back(Pending{ai, id, u, v, off});
      } STLTOPO_CATCH {
        oom = true;
        return false;
      }
      return true;
    }
    Status status() const { return oom ? detail::oom(kEditArrays) : refused(refusal); }
  };
  static void writePending(M& m, const PendingWrites& pw) {
    for (const Pending& p : pw.list) {
      Attribute& a = m.attributes_[p.attr];
      const uint8_t* src = pw.bytes.data() + p.offset;
      if (a.view.element != Element::Edge) {
        std::memcpy(at(a, p.id), src, stride(a));
        continue;
      }
      // Every pair of the edge (one, unless the edge is cut).
      forEachEdgeSide(m, p.u, p.v, [&](uint32_t s) {
        uint32_t h = m.sideHalfedge_[s];
        std::memcpy(at(a, h >> 1), src, stride(a));
      });
    }
  }

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
    if (p != kInvalid) m.cornerNext_[p] = n; else m.vertexCorner_[v] = n;
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
  static bool reserve(M& m, uint32_t newVertices) {
    const size_t R = m.chRemoved_.size(), W = m.chRewritten_.size(), A = m.chAdded_.size() / 3;
    const size_t nv = size_t(m.nVertices()) + newVertices, nt = size_t(m.nTriangles()) + A;
    if (!growTo(m.positions_, 3 * nv) || !growTo(m.vertexDead_, nv) || !growTo(m.vertexCorner_, nv) ||
        !growTo(m.vertexCornerCount_, nv) || !growTo(m.vertexHalfedge_, nv) || !growTo(m.vertexNonManifold_, nv) ||
        !growTo(m.stamp_, nv) || !reserveAttributes(m, Element::Vertex, nv))
      return false;
    if (!growTo(m.triangles_, 3 * nt) || !growTo(m.degenerate_, nt) || !growTo(m.cornerNext_, 3 * nt) ||
        !growTo(m.cornerPrev_, 3 * nt) || !growTo(m.sideHalfedge_, 3 * nt) || !growTo(m.triangleHalfedge_, nt) || !growTo(m.triStamp_, nt) ||
        !reserveAttributes(m, Element::Triangle, nt))
      return false;
    const size_t np = m.pairKind_.size() + 3 * (A + W);
    if (!growTo(m.next_, 2 * np) || !growTo(m.prev_, 2 * np) || !growTo(m.vert_, 2 * np) || !growTo(m.face_, 2 * np) ||
        !growTo(m.pairKind_, np) || !growTo(m.freePairs_, np) || !reserveAttributes(m, Element::Edge, np))
      return false;
    // Sides on the touched edges: at most the corners at the touched vertices.
    size_t corners = 0;
    auto count = [&](uint32_t v) { corners += m.vertexCornerCount_[v] + 3; };
    for (size_t i = 0; i < R; ++i)
      for (int c = 0; c < 3; ++c) count(m.triangles_[3 * size_t(m.chRemoved_[i]) + c]);
    for (size_t i = 0; i < W; ++i)
      for (int c = 0; c < 3; ++c) {
        count(m.triangles_[3 * size_t(m.chRewritten_[i]) + c]);
        uint32_t v = m.chRewrittenCorners_[3 * i + c];
        if (v < m.nVertices()) count(v);
      }
    for (size_t i = 0; i < 3 * A; ++i)
      if (m.chAdded_[i] < m.nVertices()) count(m.chAdded_[i]);
    corners += 3 * (A + W) + 3 * newVertices;
    const size_t n3 = 3 * (R + W + A);
    return growTo(m.touchedVertices_, n3 + 3 * W + newVertices) && growTo(m.touchedEdges_, n3 + 3 * W) &&
           growTo(m.detached_, n3) && growTo(m.dirtyTriangles_, corners + R + W + A) && growTo(m.sides_, corners) &&
           growTo(m.oldSlots_, 2 * corners) && growTo(m.claimed_, 2 * corners) && growTo(m.pairs_, 3 * corners);
  }
  static void clearChange(M& m) {
    m.chRemoved_.clear();
    m.chRewritten_.clear();
    m.chRewrittenCorners_.clear();
    m.chAdded_.clear();
  }
  // Appends a vertex (capacity reserved).
  static uint32_t appendVertex(M& m, const float* p) {
    uint32_t v = m.nVertices();
    size_t n = m.positions_.size();
    (void)m.positions_.resize(n + 3);
    std::memcpy(m.positions_.data() + n, p, 3 * sizeof(float));
    (void)m.vertexDead_.resize(v + 1);
    (void)m.vertexCorner_.resize(v + 1);
    (void)m.vertexCornerCount_.resize(v + 1);
    (void)m.vertexHalfedge_.resize(v + 1);
    (void)m.vertexNonManifold_.resize(v + 1);
    (void)m.stamp_.resize(v + 1);
    m.vertexDead_[v] = 0;
    m.vertexCorner_[v] = kInvalid;
    m.vertexCornerCount_[v] = 0;
    m.vertexHalfedge_[v] = kInvalid;
    m.vertexNonManifold_[v] = 0;
    m.stamp_[v] = 0;
    appendDefaults(m, Element::Vertex);
    ++m.nLiveVertices_;
    m.statsStale_ = true;
    return v;
  }
  static uint32_t newPairSlot(M& m) {
    uint32_t k;
    if (!m.freePairs_.empty()) {
      k = m.freePairs_[m.freePairs_.size() - 1];
      m.freePairs_.shrink(m.freePairs_.size() - 1);
    } else {
      k = uint32_t(m.pairKind_.size());
      (void)m.pairKind_.resize(k + 1);
      (void)m.next_.resize(2 * size_t(k) + 2);
      (void)m.prev_.resize(2 * size_t(k) + 2);
      (void)m.vert_.resize(2 * size_t(k) + 2);
      (void)m.face_.resize(2 * size_t(k) + 2);
      appendDefaults(m, Element::Edge);
    }
    ++m.nLivePairs_;
    return k;
  }
  static void freePairSlot(M& m, uint32_t k) {
    for (uint32_t e = 2 * k; e < 2 * k + 2; ++e) m.next_[e] = m.prev_[e] = m.vert_[e] = m.face_[e] = kInvalid;
    m.pairKind_[k] = 0;
    (void)m.freePairs_.push_back(k);  // capacity reserved: the list never holds more than all slots
    --m.nLivePairs_;
  }

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

  // Carries out the change (capacity reserved by reserve()). Returns the id of the first
  // added triangle (the others follow).
  static uint32_t apply(M& m) {
    newEpoch(m);
    m.touchedVertices_.clear();
    m.touchedEdges_.clear();
    m.detached_.clear();
    m.dirtyTriangles_.clear();
    uint32_t* tri = m.triangles_.data();
    auto detach = [&](uint32_t t) {
      if (!m.degenerate_[t]) {
        for (uint32_t c = 0; c < 3; ++c) {
          uint32_t s = 3 * t + c, a = tri[s], b = tri[3 * t + nextCorner(c)];
          (void)m.detached_.push_back(M::Detached{edgeKey(a, b), m.sideHalfedge_[s], a < b ? 1u : 0u});
          (void)m.touchedEdges_.push_back(edgeKey(a, b));
          m.sideHalfedge_[s] = kInvalid;
        }
      } else {
        --m.nDegenerate_;
      }
      for (uint32_t c = 0; c < 3; ++c) {
        unlink(m, 3 * t + c);
        touch(m, tri[3 * t + c]);
      }
      m.triangleHalfedge_[t] = kInvalid;
    };
    auto attach = [&](uint32_t t) {
      uint32_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
      bool deg = a == b || b == c || a == c;
      m.degenerate_[t] = deg ? 1 : 0;
      if (deg) ++m.nDegenerate_;
      for (uint32_t k = 0; k < 3; ++k) {
        link(m, 3 * t + k);
        touch(m, tri[3 * t + k]);
        m.sideHalfedge_[3 * t + k] = kInvalid;
        if (!deg) (void)m.touchedEdges_.push_back(edgeKey(tri[3 * t + k], tri[3 * t + nextCorner(k)]));
      }
      m.triangleHalfedge_[t] = kInvalid;
      (void)m.dirtyTriangles_.push_back(t);
    };
    for (uint32_t t : m.chRemoved_) {
      detach(t);
      tri[3 * t] = tri[3 * t + 1] = tri[3 * t + 2] = kInvalid;
      m.degenerate_[t] = 0;
      --m.nLiveTriangles_;
    }
    for (size_t i = 0; i < m.chRewritten_.size(); ++i) {
      uint32_t t = m.chRewritten_[i];
      detach(t);
      for (uint32_t c = 0; c < 3; ++c) tri[3 * t + c] = m.chRewrittenCorners_[3 * i + c];
    }
    for (size_t i = 0; i < m.chRewritten_.size(); ++i) attach(m.chRewritten_[i]);
    const uint32_t firstAdded = m.nTriangles();
    for (size_t i = 0; i < m.chAdded_.size(); i += 3) {
      uint32_t t = m.nTriangles();
      (void)m.triangles_.resize(3 * size_t(t) + 3);
      (void)m.degenerate_.resize(t + 1);
      (void)m.cornerNext_.resize(3 * size_t(t) + 3);
      (void)m.cornerPrev_.resize(3 * size_t(t) + 3);
      (void)m.sideHalfedge_.resize(3 * size_t(t) + 3);
      (void)m.triangleHalfedge_.resize(t + 1);
      (void)m.triStamp_.resize(t + 1);
      m.triStamp_[t] = 0;
      tri = m.triangles_.data();
      for (uint32_t c = 0; c < 3; ++c) tri[3 * t + c] = m.chAdded_[i + c];
      appendDefaults(m, Element::Triangle);
      ++m.nLiveTriangles_;
      attach(t);
    }
    // Re-pair every touched edge, in edge order, with its detached sides.
    std::sort(m.detached_.begin(), m.detached_.end(),
              [](const M::Detached& x, const M::Detached& y) { return x.edge < y.edge; });
    std::sort(m.touchedEdges_.begin(), m.touchedEdges_.end());
    size_t d = 0;
    for (size_t i = 0; i < m.touchedEdges_.size(); ++i) {
      uint64_t key = m.touchedEdges_[i];
      if (i > 0 && key == m.touchedEdges_[i - 1]) continue;
      while (d < m.detached_.size() && m.detached_[d].edge < key) ++d;
      size_t d1 = d;
      while (d1 < m.detached_.size() && m.detached_[d1].edge == key) ++d1;
      repair(m, uint32_t(key >> 32), uint32_t(key), d, d1);
      d = d1;
    }
    // Triangle next/prev for every triangle with a new half-edge.
    for (uint32_t t : m.dirtyTriangles_) {
      if (tri[3 * t] == kInvalid || m.degenerate_[t]) continue;
      const uint32_t* h = m.sideHalfedge_.data() + 3 * size_t(t);
      for (uint32_t c = 0; c < 3; ++c) {
        m.next_[h[c]] = h[nextCorner(c)];
        m.prev_[h[c]] = h[prevCorner(c)];
      }
      m.triangleHalfedge_[t] = h[0];
    }
    for (uint32_t v : m.touchedVertices_) refan(m, v);
    m.loopsStale_ = m.statsStale_ = true;
    clearChange(m);
    return firstAdded;
  }

  // Pairs the sides of edge (lo, hi) by buildTopology's rule; [d0, d1) are the edge's
  // detached sides (their old half-edges).
  static void repair(M& m, uint32_t lo, uint32_t hi, size_t d0, size_t d1) {
    const uint32_t* tri = m.triangles_.data();
    m.sides_.clear();
    forEachEdgeSide(m, lo, hi, [&](uint32_t s) { (void)m.sides_.push_back(s); });
    std::sort(m.sides_.begin(), m.sides_.end());
    // The edge before the change: surviving sides and detached sides.
    m.oldSlots_.clear();
    auto addSlot = [&](uint32_t k) {
      for (uint32_t x : m.oldSlots_)
        if (x == k) return;
      (void)m.oldSlots_.push_back(k);
    };
    uint32_t mOld = 0, lhOld = 0, lhNew = 0;
    for (uint32_t s : m.sides_) {
      lhNew += tri[s] == lo ? 1 : 0;
      uint32_t h = m.sideHalfedge_[s];
      if (h == kInvalid) continue;
      ++mOld;
      lhOld += tri[s] == lo ? 1 : 0;
      addSlot(h >> 1);
    }
    for (size_t i = d0; i < d1; ++i) {
      ++mOld;
      lhOld += m.detached_[i].lowToHigh;
      addSlot(m.detached_[i].he >> 1);
    }
    const uint32_t mNew = uint32_t(m.sides_.size());
    countEdge(m, classify(mOld, lhOld), -1);
    const EdgeClass cls = classify(mNew, lhNew);
    countEdge(m, cls, +1);
    // The pairs: (a, b or kInvalid, kind).
    m.pairs_.clear();
    auto pair = [&](uint32_t a, uint32_t b, EdgeKind k) {
      (void)m.pairs_.push_back(a);
      (void)m.pairs_.push_back(b);
      (void)m.pairs_.push_back(uint32_t(k));
    };
    const uint32_t* S = m.sides_.data();
    if (mNew == 1) {
      pair(S[0], kInvalid, EdgeKind::Boundary);
    } else if (mNew == 2) {
      if (cls == EdgeClass::Interior) {
        pair(S[0], S[1], EdgeKind::Interior);
      } else {
        pair(S[0], kInvalid, EdgeKind::Inconsistent);
        pair(S[1], kInvalid, EdgeKind::Inconsistent);
      }
    } else if (mNew >= 3) {
      // First unpaired with first unpaired, opposite directions, in side order. claimed_
      // marks the sides paired so far (reused as a flag per side index here).
      m.claimed_.clear();
      for (uint32_t i = 0; i < mNew; ++i) (void)m.claimed_.push_back(0);
      for (uint32_t i = 0; i < mNew; ++i) {
        bool di = tri[S[i]] == lo;
        for (uint32_t j = 0; j < i; ++j) {
          if (m.claimed_[j] || (tri[S[j]] == lo) == di) continue;
          m.claimed_[i] = m.claimed_[j] = 1;
          pair(S[j], S[i], EdgeKind::NonManifold);
          break;
        }
      }
      for (uint32_t i = 0; i < mNew; ++i)
        if (!m.claimed_[i]) pair(S[i], kInvalid, EdgeKind::NonManifold);
    }
    // Slots: a pair keeps the slot of its first side's half-edge, else of its second's,
    // else takes an old slot of this edge, else a new one.
    m.claimed_.clear();
    for (size_t i = 0; i < m.oldSlots_.size(); ++i) (void)m.claimed_.push_back(0);
    auto claimIfOld = [&](uint32_t k) {
      for (size_t i = 0; i < m.oldSlots_.size(); ++i)
        if (m.oldSlots_[i] == k) {
          if (m.claimed_[i]) return false;
          m.claimed_[i] = 1;
          return true;
        }
      return false;
    };
    auto setSide = [&](uint32_t s, uint32_t e) {
      if (m.sideHalfedge_[s] != e) (void)m.dirtyTriangles_.push_back(s / 3);
      m.sideHalfedge_[s] = e;
      m.vert_[e] = tri[s];
      m.face_[e] = s / 3;
    };
    for (size_t p = 0; p < m.pairs_.size(); p += 3) {
      uint32_t a = m.pairs_[p], b = m.pairs_[p + 1];
      EdgeKind kind = EdgeKind(m.pairs_[p + 2]);
      uint32_t ha = m.sideHalfedge_[a], hb = b == kInvalid ? kInvalid : m.sideHalfedge_[b];
      uint32_t ea = kInvalid;
      if (ha != kInvalid && claimIfOld(ha >> 1)) {
        ea = ha;
      } else if (hb != kInvalid && claimIfOld(hb >> 1)) {
        ea = hb ^ 1u;
      } else {
        for (size_t i = 0; i < m.oldSlots_.size() && ea == kInvalid; ++i)
          if (!m.claimed_[i]) {
            m.claimed_[i] = 1;
            ea = 2 * m.oldSlots_[i];
          }
        if (ea == kInvalid) {
          uint32_t k = newPairSlot(m);
          ea = 2 * k;
          if (!m.oldSlots_.empty()) copySlot(m, Element::Edge, m.oldSlots_[0], k);
          else resetDefault(m, Element::Edge, k);
        }
      }
      setSide(a, ea);
      uint32_t eb = ea ^ 1u;
      if (b != kInvalid) {
        setSide(b, eb);
      } else {
        m.vert_[eb] = sideDst(m, a);
        m.face_[eb] = kStaleLoopFace;
        m.next_[eb] = m.prev_[eb] = kInvalid;  // linked by refan()
      }
      m.pairKind_[ea >> 1] = uint8_t(kind);
    }
    for (size_t i = 0; i < m.oldSlots_.size(); ++i)
      if (!m.claimed_[i]) freePairSlot(m, m.oldSlots_[i]);
  }

  // The boundary next pointers into u by the fan rule, u's outgoing half-edge (the
  // lowest-id boundary one, else the lowest-id one) and its non-manifold flag.
  static void refan(M& m, uint32_t u) {
    uint32_t deg = 0, bestBoundary = kInvalid, bestAny = kInvalid;
    const uint32_t bound = m.vertexCornerCount_[u] + 1;
    forEachCorner(m, u, [&](uint32_t q) {
      uint32_t t = q / 3, c = q % 3;
      if (m.degenerate_[t]) return;
      uint32_t hOut = m.sideHalfedge_[q], hIn = m.sideHalfedge_[3 * t + prevCorner(c)];
      ++deg;
      bestAny = std::min(bestAny, hOut);
      if (boundaryFace(m.face_[hIn ^ 1u])) {
        ++deg;
        bestBoundary = std::min(bestBoundary, hIn ^ 1u);
      }
      if (boundaryFace(m.face_[hOut ^ 1u])) {
        uint32_t b = hOut ^ 1u, x = hOut;
        for (uint32_t steps = 0; steps <= bound; ++steps) {
          uint32_t p = m.next_[m.next_[x]];  // the triangle half-edge into u before x
          if (boundaryFace(m.face_[p ^ 1u])) {
            m.next_[b] = p ^ 1u;
            m.prev_[p ^ 1u] = b;
            break;
          }
          x = p ^ 1u;
        }
      }
    });
    uint32_t vh = bestBoundary != kInvalid ? bestBoundary : bestAny;
    m.vertexHalfedge_[u] = vh;
    uint8_t nm = 0;
    if (vh != kInvalid) {
      uint32_t x = vh, n = 0;
      do {
        x = m.next_[x ^ 1u];
        ++n;
      } while (x != vh && n <= deg);
      nm = n != deg ? 1 : 0;
    }
    m.nNonManifoldVertices_ += nm;
    m.nNonManifoldVertices_ -= m.vertexNonManifold_[u];
    m.vertexNonManifold_[u] = nm;
  }

  // ------------------------------------------------------------------------ loops, shells
  // Numbers the boundary loops as buildTopology would on the compacted mesh: in order of
  // their earliest triangle side, each from the twin of that side. faceOut (nullable)
  // receives kLoopFaceBit | loop for each boundary half-edge.
  static bool labelLoops(const M& m, EditLoops& out, uint32_t* faceOut) {
    out = EditLoops{};
    Array<uint64_t> seen;
    if (!seen.assign((size_t(m.nHalfedges()) + 63) / 64, 0) || !out.loopOffsets.push_back(0)) return false;
    const uint32_t nt = m.nTriangles();
    for (uint32_t t = 0; t < nt; ++t) {
      if (!m.triangleAlive(t) || m.degenerate_[t]) continue;
      for (uint32_t c = 0; c < 3; ++c) {
        uint32_t e = m.sideHalfedge_[3 * t + c] ^ 1u;
        if (!boundaryFace(m.face_[e]) || ((seen[e >> 6] >> (e & 63)) & 1u)) continue;
        uint32_t id = out.nLoops();
        bool seam = false;
        double perim = 0;
        uint32_t x = e;
        do {
          seen[x >> 6] |= uint64_t(1) << (x & 63);
          if (faceOut) faceOut[x] = kLoopFaceBit | id;
          if (!out.loopHalfedges.push_back(x)) return false;
          if (m.pairKind_[x >> 1] != uint8_t(EdgeKind::Boundary)) seam = true;
          const float* a = m.positions_.data() + size_t(m.vert_[x]) * 3;
          const float* b = m.positions_.data() + size_t(m.vert_[x ^ 1u]) * 3;
          double dx = double(a[0]) - b[0], dy = double(a[1]) - b[1], dz = double(a[2]) - b[2];
          perim += std::sqrt(dx * dx + dy * dy + dz * dz);
          x = m.next_[x];
        } while (x != e);
        if (!out.loopHalfedge.push_back(e) || !out.loopOffsets.push_back(uint32_t(out.loopHalfedges.size())) ||
            !out.loopIsSeam.push_back(seam ? 1 : 0) || !out.loopPerimeter.push_back(perim))
          return false;
      }
    }
    return true;
  }

  // Edge-connected components of the live non-degenerate triangles (every shared edge
  // counts, paired or cut). kInvalid on allocation failure.
  static uint32_t countShells(const M& m) {
    const uint32_t nt = m.nTriangles();
    Array<uint32_t> parent;
    if (!parent.resize(nt)) return kInvalid;
    for (uint32_t t = 0; t < nt; ++t) parent[t] = t;
    auto find = [&](uint32_t x) {
      while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
      }
      return x;
    };
    auto unite = [&](uint32_t a, uint32_t b) {
      a = find(a);
      b = find(b);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    };
    for (uint32_t k = 0; k < m.pairKind_.size(); ++k) {
      uint32_t e = 2 * k;
      if (m.vert_[e] == kInvalid) continue;
      uint32_t f0 = m.face_[e], f1 = m.face_[e + 1];
      if (!(f0 & kLoopFaceBit) && !(f1 & kLoopFaceBit)) unite(f0, f1);
      if (m.pairKind_[k] == uint8_t(EdgeKind::Inconsistent) || m.pairKind_[k] == uint8_t(EdgeKind::NonManifold)) {
        uint32_t t0 = (f0 & kLoopFaceBit) ? f1 : f0;
        forEachEdgeSide(m, m.vert_[e], m.vert_[e + 1], [&](uint32_t s) { unite(t0, s / 3); });
      }
    }
    uint32_t n = 0;
    for (uint32_t t = 0; t < nt; ++t)
      if (m.triangleAlive(t) && !m.degenerate_[t] && find(t) == t) ++n;
    return n;
  }

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

  // A triangle attribute's bytes of triangle t / vertex v / pair k.
  static const uint8_t* valueOf(const M& m, size_t ai, uint32_t id) {
    const Attribute& a = m.attributes_[ai];
    return a.bytes.data() + size_t(id) * stride(a);
  }
};

using Impl = EditableMesh::Impl;

// ============================================================================ init

Status EditableMesh::init(const Mesh& mesh, const TopologyOptions& options) {
  Topology topo;
  TopologyOptions o = options;
  o.prevAndFace = true;
  Status s = buildTopology(mesh, topo, o);
  if (!s.ok()) {
    *this = EditableMesh{};
    return s;
  }
  return init(mesh, topo);
}

Status EditableMesh::init(const Mesh& mesh, const Topology& topo) {
  *this = EditableMesh{};
  const uint32_t nt = mesh.nTriangles(), nv = mesh.nVertices(), nh = topo.nHalfedges();
  if (topo.nTriangles != nt || topo.nVertices != nv || topo.vertexWeld.size() != nv ||
      topo.triangleDegenerate.size() != nt)
    return badArgument("the topology was not built from this mesh");
  if (nh > 0 && (topo.prev.size() != nh || topo.face.size() != nh))
    return badArgument("the topology has no prev and face (TopologyOptions::prevAndFace = false)");
  auto fail = [&]() {
    *this = EditableMesh{};
    return detail::oom(kEditArrays);
  };
  if (!positions_.resize(size_t(nv) * 3) || !triangles_.resize(size_t(nt) * 3) || !vertexDead_.assign(nv, 0) ||
      !degenerate_.resize(nt) || !cornerNext_.resize(size_t(nt) * 3) || !cornerPrev_.resize(size_t(nt) * 3) ||
      !vertexCorner_.assign(nv, kInvalid) || !vertexCornerCount_.assign(nv, 0) || !sideHalfedge_.assign(size_t(nt) * 3, kInvalid) ||
      !next_.resize(nh) || !prev_.resize(nh) || !vert_.resize(nh) || !face_.resize(nh) || !pairKind_.resize(nh / 2) ||
      !triangleHalfedge_.resize(nt) || !vertexHalfedge_.resize(nv) || !vertexNonManifold_.resize(nv) ||
      !stamp_.assign(nv, 0) || !triStamp_.assign(nt, 0))
    return fail();
  if (nv > 0) std::memcpy(positions_.data(), mesh.positions.data(), size_t(nv) * 3 * sizeof(float));
  for (size_t i = 0; i < size_t(nt) * 3; ++i) triangles_[i] = topo.vertexWeld[mesh.triangles[i]];
  for (uint32_t t = 0; t < nt; ++t) degenerate_[t] = topo.triangleDegenerate[t];
  for (uint32_t q = 3 * nt; q-- > 0;) Impl::link(*this, q);
  if (nh > 0) {
    std::memcpy(next_.data(), topo.next.data(), size_t(nh) * 4);
    std::memcpy(prev_.data(), topo.prev.data(), size_t(nh) * 4);
    std::memcpy(vert_.data(), topo.vert.data(), size_t(nh) * 4);
    std::memcpy(pairKind_.data(), topo.pairKind.data(), nh / 2);
  }
  for (uint32_t e = 0; e < nh; ++e) face_[e] = topo.face[e] < nt ? topo.face[e] : (kLoopFaceBit | (topo.face[e] - nt));
  for (uint32_t t = 0; t < nt; ++t) {
    uint32_t h = topo.triangleHalfedge[t];
    triangleHalfedge_[t] = h;
    if (h == kInvalid) continue;
    for (uint32_t c = 0; c < 3; ++c, h = topo.next[h]) sideHalfedge_[3 * t + c] = h;
  }
  for (uint32_t v = 0; v < nv; ++v) {
    vertexHalfedge_[v] = topo.vertexHalfedge[v];
    vertexNonManifold_[v] = topo.vertexNonManifold[v];
  }
  nLiveTriangles_ = nt;
  nLiveVertices_ = nv;
  nLivePairs_ = nh / 2;
  nDegenerate_ = topo.nDegenerate;
  nEdges_ = topo.nEdges;
  nBoundaryEdges_ = topo.nBoundaryEdges;
  nNonManifoldEdges_ = topo.nNonManifoldEdges;
  nInconsistentEdges_ = topo.nInconsistentEdges;
  nNonManifoldVertices_ = topo.nNonManifoldVertices;
  // The loops as the topology numbered them.
  auto copyArray = [](auto& dst, const auto& src) {
    if (!dst.resize(src.size())) return false;
    if (src.size() > 0) std::memcpy(dst.data(), src.data(), src.size() * sizeof(src[0]));
    return true;
  };
  if (!copyArray(loops_.loopHalfedge, topo.loopHalfedge) || !copyArray(loops_.loopOffsets, topo.loopOffsets) ||
      !copyArray(loops_.loopHalfedges, topo.loopHalfedges) || !copyArray(loops_.loopIsSeam, topo.loopIsSeam) ||
      !copyArray(loops_.loopPerimeter, topo.loopPerimeter))
    return fail();
  loopsStale_ = false;
  statsStale_ = true;
  format_ = mesh.format;
  colorConvention_ = mesh.colorConvention;
  STLTOPO_TRY {
    solids_ = mesh.solids;
    warnings_ = mesh.warnings;
  } STLTOPO_CATCH {
    return fail();
  }
  // The file's per-triangle data as triangle attributes.
  Status s = addAttribute(kAttrWord, Element::Triangle, ValueType::U16, 1,
                          mesh.attributes.size() == nt ? mesh.attributes.data() : nullptr);
  if (s.ok() && mesh.colorConvention != ColorConvention::None && mesh.colors.size() == size_t(nt) * 3 &&
      mesh.colorValid.size() == nt) {
    s = addAttribute(kAttrColor, Element::Triangle, ValueType::U8, 3, mesh.colors.data());
    if (s.ok()) s = addAttribute(kAttrColorValid, Element::Triangle, ValueType::U8, 1, mesh.colorValid.data());
  }
  if (s.ok() && mesh.normals.size() == size_t(nt) * 3 && nt > 0)
    s = addAttribute(kAttrNormal, Element::Triangle, ValueType::F32, 3, mesh.normals.data());
  if (!s.ok()) return fail();
  return Status{};
}

// ============================================================================ attributes

Status EditableMesh::addAttribute(const std::string& name, Element element, ValueType type, uint32_t components,
                                  const void* values, const AttributeRules& rules, const double* defaultValue) {
  if (name.empty()) return badArgument("an attribute needs a name");
  if (components == 0 || components > kMaxComponents)
    return badArgument(detail::format("an attribute has 1 to %u components, not %u", kMaxComponents, components));
  if ((rules.merge == Rule::Custom && !rules.mergeFn) || (rules.split == Rule::Custom && !rules.splitFn))
    return badArgument("a custom rule needs its callback");
  STLTOPO_TRY {
    Attribute a;
    a.name = name;
    a.view.element = element;
    a.view.type = type;
    a.view.components = components;
    a.rules = rules;
    a.defaultValue.assign(components, 0.0);
    if (defaultValue)
      for (uint32_t k = 0; k < components; ++k) a.defaultValue[k] = defaultValue[k];
    const size_t n = Impl::elementCount(*this, element), s = Impl::stride(a);
    if (!a.bytes.resize(n * s)) return detail::oom(kEditArrays);
    if (values && n > 0) {
      std::memcpy(a.bytes.data(), values, n * s);
    } else {
      for (size_t i = 0; i < n; ++i) Impl::writeDefault(a, a.bytes.data() + i * s);
    }
    a.view.data = a.bytes.data();
    a.view.count = n;
    for (Attribute& x : attributes_)
      if (x.name == name) {
        x = std::move(a);
        x.view.data = x.bytes.data();
        return Status{};
      }
    attributes_.push_back(std::move(a));
    attributes_.back().view.data = attributes_.back().bytes.data();
  } STLTOPO_CATCH {
    return detail::oom(kEditArrays);
  }
  return Status{};
}

const AttributeView* EditableMesh::attribute(const std::string& name) const {
  for (const Attribute& a : attributes_)
    if (a.name == name) {
      // data and count follow the slot arrays (the bytes may have moved since).
      AttributeView& v = const_cast<AttributeView&>(a.view);
      v.data = const_cast<uint8_t*>(a.bytes.data());
      v.count = a.bytes.size() / Impl::stride(a);
      return &a.view;
    }
  return nullptr;
}

bool EditableMesh::removeAttribute(const std::string& name) {
  for (size_t i = 0; i < attributes_.size(); ++i)
    if (attributes_[i].name == name) {
      attributes_.erase(attributes_.begin() + long(i));
      return true;
    }
  return false;
}

std::vector<std::string> EditableMesh::attributeNames() const {
  std::vector<std::string> out;
  for (const Attribute& a : attributes_) out.push_back(a.name);
  return out;
}

// ============================================================================ reading

const EditLoops& EditableMesh::loops() {
  if (loopsStale_) {
    if (!Impl::labelLoops(*this, loops_, face_.data())) {
      loops_ = EditLoops{};  // out of memory: no loops listed; stays stale
      return loops_;
    }
    loopsStale_ = false;
  }
  return loops_;
}

uint32_t EditableMesh::face(uint32_t e) {
  if (Impl::boundaryFace(face_[e])) loops();
  return face_[e];
}

const EditStats& EditableMesh::stats() {
  if (!statsStale_) return stats_;
  EditStats s;
  s.triangles = nLiveTriangles_;
  s.degenerate = nDegenerate_;
  for (uint32_t v = 0; v < nVertices(); ++v) {
    if (vertexCornerCount_[v] > 0) ++s.vertices;
    if (vertexHalfedge_[v] != kInvalid) ++s.usedVertices;
  }
  s.edges = nEdges_;
  s.boundaryEdges = nBoundaryEdges_;
  s.nonManifoldEdges = nNonManifoldEdges_;
  s.inconsistentEdges = nInconsistentEdges_;
  s.nonManifoldVertices = nNonManifoldVertices_;
  const EditLoops& l = loops();
  for (uint32_t h = 0; h < l.nLoops(); ++h) (l.loopIsSeam[h] ? s.seams : s.holes) += 1;
  uint32_t shells = Impl::countShells(*this);
  s.shells = shells == kInvalid ? 0 : shells;
  s.eulerCharacteristic = int64_t(s.usedVertices) - int64_t(s.edges) + int64_t(s.triangles - s.degenerate);
  s.watertight = s.triangles > s.degenerate && s.boundaryEdges == 0 && s.nonManifoldEdges == 0 && s.inconsistentEdges == 0;
  s.manifold = s.nonManifoldEdges == 0 && s.nonManifoldVertices == 0;
  stats_ = s;
  statsStale_ = shells == kInvalid || loopsStale_;
  return stats_;
}

std::string EditableMesh::infoJson(const std::string& file) {
  Mesh m;
  Topology t;
  if (!toMesh(m, &t).ok()) return "";
  return stltopo::infoJson(file, m, &t);
}

// ============================================================================ output

Status EditableMesh::toMesh(Mesh& out, Topology* topo, CompactMaps* maps) const {
  out = Mesh{};
  CompactMaps local;
  CompactMaps& mp = maps ? *maps : local;
  mp = CompactMaps{};
  const uint32_t nvSlots = nVertices(), ntSlots = nTriangles(), nhSlots = nHalfedges();
  if (!mp.vertices.assign(nvSlots, kInvalid) || !mp.triangles.assign(ntSlots, kInvalid) ||
      !mp.halfedges.assign(nhSlots, kInvalid))
    return detail::oom(kEditArrays);
  uint32_t nv = 0, nt = 0;
  for (uint32_t v = 0; v < nvSlots; ++v)
    if (!vertexDead_[v] && vertexCornerCount_[v] > 0) mp.vertices[v] = nv++;
  for (uint32_t t = 0; t < ntSlots; ++t)
    if (triangleAlive(t)) mp.triangles[t] = nt++;
  out.format = format_;
  out.colorConvention = colorConvention_;
  const AttributeView* word = attribute(kAttrWord);
  const AttributeView* color = attribute(kAttrColor);
  const AttributeView* colorValid = attribute(kAttrColorValid);
  const AttributeView* normal = attribute(kAttrNormal);
  if (word && (word->type != ValueType::U16 || word->components != 1)) word = nullptr;
  if (color && (color->type != ValueType::U8 || color->components != 3)) color = nullptr;
  if (colorValid && (colorValid->type != ValueType::U8 || colorValid->components != 1)) colorValid = nullptr;
  if (normal && (normal->type != ValueType::F32 || normal->components != 3)) normal = nullptr;
  const bool colors = colorConvention_ != ColorConvention::None && color && colorValid;
  if (!colors) out.colorConvention = ColorConvention::None;
  if (!out.positions.resize(size_t(nv) * 3) || !out.triangles.resize(size_t(nt) * 3) || !out.attributes.resize(nt) ||
      (colors && (!out.colors.resize(size_t(nt) * 3) || !out.colorValid.resize(nt))) ||
      (normal && !out.normals.resize(size_t(nt) * 3)))
    return detail::oom(kEditArrays);
  for (uint32_t v = 0; v < nvSlots; ++v) {
    uint32_t w = mp.vertices[v];
    if (w == kInvalid) continue;
    std::memcpy(out.positions.data() + 3 * size_t(w), positions_.data() + 3 * size_t(v), 3 * sizeof(float));
    const float* q = positions_.data() + 3 * size_t(v);
    for (int c = 0; c < 3; ++c) {
      if (w == 0 || q[c] < out.bboxMin[c]) out.bboxMin[c] = q[c];
      if (w == 0 || q[c] > out.bboxMax[c]) out.bboxMax[c] = q[c];
    }
  }
  STLTOPO_TRY {
    for (const Solid& s : solids_) {
      Solid o;
      o.name = s.name;
      out.solids.push_back(std::move(o));
    }
    if (out.solids.empty() && nt > 0) out.solids.push_back(Solid{});
    out.warnings = warnings_;
  } STLTOPO_CATCH {
    return detail::oom(kEditArrays);
  }
  size_t solid = 0;
  for (uint32_t t = 0; t < ntSlots; ++t) {
    uint32_t w = mp.triangles[t];
    if (w == kInvalid) continue;
    while (solid + 1 < solids_.size() && solids_[solid + 1].firstTriangle <= t) ++solid;
    ++out.solids[solid].triangleCount;
    const float* P[3];
    for (int c = 0; c < 3; ++c) {
      uint32_t v = triangles_[3 * size_t(t) + c];
      out.triangles[3 * size_t(w) + c] = mp.vertices[v];
      P[c] = positions_.data() + 3 * size_t(v);
    }
    out.attributes[w] = word ? static_cast<const uint16_t*>(word->data)[t] : 0;
    if (colors) {
      std::memcpy(out.colors.data() + 3 * size_t(w), static_cast<const uint8_t*>(color->data) + 3 * size_t(t), 3);
      out.colorValid[w] = static_cast<const uint8_t*>(colorValid->data)[t];
    }
    // Figures, as the reader computes them.
    double ax = P[0][0], ay = P[0][1], az = P[0][2], bx = P[1][0], by = P[1][1], bz = P[1][2];
    double cx = P[2][0], cy = P[2][1], cz = P[2][2];
    double ux = bx - ax, uy = by - ay, uz = bz - az, wx = cx - ax, wy = cy - ay, wz = cz - az;
    double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
    out.area += 0.5 * std::sqrt(nx * nx + ny * ny + nz * nz);
    out.volume += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0;
    if (normal) {
      const float* n = static_cast<const float*>(normal->data) + 3 * size_t(t);
      std::memcpy(out.normals.data() + 3 * size_t(w), n, 3 * sizeof(float));
      if (n[0] != 0.0f || n[1] != 0.0f || n[2] != 0.0f) {
        double d = double(n[0]) * nx + double(n[1]) * ny + double(n[2]) * nz;
        if (d < 0) ++out.normalMismatches;
      }
    }
  }
  uint32_t first = 0;
  for (Solid& s : out.solids) {
    s.firstTriangle = first;
    first += s.triangleCount;
  }
  // Half-edges: pairs numbered in order of their first side in (triangle, corner) order;
  // that side's half-edge becomes even.
  Array<uint32_t> pairMap;
  Array<uint8_t> openHalf;
  const uint32_t nPairSlots = uint32_t(pairKind_.size());
  if (!pairMap.assign(nPairSlots, kInvalid) || !openHalf.assign(nPairSlots, 0)) return detail::oom(kEditArrays);
  uint32_t nPairs = 0;
  for (uint32_t t = 0; t < ntSlots; ++t) {
    if (!triangleAlive(t) || degenerate_[t]) continue;
    for (uint32_t c = 0; c < 3; ++c) {
      uint32_t h = sideHalfedge_[3 * t + c];
      if (pairMap[h >> 1] != kInvalid) continue;
      pairMap[h >> 1] = nPairs++;
      openHalf[h >> 1] = uint8_t(h & 1u);
    }
  }
  for (uint32_t e = 0; e < nhSlots; ++e)
    if (vert_[e] != kInvalid) mp.halfedges[e] = 2 * pairMap[e >> 1] + ((e & 1u) == openHalf[e >> 1] ? 0u : 1u);
  if (!topo) return Status{};

  Topology& T = *topo;
  T = Topology{};
  const uint32_t nh = 2 * nPairs;
  T.nTriangles = nt;
  T.nVertices = nv;
  // The editable mesh is welded already (a tolerance weld was applied by init()): its
  // compacted form has the exact weld.
  T.tolerance = 0;
  T.nWeldedVertices = nv;
  EditLoops L;
  if (!Impl::labelLoops(*this, L, nullptr)) return detail::oom(kEditArrays);
  Array<uint32_t> loopOf;  // per slot half-edge: its loop (boundary half-edges only)
  if (!loopOf.assign(nhSlots, kInvalid)) return detail::oom(kEditArrays);
  for (uint32_t h = 0; h < L.nLoops(); ++h)
    for (uint32_t i = L.loopOffsets[h]; i < L.loopOffsets[h + 1]; ++i) loopOf[L.loopHalfedges[i]] = h;
  if (!T.next.resize(nh) || !T.prev.resize(nh) || !T.vert.resize(nh) || !T.face.resize(nh) || !T.pairKind.resize(nPairs) ||
      !T.triangleHalfedge.resize(nt) || !T.vertexHalfedge.assign(nv, kInvalid) || !T.vertexWeld.resize(nv) ||
      !T.triangleDegenerate.resize(nt) || !T.vertexNonManifold.resize(nv))
    return detail::oom(kEditArrays);
  for (uint32_t e = 0; e < nhSlots; ++e) {
    uint32_t y = mp.halfedges[e];
    if (y == kInvalid) continue;
    T.next[y] = mp.halfedges[next_[e]];
    T.prev[y] = mp.halfedges[prev_[e]];
    T.vert[y] = mp.vertices[vert_[e]];
    T.face[y] = Impl::boundaryFace(face_[e]) ? nt + loopOf[e] : mp.triangles[face_[e]];
    if (!(y & 1u)) T.pairKind[y >> 1] = pairKind_[e >> 1];
  }
  for (uint32_t t = 0; t < ntSlots; ++t) {
    uint32_t w = mp.triangles[t];
    if (w == kInvalid) continue;
    T.triangleDegenerate[w] = degenerate_[t];
    T.triangleHalfedge[w] = degenerate_[t] ? kInvalid : mp.halfedges[triangleHalfedge_[t]];
  }
  // vertexHalfedge: the lowest-id boundary half-edge leaving the vertex, else the lowest-id
  // half-edge (boundary ids ranked before all others by the top bit).
  for (uint32_t y = 0; y < nh; ++y) {
    uint32_t key = T.face[y] >= nt ? y : (y | 0x80000000u);
    uint32_t& cur = T.vertexHalfedge[T.vert[y]];
    if (cur == kInvalid || key < cur) cur = key;
  }
  for (uint32_t v = 0; v < nv; ++v) {
    if (T.vertexHalfedge[v] != kInvalid) {
      T.vertexHalfedge[v] &= 0x7FFFFFFFu;
      ++T.nUsedVertices;
    }
    T.vertexWeld[v] = v;
  }
  for (uint32_t v = 0; v < nvSlots; ++v)
    if (mp.vertices[v] != kInvalid) T.vertexNonManifold[mp.vertices[v]] = vertexNonManifold_[v];
  if (!T.loopHalfedge.resize(L.nLoops()) || !T.loopHalfedges.resize(L.loopHalfedges.size()) ||
      !T.loopOffsets.resize(L.loopOffsets.size()) || !T.loopIsSeam.resize(L.nLoops()) ||
      !T.loopPerimeter.resize(L.nLoops()))
    return detail::oom(kEditArrays);
  for (uint32_t h = 0; h < L.nLoops(); ++h) {
    T.loopHalfedge[h] = mp.halfedges[L.loopHalfedge[h]];
    T.loopIsSeam[h] = L.loopIsSeam[h];
    T.loopPerimeter[h] = L.loopPerimeter[h];
    (L.loopIsSeam[h] ? T.nSeams : T.nHoles) += 1;
  }
  for (size_t i = 0; i < L.loopHalfedges.size(); ++i) T.loopHalfedges[i] = mp.halfedges[L.loopHalfedges[i]];
  for (size_t i = 0; i < L.loopOffsets.size(); ++i) T.loopOffsets[i] = L.loopOffsets[i];
  T.nEdges = nEdges_;
  T.nBoundaryEdges = nBoundaryEdges_;
  T.nNonManifoldEdges = nNonManifoldEdges_;
  T.nInconsistentEdges = nInconsistentEdges_;
  T.nNonManifoldVertices = nNonManifoldVertices_;
  T.nDegenerate = nDegenerate_;
  uint32_t shells = Impl::countShells(*this);
  if (shells == kInvalid) return detail::oom(kEditArrays);
  T.nShells = shells;
  return Status{};
}

Status EditableMesh::compact(CompactMaps* maps) {
  CompactMaps local;
  CompactMaps& mp = maps ? *maps : local;
  Mesh m;
  Topology t;
  Status s = toMesh(m, &t, &mp);
  if (!s.ok()) return s;
  EditableMesh fresh;
  s = fresh.init(m, t);
  if (!s.ok()) return s;
  // Every attribute, renumbered (init made the file's ones again; these replace them).
  std::vector<Attribute> renumbered;
  STLTOPO_TRY {
    renumbered.resize(attributes_.size());
  } STLTOPO_CATCH {
    return detail::oom(kEditArrays);
  }
  for (size_t i = 0; i < attributes_.size(); ++i) {
    Attribute& a = attributes_[i];
    Attribute& x = renumbered[i];
    const size_t st = Impl::stride(a);
    const Array<uint32_t>* map = nullptr;
    size_t n = 0, step = 1;
    switch (a.view.element) {
      case Element::Vertex: map = &mp.vertices; n = t.nVertices; break;
      case Element::Triangle: map = &mp.triangles; n = t.nTriangles; break;
      case Element::Edge: map = &mp.halfedges; n = t.nHalfedges() / 2; step = 2; break;
    }
    if (!x.bytes.resize(n * st)) return detail::oom(kEditArrays);
    for (size_t i0 = 0; i0 < map->size(); i0 += step) {
      uint32_t y = (*map)[i0];
      if (y != kInvalid) std::memcpy(x.bytes.data() + size_t(y / step) * st, a.bytes.data() + (i0 / step) * st, st);
    }
    STLTOPO_TRY {
      x.name = a.name;
      x.rules = a.rules;
      x.defaultValue = a.defaultValue;
    } STLTOPO_CATCH {
      return detail::oom(kEditArrays);
    }
    x.view = a.view;
    x.view.data = x.bytes.data();
    x.view.count = n;
  }
  fresh.attributes_ = std::move(renumbered);
  *this = std::move(fresh);
  return Status{};
}

// ============================================================================ validate

Status EditableMesh::validate() const {
  auto bad = [](const char* what, uint32_t element) {
    Status s = Status::error(Code::Invalid, detail::format("%s (element %u)", what, element));
    s.element = element;
    return s;
  };
  const uint32_t nt = nTriangles(), nv = nVertices(), nh = nHalfedges();
  uint32_t live = 0, degen = 0;
  for (uint32_t t = 0; t < nt; ++t) {
    if (!triangleAlive(t)) continue;
    ++live;
    for (uint32_t c = 0; c < 3; ++c) {
      uint32_t v = triangles_[3 * size_t(t) + c];
      if (v >= nv || vertexDead_[v]) return bad("triangle uses a dead or out-of-range vertex", t);
    }
    if (degenerate_[t]) {
      ++degen;
      if (triangleHalfedge_[t] != kInvalid) return bad("degenerate triangle has half-edges", t);
      continue;
    }
    for (uint32_t c = 0; c < 3; ++c) {
      uint32_t h = sideHalfedge_[3 * size_t(t) + c];
      if (h >= nh || vert_[h] != triangles_[3 * size_t(t) + c] || face_[h] != t) return bad("side half-edge differs from its side", t);
      if (next_[h] != sideHalfedge_[3 * size_t(t) + nextCorner(c)]) return bad("triangle next differs from its sides", t);
    }
    if (triangleHalfedge_[t] != sideHalfedge_[3 * size_t(t)]) return bad("triangleHalfedge is not side 0", t);
  }
  if (live != nLiveTriangles_ || degen != nDegenerate_) return bad("live or degenerate triangle count differs", live);
  uint32_t liveV = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    if (vertexDead_[v]) {
      if (vertexCorner_[v] != kInvalid) return bad("dead vertex has corners", v);
      continue;
    }
    ++liveV;
    uint32_t n = 0, prev = kInvalid;
    for (uint32_t q = vertexCorner_[v]; q != kInvalid; q = cornerNext_[q]) {
      if (q >= 3 * nt || triangles_[q] != v || cornerPrev_[q] != prev) return bad("corner list is broken", v);
      prev = q;
      if (++n > 3 * nt) return bad("corner list does not end", v);
    }
    if (n != vertexCornerCount_[v]) return bad("corner count differs from the list", v);
  }
  if (liveV != nLiveVertices_) return bad("live vertex count differs", liveV);
  uint32_t livePairs = 0;
  for (uint32_t k = 0; k < pairKind_.size(); ++k) {
    uint32_t e = 2 * k;
    if (vert_[e] == kInvalid) {
      if (vert_[e + 1] != kInvalid || face_[e] != kInvalid) return bad("half a pair is dead", e);
      continue;
    }
    ++livePairs;
    if (Impl::boundaryFace(face_[e]) && Impl::boundaryFace(face_[e + 1])) return bad("pair of two boundary half-edges", e);
    for (uint32_t x = e; x < e + 2; ++x) {
      if (next_[x] >= nh || prev_[next_[x]] != x) return bad("next/prev differ", x);
      if (vert_[next_[x]] != vert_[x ^ 1u]) return bad("vert[next[e]] != vert[twin(e)]", x);
      if (Impl::boundaryFace(face_[x]) != Impl::boundaryFace(face_[next_[x]])) return bad("next leaves the face", x);
    }
  }
  if (livePairs != nLivePairs_) return bad("live pair count differs", livePairs);
  for (uint32_t k : freePairs_)
    if (k >= pairKind_.size() || vert_[2 * k] != kInvalid) return bad("free pair slot is in use", k);
  if (livePairs + freePairs_.size() != pairKind_.size()) return bad("pair slots are lost", livePairs);
  for (const Attribute& a : attributes_)
    if (a.bytes.size() != Impl::elementCount(*this, a.view.element) * Impl::stride(a))
      return bad("attribute length differs from its element count", uint32_t(a.bytes.size()));
  Mesh m;
  Topology t;
  Status s = toMesh(m, &t);
  if (!s.ok()) return s;
  return stltopo::validate(m, t);
}

// ============================================================================ edits

Status EditableMesh::reserve(uint32_t vertices, uint32_t triangles) {
  Impl::clearChange(*this);
  // A change that adds `triangles` triangles reserves the triangle and half-edge arrays.
  for (uint32_t i = 0; i < triangles; ++i)
    for (int c = 0; c < 3; ++c)
      if (!chAdded_.push_back(kInvalid)) {
        Impl::clearChange(*this);
        return detail::oom(kEditArrays);
      }
  bool ok = Impl::reserve(*this, vertices);
  Impl::clearChange(*this);
  return ok ? Status{} : detail::oom(kEditArrays);
}

Status EditableMesh::addVertex(float x, float y, float z, uint32_t* out) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    return Status::error(Code::NonFinite, "a vertex needs finite coordinates");
  if (!Impl::reserve(*this, 1)) return detail::oom(kEditArrays);
  float p[3] = {x, y, z};
  uint32_t v = Impl::appendVertex(*this, p);
  if (out) *out = v;
  return Status{};
}

Status EditableMesh::removeTriangle(uint32_t t) {
  Status s = Impl::checkTriangle(*this, t);
  if (!s.ok()) return s;
  Impl::clearChange(*this);
  if (!chRemoved_.push_back(t) || !Impl::reserve(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  Impl::apply(*this);
  return Status{};
}

Status EditableMesh::addTriangle(uint32_t a, uint32_t b, uint32_t c, uint32_t* out, bool allowNonManifold) {
  const uint32_t v[3] = {a, b, c};
  for (uint32_t x : v) {
    Status s = Impl::checkVertex(*this, x);
    if (!s.ok()) return s;
  }
  if (a == b || b == c || a == c) return refused(detail::format("triangle (%u, %u, %u) would be degenerate", a, b, c));
  if (!allowNonManifold) {
    for (uint32_t k = 0; k < 3; ++k) {
      uint32_t p = v[k], q = v[nextCorner(k)], m = 0, same = 0;
      Impl::forEachEdgeSide(*this, p, q, [&](uint32_t s) {
        ++m;
        if (triangles_[s] == p) ++same;
      });
      if (m >= 2) return refused(detail::format("edge %u-%u has %u sides already: a third would make it non-manifold", p, q, m));
      if (same > 0) return refused(detail::format("edge %u-%u has a side running the same way (%u -> %u): it would become inconsistent", p, q, p, q));
    }
  }
  Impl::clearChange(*this);
  for (uint32_t x : v)
    if (!chAdded_.push_back(x)) {
      Impl::clearChange(*this);
      return detail::oom(kEditArrays);
    }
  if (!Impl::reserve(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  uint32_t t = Impl::apply(*this);
  if (out) *out = t;
  return Status{};
}

Status EditableMesh::flipEdge(uint32_t e) {
  Status s = Impl::checkHalfedge(*this, e);
  if (!s.ok()) return s;
  if (pairKind_[e >> 1] != uint8_t(EdgeKind::Interior) || Impl::boundaryFace(face_[e]) || Impl::boundaryFace(face_[e ^ 1u]))
    return refused(detail::format("half-edge %u is not on an interior manifold edge (a boundary, inconsistent or non-manifold edge cannot be flipped)", e));
  const uint32_t t1 = face_[e], t2 = face_[e ^ 1u];
  uint32_t s1 = kInvalid, s2 = kInvalid;
  for (uint32_t k = 0; k < 3; ++k) {
    if (sideHalfedge_[3 * t1 + k] == e) s1 = 3 * t1 + k;
    if (sideHalfedge_[3 * t2 + k] == (e ^ 1u)) s2 = 3 * t2 + k;
  }
  const uint32_t a = triangles_[s1], b = Impl::sideDst(*this, s1);
  const uint32_t c = Impl::thirdCorner(*this, s1), d = Impl::thirdCorner(*this, s2);
  if (c == d) return refused(detail::format("the two triangles of half-edge %u share all three vertices", e));
  if (Impl::edgeExists(*this, c, d))
    return refused(detail::format("the flipped edge %u-%u exists already", c, d));
  Impl::PendingWrites pw;
  for (size_t ai = 0; ai < attributes_.size(); ++ai) {
    const Attribute& at = attributes_[ai];
    if (at.view.element == Element::Triangle) {
      const uint8_t* x = Impl::valueOf(*this, ai, t1);
      const uint8_t* y = Impl::valueOf(*this, ai, t2);
      if (!pw.add(*this, ai, true, x, y, 0.5, t1) || !pw.add(*this, ai, true, y, x, 0.5, t2)) return pw.status();
    } else if (at.view.element == Element::Edge) {
      if (!pw.add(*this, ai, false, Impl::valueOf(*this, ai, e >> 1), Impl::valueOf(*this, ai, e >> 1), 0.5, kInvalid, c, d))
        return pw.status();
    }
  }
  Impl::clearChange(*this);
  const uint32_t corners[6] = {c, a, d, d, b, c};
  bool ok = chRewritten_.push_back(t1) && chRewritten_.push_back(t2);
  for (uint32_t x : corners) ok = ok && chRewrittenCorners_.push_back(x);
  if (!ok || !Impl::reserve(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  Impl::apply(*this);
  Impl::writePending(*this, pw);
  return Status{};
}

Status EditableMesh::splitEdge(uint32_t e, double t, uint32_t* newVertex) {
  Status s = Impl::checkHalfedge(*this, e);
  if (!s.ok()) return s;
  if (!(t > 0 && t < 1)) return badArgument(detail::format("the split parameter must be strictly between 0 and 1, not %g", t));
  const uint32_t a = vert_[e], b = vert_[e ^ 1u];
  // The sides on the edge, in side order.
  Impl::clearChange(*this);
  Array<uint32_t> sides;
  bool ok = true;
  Impl::forEachEdgeSide(*this, a, b, [&](uint32_t x) { ok = ok && sides.push_back(x); });
  if (!ok) return detail::oom(kEditArrays);
  std::sort(sides.begin(), sides.end());
  const uint32_t m = nVertices();
  Impl::PendingWrites pw;
  for (size_t ai = 0; ai < attributes_.size(); ++ai) {
    const Attribute& at = attributes_[ai];
    if (at.view.element == Element::Vertex) {
      if (!pw.add(*this, ai, false, Impl::valueOf(*this, ai, a), Impl::valueOf(*this, ai, b), t, m)) return pw.status();
    } else if (at.view.element == Element::Edge) {
      const uint8_t* x = Impl::valueOf(*this, ai, e >> 1);
      if (!pw.add(*this, ai, false, x, x, t, kInvalid, a, m) || !pw.add(*this, ai, false, x, x, t, kInvalid, m, b))
        return pw.status();
    } else {
      uint32_t added = nTriangles();
      for (uint32_t x : sides) {
        const uint8_t* y = Impl::valueOf(*this, ai, x / 3);
        if (!pw.add(*this, ai, false, y, y, t, x / 3) || !pw.add(*this, ai, false, y, y, t, added++)) return pw.status();
      }
    }
  }
  for (uint32_t x : sides) {
    uint32_t tr = x / 3, c = x % 3;
    uint32_t p = triangles_[x], q = triangles_[3 * tr + nextCorner(c)], r = triangles_[3 * tr + prevCorner(c)];
    uint32_t cs[3] = {triangles_[3 * tr], triangles_[3 * tr + 1], triangles_[3 * tr + 2]};
    cs[nextCorner(c)] = m;  // (p, q, r) -> (p, m, r)
    ok = ok && chRewritten_.push_back(tr);
    for (uint32_t k = 0; k < 3; ++k) ok = ok && chRewrittenCorners_.push_back(cs[k]);
    ok = ok && chAdded_.push_back(m) && chAdded_.push_back(q) && chAdded_.push_back(r);
    (void)p;
  }
  if (!ok || !Impl::reserve(*this, 1)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  float pm[3];
  for (int k = 0; k < 3; ++k)
    pm[k] = float((1 - t) * double(positions_[3 * size_t(a) + k]) + t * double(positions_[3 * size_t(b) + k]));
  Impl::appendVertex(*this, pm);
  Impl::apply(*this);
  Impl::writePending(*this, pw);
  if (newVertex) *newVertex = m;
  return Status{};
}

Status EditableMesh::collapseEdge(uint32_t e, double t, uint32_t* remaining) {
  Status s = Impl::checkHalfedge(*this, e);
  if (!s.ok()) return s;
  if (!(t >= 0 && t <= 1)) return badArgument(detail::format("the collapse parameter must be in [0, 1], not %g", t));
  const uint8_t kind = pairKind_[e >> 1];
  if (kind != uint8_t(EdgeKind::Interior) && kind != uint8_t(EdgeKind::Boundary))
    return refused(detail::format("half-edge %u is on an inconsistent or non-manifold edge", e));
  const uint32_t a = vert_[e], b = vert_[e ^ 1u];
  if (vertexNonManifold_[a] || vertexNonManifold_[b])
    return refused(detail::format("vertex %u is non-manifold", vertexNonManifold_[a] ? a : b));
  // Every edge at a and b must be interior or boundary.
  bool manifoldEdges = true;
  for (uint32_t v : {a, b})
    Impl::forEachCorner(*this, v, [&](uint32_t q) {
      uint32_t tr = q / 3, c = q % 3;
      if (degenerate_[tr]) return;
      for (uint32_t x : {q, 3 * tr + prevCorner(c)})
        if (pairKind_[sideHalfedge_[x] >> 1] > uint8_t(EdgeKind::Boundary)) manifoldEdges = false;
    });
  if (!manifoldEdges) return refused("an edge at the collapsed vertices is inconsistent or non-manifold");
  const bool interior = kind == uint8_t(EdgeKind::Interior);
  uint32_t t1 = kInvalid, t2 = kInvalid, c = kInvalid, d = kInvalid;
  if (!Impl::boundaryFace(face_[e])) {
    t1 = face_[e];
    for (uint32_t k = 0; k < 3; ++k)
      if (sideHalfedge_[3 * t1 + k] == e) c = Impl::thirdCorner(*this, 3 * t1 + k);
  }
  if (!Impl::boundaryFace(face_[e ^ 1u])) {
    t2 = face_[e ^ 1u];
    for (uint32_t k = 0; k < 3; ++k)
      if (sideHalfedge_[3 * t2 + k] == (e ^ 1u)) d = Impl::thirdCorner(*this, 3 * t2 + k);
  }
  if (interior && c == d) return refused(detail::format("the two triangles of half-edge %u share all three vertices", e));
  auto onBoundary = [&](uint32_t v) { return vertexHalfedge_[v] != kInvalid && Impl::boundaryFace(face_[vertexHalfedge_[v]]); };
  if (interior && onBoundary(a) && onBoundary(b))
    return refused(detail::format("vertices %u and %u are both on the boundary but the edge between them is not: the collapse would pinch the surface", a, b));
  // Link condition: the common neighbours of a and b are the opposite vertices c and d.
  Impl::newEpoch(*this);
  Impl::forEachCorner(*this, a, [&](uint32_t q) {
    uint32_t tr = q / 3;
    if (degenerate_[tr]) return;
    for (uint32_t k = 0; k < 3; ++k) stamp_[triangles_[3 * tr + k]] = epoch_;
  });
  uint32_t common = kInvalid;
  Impl::forEachCorner(*this, b, [&](uint32_t q) {
    uint32_t tr = q / 3;
    if (degenerate_[tr]) return;
    for (uint32_t k = 0; k < 3; ++k) {
      uint32_t w = triangles_[3 * tr + k];
      if (w != a && w != b && w != c && w != d && stamp_[w] == epoch_) common = w;
    }
  });
  if (common != kInvalid)
    return refused(detail::format("link condition: vertices %u and %u share the neighbour %u besides the edge's triangles", a, b, common));
  auto hasTriangle = [&](uint32_t x, uint32_t y, uint32_t z) {
    bool found = false;
    Impl::forEachCorner(*this, x, [&](uint32_t q) {
      uint32_t tr = q / 3;
      if (degenerate_[tr]) return;
      const uint32_t* C = triangles_.data() + 3 * size_t(tr);
      bool hy = C[0] == y || C[1] == y || C[2] == y, hz = C[0] == z || C[1] == z || C[2] == z;
      if (hy && hz) found = true;
    });
    return found;
  };
  if (interior && hasTriangle(a, c, d) && hasTriangle(b, c, d))
    return refused(detail::format("link condition: triangles %u-%u-%u and %u-%u-%u both exist (the collapse would close a tetrahedron)", a, c, d, b, c, d));
  // The boundary seen as a vertex at infinity: for a boundary edge, a triangle whose other
  // two edges are boundary edges too would vanish with the edge.
  if (!interior) {
    uint32_t tr = t1 != kInvalid ? t1 : t2;
    bool allBoundary = true;
    for (uint32_t k = 0; k < 3; ++k)
      if (!Impl::boundaryFace(face_[sideHalfedge_[3 * tr + k] ^ 1u])) allBoundary = false;
    if (allBoundary) return refused(detail::format("triangle %u is a whole shell: the collapse would remove it", tr));
  }
  // Fold-over: no remaining triangle at a or b may turn its normal by more than 90 degrees.
  double pa[3], pb[3], pn[3];
  Impl::position(*this, a, pa);
  Impl::position(*this, b, pb);
  for (int k = 0; k < 3; ++k) pn[k] = double(float((1 - t) * pa[k] + t * pb[k]));
  uint32_t folded = kInvalid;
  for (uint32_t v : {a, b})
    Impl::forEachCorner(*this, v, [&](uint32_t q) {
      uint32_t tr = q / 3;
      if (degenerate_[tr] || tr == t1 || tr == t2) return;
      double P[3][3], Q[3][3];
      for (uint32_t k = 0; k < 3; ++k) {
        uint32_t w = triangles_[3 * tr + k];
        Impl::position(*this, w, P[k]);
        for (int j = 0; j < 3; ++j) Q[k][j] = (w == a || w == b) ? pn[j] : P[k][j];
      }
      double n0[3], n1[3];
      triangleNormal(P[0], P[1], P[2], n0);
      triangleNormal(Q[0], Q[1], Q[2], n1);
      if (n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2] < 0) folded = tr;
    });
  if (folded != kInvalid) return refused(detail::format("triangle %u would fold over (its normal would turn by more than 90 degrees)", folded));
  // Attributes: the two vertices merge; on each side the edges to c (d) merge.
  Impl::PendingWrites pw;
  auto pairOf = [&](uint32_t x, uint32_t y) {
    uint32_t k = kInvalid;
    Impl::forEachEdgeSide(*this, x, y, [&](uint32_t sd) { k = sideHalfedge_[sd] >> 1; });
    return k;
  };
  for (size_t ai = 0; ai < attributes_.size(); ++ai) {
    const Attribute& at = attributes_[ai];
    if (at.view.element == Element::Vertex) {
      if (!pw.add(*this, ai, true, Impl::valueOf(*this, ai, a), Impl::valueOf(*this, ai, b), t, a)) return pw.status();
    } else if (at.view.element == Element::Edge) {
      for (uint32_t o : {c, d}) {
        if (o == kInvalid) continue;
        uint32_t ka = pairOf(a, o), kb = pairOf(b, o);
        if (!pw.add(*this, ai, true, Impl::valueOf(*this, ai, ka), Impl::valueOf(*this, ai, kb), 0.5, kInvalid, a, o))
          return pw.status();
      }
    }
  }
  // The change: the edge's triangles go, the others at b now use a.
  Impl::clearChange(*this);
  bool ok = true;
  if (t1 != kInvalid) ok = ok && chRemoved_.push_back(t1);
  if (t2 != kInvalid) ok = ok && chRemoved_.push_back(t2);
  Impl::forEachCorner(*this, b, [&](uint32_t q) {
    uint32_t tr = q / 3;
    if (tr == t1 || tr == t2) return;
    for (uint32_t x : chRewritten_)
      if (x == tr) return;  // a degenerate triangle with b twice
    ok = ok && chRewritten_.push_back(tr);
    for (uint32_t k = 0; k < 3; ++k) {
      uint32_t w = triangles_[3 * tr + k];
      ok = ok && chRewrittenCorners_.push_back(w == b ? a : w);
    }
  });
  if (!ok || !Impl::reserve(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  for (int k = 0; k < 3; ++k) positions_[3 * size_t(a) + k] = float(pn[k]);
  Impl::apply(*this);
  vertexDead_[b] = 1;
  --nLiveVertices_;
  Impl::writePending(*this, pw);
  if (remaining) *remaining = a;
  return Status{};
}

namespace {
// Negates the kept normal of triangle t, if the mesh keeps normals.
void negateNormal(const AttributeView* n, uint32_t t) {
  if (!n || n->type != ValueType::F32 || n->components != 3) return;
  float* p = static_cast<float*>(n->data) + 3 * size_t(t);
  for (int k = 0; k < 3; ++k) p[k] = -p[k];
}
}  // namespace

Status EditableMesh::reverseTriangle(uint32_t t) {
  Status s = Impl::checkTriangle(*this, t);
  if (!s.ok()) return s;
  Impl::clearChange(*this);
  const uint32_t* C = triangles_.data() + 3 * size_t(t);
  uint32_t cs[3] = {C[0], C[2], C[1]};
  bool ok = chRewritten_.push_back(t);
  for (uint32_t x : cs) ok = ok && chRewrittenCorners_.push_back(x);
  if (!ok || !Impl::reserve(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  Impl::apply(*this);
  negateNormal(attribute(kAttrNormal), t);
  return Status{};
}

Status EditableMesh::reverseShell(uint32_t t) {
  Status s = Impl::checkTriangle(*this, t);
  if (!s.ok()) return s;
  Impl::clearChange(*this);
  // Breadth-first over shared edges; chRewritten_ is the queue, triangle stamps the marks.
  Impl::newTriangleEpoch(*this);
  if (!chRewritten_.push_back(t)) return detail::oom(kEditArrays);
  triStamp_[t] = triEpoch_;
  bool ok = true;
  if (!degenerate_[t])
    for (size_t i = 0; i < chRewritten_.size() && ok; ++i) {
      uint32_t tr = chRewritten_[i];
      for (uint32_t c = 0; c < 3; ++c)
        Impl::forEachEdgeSide(*this, triangles_[3 * tr + c], triangles_[3 * tr + nextCorner(c)], [&](uint32_t x) {
          if (triStamp_[x / 3] == triEpoch_) return;
          triStamp_[x / 3] = triEpoch_;
          ok = ok && chRewritten_.push_back(x / 3);
        });
    }
  for (uint32_t tr : chRewritten_) {
    const uint32_t* C = triangles_.data() + 3 * size_t(tr);
    uint32_t c0 = C[0], c1 = C[1], c2 = C[2];
    ok = ok && chRewrittenCorners_.push_back(c0) && chRewrittenCorners_.push_back(c2) && chRewrittenCorners_.push_back(c1);
  }
  Array<uint32_t> done;  // apply() clears the change
  ok = ok && done.resize(chRewritten_.size());
  if (!ok || !Impl::reserve(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  std::memcpy(done.data(), chRewritten_.data(), chRewritten_.size() * 4);
  Impl::apply(*this);
  const AttributeView* n = attribute(kAttrNormal);
  for (uint32_t tr : done) negateNormal(n, tr);
  return Status{};
}

Status EditableMesh::fillLoop(uint32_t h, FillMethod method, Array<uint32_t>* out) {
  const EditLoops& l = loops();
  if (h >= l.nLoops()) return badArgument(detail::format("loop %u is out of range (%u loops)", h, l.nLoops()));
  return fillHole(l.loopHalfedge[h], method, out);
}

Status EditableMesh::fillHole(uint32_t e, FillMethod method, Array<uint32_t>* out) {
  Status s = Impl::checkHalfedge(*this, e);
  if (!s.ok()) return s;
  if (!Impl::boundaryFace(face_[e])) return badArgument(detail::format("half-edge %u is not a boundary half-edge", e));
  // The loop's vertices in next order.
  Array<uint32_t> loop;
  uint32_t x = e;
  do {
    if (pairKind_[x >> 1] != uint8_t(EdgeKind::Boundary))
      return refused(detail::format("the loop of half-edge %u is a seam (it has a cut side): filling it would make non-manifold edges", e));
    if (!loop.push_back(vert_[x])) return detail::oom(kEditArrays);
    x = next_[x];
  } while (x != e);
  // Cut the loop at repeated vertices into simple polygons: a stack of vertices; when a
  // vertex comes again, the part since its last visit is a polygon.
  // A vertex on the stack has stamp_ == epoch_ (found by a search back, only when it
  // repeats).
  Array<uint32_t> stack, polys, polyOffsets;
  if (!polyOffsets.push_back(0)) return detail::oom(kEditArrays);
  Impl::newEpoch(*this);
  auto emit = [&](size_t from) {
    for (size_t i = from; i < stack.size(); ++i) {
      if (!polys.push_back(stack[i])) return false;
      stamp_[stack[i]] = epoch_ - 1;
    }
    stack.shrink(from);
    return polyOffsets.push_back(uint32_t(polys.size()));
  };
  for (uint32_t v : loop) {
    if (stamp_[v] == epoch_) {
      size_t from = stack.size();
      while (from > 0 && stack[from - 1] != v) --from;
      if (!emit(from - 1)) return detail::oom(kEditArrays);
    }
    stamp_[v] = epoch_;
    if (!stack.push_back(v)) return detail::oom(kEditArrays);
  }
  if (!emit(0)) return detail::oom(kEditArrays);
  // Triangulate each polygon.
  Array<uint32_t> tris;
  Array<uint64_t> diagonals;
  for (size_t p = 0; p + 1 < polyOffsets.size(); ++p) {
    const uint32_t* P = polys.data() + polyOffsets[p];
    const uint32_t n = polyOffsets[p + 1] - polyOffsets[p];
    if (n < 3) return refused(detail::format("the loop of half-edge %u has a part of %u edges, which no triangle can fill", e, n));
    auto isDiagonalFree = [&](uint32_t u, uint32_t v) { return !Impl::edgeExists(*this, u, v); };
    bool ear = method == FillMethod::Ear && n > 3;
    double basis[2][3] = {{0, 0, 0}, {0, 0, 0}};
    if (ear) {
      // Newell normal of the polygon; the projection keeps its orientation counter-clockwise.
      double nrm[3] = {0, 0, 0};
      for (uint32_t i = 0; i < n; ++i) {
        double A[3], B[3];
        Impl::position(*this, P[i], A);
        Impl::position(*this, P[(i + 1) % n], B);
        nrm[0] += (A[1] - B[1]) * (A[2] + B[2]);
        nrm[1] += (A[2] - B[2]) * (A[0] + B[0]);
        nrm[2] += (A[0] - B[0]) * (A[1] + B[1]);
      }
      double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
      if (!(len > 0) || !std::isfinite(len)) {
        ear = false;  // no plane (a flat or degenerate loop): a fan
      } else {
        for (double& c : nrm) c /= len;
        int axis = std::fabs(nrm[0]) <= std::fabs(nrm[1]) && std::fabs(nrm[0]) <= std::fabs(nrm[2]) ? 0
                   : std::fabs(nrm[1]) <= std::fabs(nrm[2])                                         ? 1
                                                                                                     : 2;
        double ax[3] = {0, 0, 0};
        ax[axis] = 1;
        double* u = basis[0];
        double* w = basis[1];
        u[0] = nrm[1] * ax[2] - nrm[2] * ax[1];
        u[1] = nrm[2] * ax[0] - nrm[0] * ax[2];
        u[2] = nrm[0] * ax[1] - nrm[1] * ax[0];
        double ul = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        for (int k = 0; k < 3; ++k) u[k] /= ul;
        w[0] = nrm[1] * u[2] - nrm[2] * u[1];
        w[1] = nrm[2] * u[0] - nrm[0] * u[2];
        w[2] = nrm[0] * u[1] - nrm[1] * u[0];
      }
    }
    if (!ear) {
      for (uint32_t i = 1; i + 1 < n; ++i) {
        if (!tris.push_back(P[0]) || !tris.push_back(P[i]) || !tris.push_back(P[i + 1])) return detail::oom(kEditArrays);
        if (i + 1 < n - 1 && !diagonals.push_back(edgeKey(P[0], P[i + 1]))) return detail::oom(kEditArrays);
      }
      continue;
    }
    // Ear clipping in the plane.
    Array<double> xy;
    Array<uint32_t> ring;
    if (!xy.resize(2 * size_t(n)) || !ring.resize(n)) return detail::oom(kEditArrays);
    for (uint32_t i = 0; i < n; ++i) {
      double A[3];
      Impl::position(*this, P[i], A);
      xy[2 * i] = A[0] * basis[0][0] + A[1] * basis[0][1] + A[2] * basis[0][2];
      xy[2 * i + 1] = A[0] * basis[1][0] + A[1] * basis[1][1] + A[2] * basis[1][2];
      ring[i] = i;
    }
    auto cross = [&](uint32_t i, uint32_t j, uint32_t k) {
      return (xy[2 * j] - xy[2 * i]) * (xy[2 * k + 1] - xy[2 * i + 1]) - (xy[2 * j + 1] - xy[2 * i + 1]) * (xy[2 * k] - xy[2 * i]);
    };
    uint32_t m = n;
    while (m > 3) {
      uint32_t pick = kInvalid, fallback = kInvalid;
      for (uint32_t r = 0; r < m && pick == kInvalid; ++r) {
        uint32_t i = ring[(r + m - 1) % m], j = ring[r], k = ring[(r + 1) % m];
        if (!isDiagonalFree(P[i], P[k])) continue;
        bool convex = cross(i, j, k) > 0;
        if (fallback == kInvalid) fallback = r;
        if (!convex) continue;
        bool inside = false;
        for (uint32_t q = 0; q < m && !inside; ++q) {
          uint32_t o = ring[q];
          if (o == i || o == j || o == k) continue;
          if (cross(i, j, o) >= 0 && cross(j, k, o) >= 0 && cross(k, i, o) >= 0) inside = true;
        }
        if (!inside) pick = r;
      }
      if (pick == kInvalid) pick = fallback;
      if (pick == kInvalid)
        return refused(detail::format("every ear of the loop of half-edge %u would make an existing edge non-manifold", e));
      uint32_t i = ring[(pick + m - 1) % m], j = ring[pick], k = ring[(pick + 1) % m];
      if (!tris.push_back(P[i]) || !tris.push_back(P[j]) || !tris.push_back(P[k]) || !diagonals.push_back(edgeKey(P[i], P[k])))
        return detail::oom(kEditArrays);
      for (uint32_t r = pick; r + 1 < m; ++r) ring[r] = ring[r + 1];
      --m;
    }
    if (!tris.push_back(P[ring[0]]) || !tris.push_back(P[ring[1]]) || !tris.push_back(P[ring[2]])) return detail::oom(kEditArrays);
  }
  // No inner edge may land on an existing edge, nor on another inner edge.
  std::sort(diagonals.begin(), diagonals.end());
  for (size_t i = 0; i < diagonals.size(); ++i) {
    uint32_t u = uint32_t(diagonals[i] >> 32), v = uint32_t(diagonals[i]);
    if ((i > 0 && diagonals[i] == diagonals[i - 1]) || Impl::edgeExists(*this, u, v))
      return refused(detail::format("filling the loop of half-edge %u would make edge %u-%u non-manifold", e, u, v));
  }
  Impl::clearChange(*this);
  bool ok = true;
  for (uint32_t v : tris) ok = ok && chAdded_.push_back(v);
  if (out) {
    out->clear();
    ok = ok && out->reserve(tris.size() / 3);
  }
  if (!ok || !Impl::reserve(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  uint32_t first = Impl::apply(*this);
  if (out)
    for (uint32_t i = 0; i < tris.size() / 3; ++i) (void)out->push_back(first + i);
  return Status{};
}

}  // namespace stltopo
