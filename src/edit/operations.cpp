// EditableMesh operations: init and every edit. See impl.h.
#include "edit/impl.h"

namespace stltopo {
using Impl = EditableMesh::Impl;

namespace {

// Newell normal of triangle (p, q, r), unnormalized, in double.
void triangleNormal(const double* p, const double* q, const double* r, double* n) {
  double ux = q[0] - p[0], uy = q[1] - p[1], uz = q[2] - p[2];
  double wx = r[0] - p[0], wy = r[1] - p[1], wz = r[2] - p[2];
  n[0] = uy * wz - uz * wy;
  n[1] = uz * wx - ux * wz;
  n[2] = ux * wy - uy * wx;
}

}  // namespace

// ============================================================================ init

Status EditableMesh::Impl::init(const Mesh& mesh, const TopologyOptions& options) {
  Topology topo;
  TopologyOptions o = options;
  o.prevAndFace = true;
  Status s = buildTopology(mesh, topo, o);
  if (!s.ok()) {
    *this = Impl{};
    return s;
  }
  return init(mesh, topo);
}

Status EditableMesh::Impl::init(const Mesh& mesh, const Topology& topo) {
  *this = Impl{};
  const uint32_t nt = mesh.nTriangles(), nv = mesh.nVertices(), nh = topo.nHalfedges();
  if (topo.nTriangles != nt || topo.nVertices != nv || topo.vertexWeld.size() != nv ||
      topo.triangleDegenerate.size() != nt)
    return badArgument("the topology was not built from this mesh");
  if (nh > 0 && (topo.prev.size() != nh || topo.face.size() != nh))
    return badArgument("the topology has no prev and face (TopologyOptions::prevAndFace = false)");
  auto fail = [&]() {
    *this = Impl{};
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

// ============================================================================ edits

Status EditableMesh::Impl::reserve(uint32_t vertices, uint32_t triangles) {
  Impl::clearChange(*this);
  // A change that adds `triangles` triangles reserves the triangle and half-edge arrays.
  for (uint32_t i = 0; i < triangles; ++i)
    for (int c = 0; c < 3; ++c)
      if (!chAdded_.push_back(kInvalid)) {
        Impl::clearChange(*this);
        return detail::oom(kEditArrays);
      }
  bool ok = Impl::reserveChange(*this, vertices);
  Impl::clearChange(*this);
  return ok ? Status{} : detail::oom(kEditArrays);
}

Status EditableMesh::Impl::addVertex(float x, float y, float z, uint32_t* out) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    return Status::error(Code::NonFinite, "a vertex needs finite coordinates");
  if (!Impl::reserveChange(*this, 1)) return detail::oom(kEditArrays);
  float p[3] = {x, y, z};
  uint32_t v = Impl::appendVertex(*this, p);
  if (out) *out = v;
  return Status{};
}

Status EditableMesh::Impl::setPosition(uint32_t v, float x, float y, float z) {
  Status s = Impl::checkVertex(*this, v);
  if (!s.ok()) return s;
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    return badArgument(detail::format("vertex %u needs finite coordinates", v));
  positions_[3 * size_t(v)] = x;
  positions_[3 * size_t(v) + 1] = y;
  positions_[3 * size_t(v) + 2] = z;
  // Nothing of the topology depends on positions but the loops' perimeters. Numbered loops
  // through v get theirs summed again, from each loop's first half-edge as a fresh build
  // sums them; stale loops get theirs when they are numbered. The boundary half-edges at v
  // are the partners of v's triangle sides that have boundary partners.
  if (loopsStale_) return Status{};
  constexpr int kMaxLoops = 8;
  uint32_t done[kMaxLoops];
  int nDone = 0;
  bool overflow = false;
  Impl::forEachCorner(*this, v, [&](uint32_t q) {
    const uint32_t t = q / 3, c = q % 3;
    if (degenerate_[t] || overflow) return;
    for (uint32_t side : {q, 3 * t + prevCorner(c)}) {
      const uint32_t b = sideHalfedge_[side] ^ 1u;
      if (!Impl::boundaryFace(face_[b])) continue;
      const uint32_t h = face_[b] & ~kLoopFaceBit;
      bool seen = false;
      for (int i = 0; i < nDone; ++i) seen = seen || done[i] == h;
      if (seen) continue;
      if (nDone == kMaxLoops) {
        overflow = true;
        return;
      }
      done[nDone++] = h;
      loops_.loopPerimeter[h] = Impl::loopPerimeter(*this, loops_.loopHalfedge[h]);
    }
  });
  // More loops through one vertex than the list holds (a vertex pinching many holes): they
  // are numbered and summed again when next read, O(n) once.
  if (overflow) loopsStale_ = statsStale_ = true;
  return Status{};
}

Status EditableMesh::Impl::removeTriangle(uint32_t t) {
  Status s = Impl::checkTriangle(*this, t);
  if (!s.ok()) return s;
  Impl::clearChange(*this);
  if (!chRemoved_.push_back(t) || !Impl::reserveChange(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  Impl::apply(*this);
  return Status{};
}

Status EditableMesh::Impl::addTriangle(uint32_t a, uint32_t b, uint32_t c, uint32_t* out, bool allowNonManifold) {
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
  if (!Impl::reserveChange(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  uint32_t t = Impl::apply(*this);
  if (out) *out = t;
  return Status{};
}

Status EditableMesh::Impl::flipEdge(uint32_t e) {
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
  if (!ok || !Impl::reserveChange(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  Impl::apply(*this);
  Impl::writePending(*this, pw);
  return Status{};
}

Status EditableMesh::Impl::splitEdge(uint32_t e, double t, uint32_t* newVertex) {
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
  if (!ok || !Impl::reserveChange(*this, 1)) {
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

Status EditableMesh::Impl::collapseEdge(uint32_t e, double t, uint32_t* remaining) {
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
  if (!ok || !Impl::reserveChange(*this, 0)) {
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

Status EditableMesh::Impl::reverseTriangle(uint32_t t) {
  Status s = Impl::checkTriangle(*this, t);
  if (!s.ok()) return s;
  Impl::clearChange(*this);
  const uint32_t* C = triangles_.data() + 3 * size_t(t);
  uint32_t cs[3] = {C[0], C[2], C[1]};
  bool ok = chRewritten_.push_back(t);
  for (uint32_t x : cs) ok = ok && chRewrittenCorners_.push_back(x);
  if (!ok || !Impl::reserveChange(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  Impl::apply(*this);
  negateNormal(attribute(kAttrNormal), t);
  return Status{};
}

Status EditableMesh::Impl::reverseShell(uint32_t t) {
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
  if (!ok || !Impl::reserveChange(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  std::memcpy(done.data(), chRewritten_.data(), chRewritten_.size() * 4);
  Impl::apply(*this);
  const AttributeView* n = attribute(kAttrNormal);
  for (uint32_t tr : done) negateNormal(n, tr);
  return Status{};
}

Status EditableMesh::Impl::fillLoop(uint32_t h, FillMethod method, Array<uint32_t>* out) {
  const EditLoops& l = loops();
  if (h >= l.nLoops()) return badArgument(detail::format("loop %u is out of range (%u loops)", h, l.nLoops()));
  return fillHole(l.loopHalfedge[h], method, out);
}

Status EditableMesh::Impl::fillHole(uint32_t e, FillMethod method, Array<uint32_t>* out) {
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
  if (!ok || !Impl::reserveChange(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  uint32_t first = Impl::apply(*this);
  if (out)
    for (uint32_t i = 0; i < tris.size() / 3; ++i) (void)out->push_back(first + i);
  return Status{};
}

}  // namespace stltopo
