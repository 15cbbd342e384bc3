// The EditableMesh topology engine: the change (reserve, apply, repair, refan), slots,
// the loop numbering and the shell count. See impl.h.
#include <algorithm>

#include "edit/impl.h"

namespace stltopo {
using Impl = EditableMesh::Impl;

bool EditableMesh::Impl::reserveChange(M& m, uint32_t newVertices) {
  const size_t R = m.chRemoved_.size(), W = m.chRewritten_.size(), A = m.chAdded_.size() / 3;
  const size_t nv = size_t(m.nVertices()) + newVertices, nt = size_t(m.nTriangles()) + A;
  if (!growTo(m.positions_, 3 * nv) || !growTo(m.vertexDead_, nv) || !growTo(m.vertexCorner_, nv) ||
      !growTo(m.vertexCornerCount_, nv) || !growTo(m.vertexHalfedge_, nv) || !growTo(m.vertexNonManifold_, nv) ||
      !growTo(m.stamp_, nv) || !reserveAttributes(m, Element::Vertex, nv))
    return false;
  if (!growTo(m.triangles_, 3 * nt) || !growTo(m.degenerate_, nt) || !growTo(m.cornerNext_, 3 * nt) ||
      !growTo(m.cornerPrev_, 3 * nt) || !growTo(m.sideHalfedge_, 3 * nt) || !growTo(m.triangleHalfedge_, nt) ||
      !growTo(m.triStamp_, nt) || !reserveAttributes(m, Element::Triangle, nt))
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

uint32_t EditableMesh::Impl::appendVertex(M& m, const float* p) {
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
  m.knownShells_ = kInvalid;
  return v;
}

uint32_t EditableMesh::Impl::newPairSlot(M& m) {
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

void EditableMesh::Impl::freePairSlot(M& m, uint32_t k) {
  for (uint32_t e = 2 * k; e < 2 * k + 2; ++e) m.next_[e] = m.prev_[e] = m.vert_[e] = m.face_[e] = kInvalid;
  m.pairKind_[k] = 0;
  (void)m.freePairs_.push_back(k);  // capacity reserved: the list never holds more than all slots
  --m.nLivePairs_;
}

uint32_t EditableMesh::Impl::apply(M& m) {
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
  m.knownShells_ = kInvalid;
  clearChange(m);
  return firstAdded;
}

void EditableMesh::Impl::repair(M& m, uint32_t lo, uint32_t hi, size_t d0, size_t d1) {
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
        if (!m.oldSlots_.empty())
          copySlot(m, Element::Edge, m.oldSlots_[0], k);
        else
          resetDefault(m, Element::Edge, k);
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

void EditableMesh::Impl::refan(M& m, uint32_t u) {
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

double EditableMesh::Impl::loopPerimeter(const M& m, uint32_t e) {
  double perim = 0;
  uint32_t x = e;
  do {
    const float* a = m.positions_.data() + size_t(m.vert_[x]) * 3;
    const float* b = m.positions_.data() + size_t(m.vert_[x ^ 1u]) * 3;
    double dx = double(a[0]) - b[0], dy = double(a[1]) - b[1], dz = double(a[2]) - b[2];
    perim += std::sqrt(dx * dx + dy * dy + dz * dz);
    x = m.next_[x];
  } while (x != e);
  return perim;
}

bool EditableMesh::Impl::labelLoops(const M& m, EditLoops& out, uint32_t* faceOut) {
  out = EditLoops{};
  Array<uint64_t> seen;
  if (!out.loopOffsets.push_back(0)) return false;
  // Only an edge that is not interior (boundary, inconsistent or non-manifold) has a side
  // whose twin is a boundary half-edge: without one, there is no loop.
  if (m.nBoundaryEdges_ == 0 && m.nInconsistentEdges_ == 0 && m.nNonManifoldEdges_ == 0) return true;
  if (!seen.assign((size_t(m.nHalfedges()) + 63) / 64, 0)) return false;
  // The loop of boundary half-edge e (not labelled yet), numbered next.
  auto loopFrom = [&](uint32_t e) {
    uint32_t id = out.nLoops();
    bool seam = false;
    uint32_t x = e;
    do {
      seen[x >> 6] |= uint64_t(1) << (x & 63);
      if (faceOut) faceOut[x] = kLoopFaceBit | id;
      if (!out.loopHalfedges.push_back(x)) return false;
      if (m.pairKind_[x >> 1] != uint8_t(EdgeKind::Boundary)) seam = true;
      x = m.next_[x];
    } while (x != e);
    const double perim = loopPerimeter(m, e);
    return out.loopHalfedge.push_back(e) && out.loopOffsets.push_back(uint32_t(out.loopHalfedges.size())) &&
           out.loopIsSeam.push_back(seam ? 1 : 0) && out.loopPerimeter.push_back(perim);
  };
  auto unseen = [&](uint32_t e) { return !((seen[e >> 6] >> (e & 63)) & 1u); };
  // Loops are numbered in the order a scan of the sides (by triangle, then corner) meets
  // the first side whose twin is in them, and start at that twin. The sides of the edges
  // that are not interior (one byte per pair says which), sorted by that order, give the
  // same loops without reading every side; when they are many (a soup), the scan is cheaper.
  const uint32_t nt = m.nTriangles(), nPairs = uint32_t(m.pairKind_.size());
  const size_t most = size_t(nt) / 8 + 64;
  Array<uint64_t> starts;  // (3 * triangle + corner) << 32 | boundary half-edge
  bool few = true;
  for (uint32_t k = 0; k < nPairs && few; ++k) {
    if (m.pairKind_[k] == uint8_t(EdgeKind::Interior)) continue;  // (a free slot's kind is Interior too)
    for (uint32_t e = 2 * k; e < 2 * k + 2; ++e) {
      if (m.vert_[e] == kInvalid || !boundaryFace(m.face_[e])) continue;
      const uint32_t side = e ^ 1u, t = m.face_[side];
      if (boundaryFace(t)) continue;
      uint32_t c = 0;
      while (c < 3 && m.sideHalfedge_[3 * size_t(t) + c] != side) ++c;
      if (c == 3) continue;
      if (starts.size() >= most) {
        few = false;
        break;
      }
      if (!starts.push_back((uint64_t(3) * t + c) << 32 | e)) return false;
    }
  }
  if (few) {
    std::sort(starts.begin(), starts.end());
    for (uint64_t k : starts) {
      const uint32_t e = uint32_t(k);
      if (unseen(e) && !loopFrom(e)) return false;
    }
    return true;
  }
  for (uint32_t t = 0; t < nt; ++t) {
    if (!m.triangleAlive(t) || m.degenerate_[t]) continue;
    for (uint32_t c = 0; c < 3; ++c) {
      uint32_t e = m.sideHalfedge_[3 * t + c] ^ 1u;
      if (boundaryFace(m.face_[e]) && unseen(e) && !loopFrom(e)) return false;
    }
  }
  return true;
}

uint32_t EditableMesh::Impl::countShells(const M& m) {
  const uint32_t nt = m.nTriangles();
  Array<uint32_t> parent;
  if (!uniteShells(m, parent)) return kInvalid;
  uint32_t n = 0;
  for (uint32_t t = 0; t < nt; ++t)
    if (m.triangleAlive(t) && !m.degenerate_[t] && parent[t] == t) ++n;
  return n;
}

bool EditableMesh::Impl::labelShells(const M& m, const Array<uint32_t>& compacted, Array<uint32_t>& triangleShell,
                                     uint32_t& nShells) {
  const uint32_t nt = m.nTriangles();
  Array<uint32_t> parent;
  if (!uniteShells(m, parent)) return false;
  // As buildTopology's numberShells: parent[t] <= t, equal for the roots (the lowest slot
  // of each shell, which is its lowest compacted id too: compaction keeps the order). In
  // increasing t the roots below t already hold their shell numbers.
  uint32_t n = 0, live = 0;
  for (uint32_t t = 0; t < nt; ++t) {
    if (compacted[t] == kInvalid) continue;
    ++live;
    if (m.degenerate_[t]) continue;
    parent[t] = parent[t] == t ? n++ : parent[parent[t]];
  }
  if (!triangleShell.resize(live)) return false;
  for (uint32_t t = 0; t < nt; ++t)
    if (compacted[t] != kInvalid) triangleShell[compacted[t]] = m.degenerate_[t] ? kInvalid : parent[t];
  nShells = n;
  return true;
}

bool EditableMesh::Impl::uniteShells(const M& m, Array<uint32_t>& parent) {
  const uint32_t nt = m.nTriangles();
  if (!parent.resize(nt)) return false;
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
  for (uint32_t t = 0; t < nt; ++t) parent[t] = find(t);
  return true;
}

}  // namespace stltopo
