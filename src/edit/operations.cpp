// EditableMesh operations: init and every edit. See impl.h.
#include "edit/impl.h"
#include "predicates.h"

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
  {
    // Impl{}, but the arrays that are rebuilt below keep their memory (emptied()).
    Impl fresh;
    fresh.positions_ = emptied(positions_);
    fresh.triangles_ = emptied(triangles_);
    fresh.vertexDead_ = emptied(vertexDead_);
    fresh.degenerate_ = emptied(degenerate_);
    fresh.cornerNext_ = emptied(cornerNext_);
    fresh.cornerPrev_ = emptied(cornerPrev_);
    fresh.vertexCorner_ = emptied(vertexCorner_);
    fresh.vertexCornerCount_ = emptied(vertexCornerCount_);
    fresh.sideHalfedge_ = emptied(sideHalfedge_);
    fresh.next_ = emptied(next_);
    fresh.prev_ = emptied(prev_);
    fresh.vert_ = emptied(vert_);
    fresh.face_ = emptied(face_);
    fresh.pairKind_ = emptied(pairKind_);
    fresh.triangleHalfedge_ = emptied(triangleHalfedge_);
    fresh.vertexHalfedge_ = emptied(vertexHalfedge_);
    fresh.vertexNonManifold_ = emptied(vertexNonManifold_);
    fresh.stamp_ = emptied(stamp_);
    fresh.triStamp_ = emptied(triStamp_);
    *this = std::move(fresh);
  }
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
  // Room past the end for the first edits. An edit reserves room for its worst case first
  // (reserveChange): at exact capacity, the first one (a reversed triangle, a filled hole)
  // moved every array the edit can grow to twice its size, copying all of a big mesh's
  // memory into fresh pages. The room is not written, so it takes no pages until used.
  auto room = [](size_t n) { return n + n / 16 + 64; };
  const size_t np = nh / 2;
  if (!positions_.reserve(room(nv) * 3) || !vertexDead_.reserve(room(nv)) || !vertexCorner_.reserve(room(nv)) ||
      !vertexCornerCount_.reserve(room(nv)) || !vertexHalfedge_.reserve(room(nv)) ||
      !vertexNonManifold_.reserve(room(nv)) || !stamp_.reserve(room(nv)) || !triangles_.reserve(room(nt) * 3) ||
      !degenerate_.reserve(room(nt)) || !cornerNext_.reserve(room(nt) * 3) || !cornerPrev_.reserve(room(nt) * 3) ||
      !sideHalfedge_.reserve(room(nt) * 3) || !triangleHalfedge_.reserve(room(nt)) || !triStamp_.reserve(room(nt)) ||
      !next_.reserve(room(np) * 2) || !prev_.reserve(room(np) * 2) || !vert_.reserve(room(np) * 2) ||
      !face_.reserve(room(np) * 2) || !pairKind_.reserve(room(np)))
    return fail();
  if (!positions_.resize(size_t(nv) * 3) || !triangles_.resize(size_t(nt) * 3) || !vertexDead_.assign(nv, 0) ||
      !degenerate_.resize(nt) || !cornerNext_.resize(size_t(nt) * 3) || !cornerPrev_.resize(size_t(nt) * 3) ||
      !vertexCorner_.assign(nv, kInvalid) || !vertexCornerCount_.assign(nv, 0) ||
      !sideHalfedge_.assign(size_t(nt) * 3, kInvalid) || !next_.resize(nh) || !prev_.resize(nh) || !vert_.resize(nh) ||
      !face_.resize(nh) || !pairKind_.resize(nh / 2) || !triangleHalfedge_.resize(nt) || !vertexHalfedge_.resize(nv) ||
      !vertexNonManifold_.resize(nv) || !stamp_.assign(nv, 0) || !triStamp_.assign(nt, 0))
    return fail();
  if (nv > 0) std::memcpy(positions_.data(), mesh.positions.data(), size_t(nv) * 3 * sizeof(float));
  // The exact weld's representatives are the vertices themselves: the corners as they are.
  if (nt > 0 && !(topo.tolerance > 0) && topo.nWeldedVertices == nv) {
    std::memcpy(triangles_.data(), mesh.triangles.data(), size_t(nt) * 3 * sizeof(uint32_t));
    std::memcpy(degenerate_.data(), topo.triangleDegenerate.data(), nt);
  } else {
    for (size_t i = 0; i < size_t(nt) * 3; ++i) triangles_[i] = topo.vertexWeld[mesh.triangles[i]];
    for (uint32_t t = 0; t < nt; ++t) degenerate_[t] = topo.triangleDegenerate[t];
  }
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
  if (nv > 0) {
    std::memcpy(vertexHalfedge_.data(), topo.vertexHalfedge.data(), size_t(nv) * sizeof(uint32_t));
    std::memcpy(vertexNonManifold_.data(), topo.vertexNonManifold.data(), nv);
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
  knownShells_ = topo.nShells;
  format_ = mesh.format;
  colorConvention_ = mesh.colorConvention;
  STLTOPO_TRY {
    solids_ = mesh.solids;
    warnings_ = mesh.warnings;
  }
  STLTOPO_CATCH { return fail(); }
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
  if (overflow) {
    loopsStale_ = statsStale_ = true;
    knownShells_ = kInvalid;
  }
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
      if (m >= 2)
        return refused(detail::format("edge %u-%u has %u sides already: a third would make it non-manifold", p, q, m));
      if (same > 0)
        return refused(detail::format(
            "edge %u-%u has a side running the same way (%u -> %u): it would become inconsistent", p, q, p, q));
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
  if (pairKind_[e >> 1] != uint8_t(EdgeKind::Interior) || Impl::boundaryFace(face_[e]) ||
      Impl::boundaryFace(face_[e ^ 1u]))
    return refused(
        detail::format("half-edge %u is not on an interior manifold edge (a boundary, inconsistent or non-manifold "
                       "edge cannot be flipped)",
                       e));
  const uint32_t t1 = face_[e], t2 = face_[e ^ 1u];
  uint32_t s1 = kInvalid, s2 = kInvalid;
  for (uint32_t k = 0; k < 3; ++k) {
    if (sideHalfedge_[3 * t1 + k] == e) s1 = 3 * t1 + k;
    if (sideHalfedge_[3 * t2 + k] == (e ^ 1u)) s2 = 3 * t2 + k;
  }
  const uint32_t a = triangles_[s1], b = Impl::sideDst(*this, s1);
  const uint32_t c = Impl::thirdCorner(*this, s1), d = Impl::thirdCorner(*this, s2);
  if (c == d) return refused(detail::format("the two triangles of half-edge %u share all three vertices", e));
  if (Impl::edgeExists(*this, c, d)) return refused(detail::format("the flipped edge %u-%u exists already", c, d));
  Impl::PendingWrites pw;
  for (size_t ai = 0; ai < attributes_.size(); ++ai) {
    const Attribute& at = attributes_[ai];
    if (at.view.element == Element::Triangle) {
      const uint8_t* x = Impl::valueOf(*this, ai, t1);
      const uint8_t* y = Impl::valueOf(*this, ai, t2);
      if (!pw.add(*this, ai, true, x, y, 0.5, t1) || !pw.add(*this, ai, true, y, x, 0.5, t2)) return pw.status();
    } else if (at.view.element == Element::Edge) {
      if (!pw.add(*this, ai, false, Impl::valueOf(*this, ai, e >> 1), Impl::valueOf(*this, ai, e >> 1), 0.5, kInvalid,
                  c, d))
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
  if (!(t > 0 && t < 1))
    return badArgument(detail::format("the split parameter must be strictly between 0 and 1, not %g", t));
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
        if (!pw.add(*this, ai, false, y, y, t, x / 3) || !pw.add(*this, ai, false, y, y, t, added++))
          return pw.status();
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
  if (interior && c == d)
    return refused(detail::format("the two triangles of half-edge %u share all three vertices", e));
  auto onBoundary = [&](uint32_t v) {
    return vertexHalfedge_[v] != kInvalid && Impl::boundaryFace(face_[vertexHalfedge_[v]]);
  };
  if (interior && onBoundary(a) && onBoundary(b))
    return refused(
        detail::format("vertices %u and %u are both on the boundary but the edge between them is not: the collapse "
                       "would pinch the surface",
                       a, b));
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
    return refused(detail::format(
        "link condition: vertices %u and %u share the neighbour %u besides the edge's triangles", a, b, common));
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
    return refused(detail::format(
        "link condition: triangles %u-%u-%u and %u-%u-%u both exist (the collapse would close a tetrahedron)", a, c, d,
        b, c, d));
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
  if (folded != kInvalid)
    return refused(
        detail::format("triangle %u would fold over (its normal would turn by more than 90 degrees)", folded));
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

Status EditableMesh::Impl::reverseTriangle(uint32_t t) { return reverseTriangles(&t, 1); }

Status EditableMesh::Impl::reverseTriangles(const uint32_t* ids, uint32_t n) {
  if (n == 0) return Status{};
  if (!ids) return badArgument("reverseTriangles: no ids");
  // Every id live and listed once (the stamps mark the ones seen), before anything changes.
  Impl::newTriangleEpoch(*this);
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t t = ids[i];
    Status s = Impl::checkTriangle(*this, t);
    if (!s.ok()) return s;
    if (triStamp_[t] == triEpoch_) return badArgument(detail::format("triangle %u is listed twice", t));
    triStamp_[t] = triEpoch_;
  }
  Impl::clearChange(*this);
  bool ok = chRewritten_.reserve(n) && chRewrittenCorners_.reserve(3 * size_t(n));
  for (uint32_t i = 0; ok && i < n; ++i) {
    const uint32_t* C = triangles_.data() + 3 * size_t(ids[i]);
    (void)chRewritten_.push_back(ids[i]);  // reserved
    (void)chRewrittenCorners_.push_back(C[0]);
    (void)chRewrittenCorners_.push_back(C[2]);
    (void)chRewrittenCorners_.push_back(C[1]);
  }
  if (!ok || !Impl::reserveChange(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  // A reversed triangle shares the same edges as before: the shells (edge-connected
  // components) and so a known shell count stay.
  const uint32_t shells = knownShells_;
  Impl::apply(*this);
  knownShells_ = shells;
  const AttributeView* normal = attribute(kAttrNormal);
  for (uint32_t i = 0; i < n; ++i) negateNormal(normal, ids[i]);
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
    ok = ok && chRewrittenCorners_.push_back(c0) && chRewrittenCorners_.push_back(c2) &&
         chRewrittenCorners_.push_back(c1);
  }
  Array<uint32_t> done;  // apply() clears the change
  ok = ok && done.resize(chRewritten_.size());
  if (!ok || !Impl::reserveChange(*this, 0)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  std::memcpy(done.data(), chRewritten_.data(), chRewritten_.size() * 4);
  const uint32_t shells = knownShells_;  // as for reverseTriangles: the shells stay
  Impl::apply(*this);
  knownShells_ = shells;
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
      return refused(detail::format(
          "the loop of half-edge %u is a seam (it has a cut side): filling it would make non-manifold edges", e));
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
    if (n < 3)
      return refused(
          detail::format("the loop of half-edge %u has a part of %u edges, which no triangle can fill", e, n));
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
        if (!tris.push_back(P[0]) || !tris.push_back(P[i]) || !tris.push_back(P[i + 1]))
          return detail::oom(kEditArrays);
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
      return (xy[2 * j] - xy[2 * i]) * (xy[2 * k + 1] - xy[2 * i + 1]) -
             (xy[2 * j + 1] - xy[2 * i + 1]) * (xy[2 * k] - xy[2 * i]);
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
        return refused(
            detail::format("every ear of the loop of half-edge %u would make an existing edge non-manifold", e));
      uint32_t i = ring[(pick + m - 1) % m], j = ring[pick], k = ring[(pick + 1) % m];
      if (!tris.push_back(P[i]) || !tris.push_back(P[j]) || !tris.push_back(P[k]) ||
          !diagonals.push_back(edgeKey(P[i], P[k])))
        return detail::oom(kEditArrays);
      for (uint32_t r = pick; r + 1 < m; ++r) ring[r] = ring[r + 1];
      --m;
    }
    if (!tris.push_back(P[ring[0]]) || !tris.push_back(P[ring[1]]) || !tris.push_back(P[ring[2]]))
      return detail::oom(kEditArrays);
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

// ============================================================================ joining and splitting vertices
// mergeVertices, splitEdgeAt (repair: stitch) and splitVertex (repair: split-nonmanifold).
// Each builds its change, checks it completely (checkJoin for the joins), and only then
// applies it, so that a refusal changes nothing.

namespace stltopo {
namespace {

constexpr uint64_t kNewEdge = ~uint64_t(0);

// A side of the mesh after a proposed change: its edge, the edge it was on before
// (kNewEdge for a side of an added triangle), its side id and direction.
struct JoinSide {
  uint64_t key, oldKey;
  uint32_t side;
  uint8_t lowToHigh;
};

// A side at a vertex x: the other end of its edge, its side id, whether it leaves x, and
// the index of its triangle in the vertex's list.
struct FanSide {
  uint32_t other, side, out, tri;
};

bool lessFanSide(const FanSide& a, const FanSide& b) {
  return a.other != b.other ? a.other < b.other : a.side < b.side;
}

uint32_t findRoot(Array<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// Pairs the sides [b, e) of one edge at a vertex by buildTopology's rule (sorted by side
// id): two sides pair when they run opposite ways; three or more: first unpaired with first
// unpaired running the other way, in side order. Calls f(i, j) for each pair (indices into
// the array). `claimed`: scratch of at least e - b flags.
template <class F>
bool pairByRule(const FanSide* s, size_t n, Array<uint8_t>& claimed, F&& f) {
  if (n < 2) return true;
  if (n == 2) {
    if (s[0].out != s[1].out) f(size_t(0), size_t(1));
    return true;
  }
  if (!claimed.assign(n, 0)) return false;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < i; ++j) {
      if (claimed[j] || s[j].out == s[i].out) continue;
      claimed[i] = claimed[j] = 1;
      f(j, i);
      break;
    }
  return true;
}

// The number of vnext cycles (fans joined through paired sides) at x of the triangles in
// `tris` (3 corners each, all non-degenerate, each using x once), whose side ids are
// 3 * ids[i] + c. `sides`, `parent`, `claimed`: scratch. kInvalid when memory runs out.
uint32_t cyclesAt(uint32_t x, const Array<uint32_t>& tris, const Array<uint32_t>& ids, Array<FanSide>& sides,
                  Array<uint32_t>& parent, Array<uint8_t>& claimed) {
  const uint32_t n = uint32_t(ids.size());
  sides.clear();
  if (!parent.resize(n)) return kInvalid;
  for (uint32_t i = 0; i < n; ++i) {
    parent[i] = i;
    const uint32_t* C = tris.data() + 3 * size_t(i);
    uint32_t cx = C[0] == x ? 0 : C[1] == x ? 1 : 2;
    if (!sides.push_back(FanSide{C[nextCorner(cx)], 3 * ids[i] + cx, 1, i}) ||
        !sides.push_back(FanSide{C[prevCorner(cx)], 3 * ids[i] + prevCorner(cx), 0, i}))
      return kInvalid;
  }
  std::sort(sides.begin(), sides.end(), lessFanSide);
  uint32_t comps = n;
  for (size_t b = 0; b < sides.size();) {
    size_t e = b;
    while (e < sides.size() && sides[e].other == sides[b].other) ++e;
    const FanSide* S = sides.data() + b;
    if (!pairByRule(S, e - b, claimed, [&](size_t i, size_t j) {
          uint32_t r = findRoot(parent, S[i].tri), q = findRoot(parent, S[j].tri);
          if (r != q) {
            parent[std::max(r, q)] = std::min(r, q);
            --comps;
          }
        }))
      return kInvalid;
    b = e;
  }
  return comps;
}

// Whether triangle (p, q, r) (old corners) would fold over as (P, Q, R) (new corners):
// the normal turns by more than 90 degrees (as collapseEdge decides), or becomes zero-area
// (exactly collinear corners) when the old one was not.
const char* foldReason(const float* p, const float* q, const float* r, const float* P, const float* Q, const float* R) {
  if (pred::collinear(P, Q, R)) return pred::collinear(p, q, r) ? nullptr : "become zero-area";
  double a[3][3], b[3][3];
  for (int k = 0; k < 3; ++k) {
    a[0][k] = p[k], a[1][k] = q[k], a[2][k] = r[k];
    b[0][k] = P[k], b[1][k] = Q[k], b[2][k] = R[k];
  }
  double n0[3], n1[3];
  triangleNormal(a[0], a[1], a[2], n0);
  triangleNormal(b[0], b[1], b[2], n1);
  if (n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2] < 0)
    return "fold over (its normal would turn by more than 90 degrees)";
  return nullptr;
}

}  // namespace

Status EditableMesh::Impl::checkJoin(M& m, bool allowNonManifold) {
  const size_t W = m.chRewritten_.size(), A = m.chAdded_.size() / 3, N = W + A;
  const uint32_t nt = m.nTriangles();
  const uint32_t* tri = m.triangles_.data();
  auto corner = [&](size_t j, uint32_t c) {
    return j < W ? m.chRewrittenCorners_[3 * j + c] : m.chAdded_[3 * (j - W) + c];
  };
  auto idOf = [&](size_t j) { return j < W ? m.chRewritten_[j] : nt + uint32_t(j - W); };
  auto degenerateNew = [&](size_t j) {
    uint32_t a = corner(j, 0), b = corner(j, 1), c = corner(j, 2);
    return a == b || b == c || a == c;
  };
  for (size_t j = 0; j < N; ++j)
    if (degenerateNew(j) && !(j < W && m.degenerate_[m.chRewritten_[j]]))
      return refused(detail::format("triangle %u would have a repeated corner", idOf(j)));
  Array<uint32_t> rewritten;
  if (!rewritten.resize(W)) return detail::oom(kEditArrays);
  if (W > 0) std::memcpy(rewritten.data(), m.chRewritten_.data(), W * 4);
  std::sort(rewritten.begin(), rewritten.end());
  auto isRewritten = [&](uint32_t t) { return std::binary_search(rewritten.begin(), rewritten.end(), t); };

  // Edges: the sides of the changed triangles after the change, the edges they touch.
  Array<JoinSide> fin;
  Array<uint64_t> keys;
  bool ok = true;
  for (size_t j = 0; j < N; ++j) {
    const bool oldSides = j < W && !m.degenerate_[m.chRewritten_[j]];
    const uint32_t t = j < W ? m.chRewritten_[j] : kInvalid;
    for (uint32_t c = 0; c < 3; ++c) {
      uint64_t old = oldSides ? edgeKey(tri[3 * t + c], tri[3 * t + nextCorner(c)]) : kNewEdge;
      if (old != kNewEdge) ok = ok && keys.push_back(old);
      if (degenerateNew(j)) continue;
      uint32_t p = corner(j, c), q = corner(j, nextCorner(c));
      ok = ok && fin.push_back(JoinSide{edgeKey(p, q), old, 3 * idOf(j) + c, uint8_t(p < q ? 1 : 0)}) &&
           keys.push_back(edgeKey(p, q));
    }
  }
  if (!ok) return detail::oom(kEditArrays);
  std::sort(keys.begin(), keys.end());
  keys.shrink(size_t(std::unique(keys.begin(), keys.end()) - keys.begin()));
  Array<uint32_t> curCount, curLowToHigh;
  if (!curCount.resize(keys.size()) || !curLowToHigh.resize(keys.size())) return detail::oom(kEditArrays);
  for (size_t i = 0; i < keys.size(); ++i) {
    const uint32_t lo = uint32_t(keys[i] >> 32), hi = uint32_t(keys[i]);
    uint32_t cnt = 0, lh = 0;
    Impl::forEachEdgeSide(m, lo, hi, [&](uint32_t s) {
      ++cnt;
      uint8_t d = tri[s] == lo ? 1 : 0;
      lh += d;
      if (!isRewritten(s / 3)) ok = ok && fin.push_back(JoinSide{keys[i], keys[i], s, d});
    });
    curCount[i] = cnt;
    curLowToHigh[i] = lh;
  }
  if (!ok) return detail::oom(kEditArrays);
  std::sort(fin.begin(), fin.end(),
            [](const JoinSide& a, const JoinSide& b) { return a.key != b.key ? a.key < b.key : a.side < b.side; });
  auto countOf = [&](uint64_t key) {
    size_t i = size_t(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
    return i < keys.size() && keys[i] == key ? curCount[i] : 0u;
  };
  int64_t delta[5] = {0, 0, 0, 0, 0};  // by EdgeClass
  size_t f = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    --delta[int(classify(curCount[i], curLowToHigh[i]))];
    while (f < fin.size() && fin[f].key < keys[i]) ++f;
    size_t g = f;
    uint32_t lh = 0;
    bool renamed = true;
    for (; g < fin.size() && fin[g].key == keys[i]; ++g) {
      lh += fin[g].lowToHigh;
      if (fin[g].oldKey == kNewEdge || fin[g].oldKey != fin[f].oldKey) renamed = false;
    }
    const uint32_t cnt = uint32_t(g - f);
    const EdgeClass cls = classify(cnt, lh);
    ++delta[int(cls)];
    // A defective edge is refused unless it was one already: its sides all come from one
    // edge with as many sides (renamed by a merge), or the edge had as many sides of the same
    // class before (a side handed from a split triangle to its new part, beside a flipped
    // neighbour: the inconsistent edge stays as it was).
    const bool wasSo = curCount[i] == cnt && classify(curCount[i], curLowToHigh[i]) == cls;
    if (cnt >= 2 && cls != EdgeClass::Interior && !(renamed && countOf(fin[f].oldKey) == cnt) && !wasSo)
      return refused(detail::format("edge %u-%u would have %s", uint32_t(keys[i] >> 32), uint32_t(keys[i]),
                                    cnt > 2 ? detail::format("%u sides (non-manifold)", cnt).c_str()
                                            : "two sides running the same way (inconsistent)"));
    f = g;
  }
  const int64_t bad =
      delta[int(EdgeClass::Boundary)] + delta[int(EdgeClass::NonManifold)] + delta[int(EdgeClass::Inconsistent)];
  if (bad > 0 || delta[int(EdgeClass::NonManifold)] > 0 || delta[int(EdgeClass::Inconsistent)] > 0)
    return refused(detail::format("the change would add %lld boundary, non-manifold or inconsistent edges",
                                  (long long)std::max<int64_t>(bad, 1)));

  // Vertices: the vnext cycles after the change at every corner of a changed triangle.
  Array<uint32_t> verts;
  Array<uint64_t> at;  // (vertex << 32) | j for the corners of the changed triangles after
  for (size_t j = 0; j < N && ok; ++j)
    for (uint32_t c = 0; c < 3; ++c) {
      ok = ok && verts.push_back(corner(j, c));
      if (j < W) ok = ok && verts.push_back(tri[3 * size_t(m.chRewritten_[j]) + c]);
      if (!degenerateNew(j) && (c == 0 || corner(j, c) != corner(j, c - 1)))
        ok = ok && at.push_back((uint64_t(corner(j, c)) << 32) | j);
    }
  if (!ok) return detail::oom(kEditArrays);
  std::sort(verts.begin(), verts.end());
  verts.shrink(size_t(std::unique(verts.begin(), verts.end()) - verts.begin()));
  std::sort(at.begin(), at.end());
  uint32_t before = 0, after = 0, firstBad = kInvalid;
  Array<uint32_t> tris, ids, parent;
  Array<FanSide> sides;
  Array<uint8_t> claimed;
  for (uint32_t x : verts) {
    tris.clear();
    ids.clear();
    before += x < m.nVertices() ? m.vertexNonManifold_[x] : 0;
    if (x < m.nVertices())
      Impl::forEachCorner(m, x, [&](uint32_t q) {
        uint32_t t = q / 3;
        if (m.degenerate_[t] || isRewritten(t)) return;
        ok = ok && ids.push_back(t) && tris.push_back(tri[3 * t]) && tris.push_back(tri[3 * t + 1]) &&
             tris.push_back(tri[3 * t + 2]);
      });
    for (size_t i = size_t(std::lower_bound(at.begin(), at.end(), uint64_t(x) << 32) - at.begin());
         i < at.size() && uint32_t(at[i] >> 32) == x; ++i) {
      size_t j = size_t(uint32_t(at[i]));
      ok = ok && ids.push_back(idOf(j)) && tris.push_back(corner(j, 0)) && tris.push_back(corner(j, 1)) &&
           tris.push_back(corner(j, 2));
    }
    if (!ok) return detail::oom(kEditArrays);
    uint32_t cycles = cyclesAt(x, tris, ids, sides, parent, claimed);
    if (cycles == kInvalid) return detail::oom(kEditArrays);
    if (cycles > 1) {
      ++after;
      if (firstBad == kInvalid && !(x < m.nVertices() && m.vertexNonManifold_[x])) firstBad = x;
    }
  }
  if (!allowNonManifold && after > before)
    return refused(detail::format(
        "vertex %u would become non-manifold (its fans would meet at one point without joining)", firstBad));
  return Status{};
}

Status EditableMesh::Impl::mergeVertices(const uint32_t* keep, const uint32_t* gone, uint32_t n,
                                         bool allowNonManifold) {
  if (n == 0 || !keep || !gone) return badArgument("mergeVertices needs at least one pair of vertices");
  return stitch(keep, gone, n, nullptr, nullptr, 0, allowNonManifold);
}

Status EditableMesh::Impl::splitEdgeAt(uint32_t e, uint32_t v, bool allowNonManifold) {
  return stitch(nullptr, nullptr, 0, &e, &v, 1, allowNonManifold);
}

Status EditableMesh::Impl::stitch(const uint32_t* keep, const uint32_t* gone, uint32_t n, const uint32_t* edges,
                                  const uint32_t* vertices, uint32_t nSplits, bool allowNonManifold) {
  if ((n > 0 && (!keep || !gone)) || (nSplits > 0 && (!edges || !vertices)) || n + nSplits == 0)
    return badArgument("stitch needs vertex pairs or T-junctions");
  for (uint32_t i = 0; i < n; ++i) {
    Status s = Impl::checkVertex(*this, keep[i]);
    if (s.ok()) s = Impl::checkVertex(*this, gone[i]);
    if (!s.ok()) return s;
  }
  Impl::newEpoch(*this);
  for (uint32_t i = 0; i < 2 * n; ++i) {
    uint32_t v = i < n ? keep[i] : gone[i - n];
    if (stamp_[v] == epoch_) return badArgument(detail::format("vertex %u appears twice in the vertices to merge", v));
    stamp_[v] = epoch_;
  }
  // The T-junctions: (pair of the edge, parameter, vertex, half-edge), sorted by edge and
  // parameter.
  struct Split {
    uint32_t pair;
    double t;
    uint32_t v, e;
  };
  Array<Split> splits;
  for (uint32_t i = 0; i < nSplits; ++i) {
    const uint32_t e = edges[i], v = vertices[i];
    Status s = Impl::checkHalfedge(*this, e);
    if (s.ok()) s = Impl::checkVertex(*this, v);
    if (!s.ok()) return s;
    if (pairKind_[e >> 1] != uint8_t(EdgeKind::Boundary))
      return badArgument(detail::format("half-edge %u is not on a boundary edge", e));
    uint32_t tr = kInvalid;
    const uint32_t side = Impl::triangleSide(*this, e, tr);
    const uint32_t a = triangles_[side], b = Impl::sideDst(*this, side), o = Impl::thirdCorner(*this, side);
    if (v == a || v == b || v == o) return refused(detail::format("vertex %u is a corner of triangle %u", v, tr));
    double pa[3], pb[3], pv[3], ab2 = 0, av = 0;
    Impl::position(*this, a, pa);
    Impl::position(*this, b, pb);
    Impl::position(*this, v, pv);
    for (int k = 0; k < 3; ++k) {
      ab2 += (pb[k] - pa[k]) * (pb[k] - pa[k]);
      av += (pv[k] - pa[k]) * (pb[k] - pa[k]);
    }
    const double t = av / ab2;
    if (!(t > 0 && t < 1))
      return refused(detail::format("vertex %u does not project strictly inside edge %u-%u", v, a, b));
    if (!splits.push_back(Split{e >> 1, t, v, side})) return detail::oom(kEditArrays);
  }
  std::sort(splits.begin(), splits.end(),
            [](const Split& x, const Split& y) { return x.pair != y.pair ? x.pair < y.pair : x.t < y.t; });
  for (size_t i = 1; i < splits.size(); ++i)
    if (splits[i].pair == splits[i - 1].pair && (splits[i].v == splits[i - 1].v || splits[i].t == splits[i - 1].t))
      return badArgument(detail::format("vertex %u splits edge %u-%u twice, or at the same point as vertex %u",
                                        splits[i].v, vert_[2 * splits[i].pair], vert_[2 * splits[i].pair + 1],
                                        splits[i - 1].v));
  // gone -> keep, sorted by gone.
  Array<uint64_t> map;
  if (!map.resize(n)) return detail::oom(kEditArrays);
  for (uint32_t i = 0; i < n; ++i) map[i] = (uint64_t(gone[i]) << 32) | keep[i];
  std::sort(map.begin(), map.end());
  auto image = [&](uint32_t v) {
    size_t i = size_t(std::lower_bound(map.begin(), map.end(), uint64_t(v) << 32) - map.begin());
    return i < map.size() && uint32_t(map[i] >> 32) == v ? uint32_t(map[i]) : v;
  };
  // The change: each split triangle (a, b, o) becomes (a, v1, o) (its id) and (v1, v2, o),
  // ..., (vk, b, o) (new ids); then every triangle at a gone vertex is rewritten; finally
  // every corner goes through the merge map. origin: the triangle each new one comes from;
  // param: the split parameter of each part (for the triangle attributes), -1 for none.
  Impl::clearChange(*this);
  Impl::newTriangleEpoch(*this);
  Array<uint32_t> originRw, originAdd;
  Array<double> paramRw, paramAdd;
  bool ok = true;
  for (size_t i = 0; i < splits.size() && ok;) {
    size_t j = i;
    while (j < splits.size() && splits[j].pair == splits[i].pair) ++j;
    const uint32_t side = splits[i].e, tr = side / 3, c = side % 3;
    if (triStamp_[tr] == triEpoch_) {
      Impl::clearChange(*this);
      return refused(detail::format("triangle %u has T-junctions on two of its edges", tr));
    }
    triStamp_[tr] = triEpoch_;
    const uint32_t b = Impl::sideDst(*this, side), o = Impl::thirdCorner(*this, side);
    uint32_t cs[3] = {triangles_[3 * tr], triangles_[3 * tr + 1], triangles_[3 * tr + 2]};
    cs[nextCorner(c)] = splits[i].v;
    ok = ok && chRewritten_.push_back(tr) && originRw.push_back(tr) && paramRw.push_back(splits[i].t);
    for (uint32_t x : cs) ok = ok && chRewrittenCorners_.push_back(x);
    for (size_t k = i; k < j; ++k) {
      const uint32_t next = k + 1 < j ? splits[k + 1].v : b;
      ok = ok && chAdded_.push_back(splits[k].v) && chAdded_.push_back(next) && chAdded_.push_back(o) &&
           originAdd.push_back(tr) && paramAdd.push_back(splits[k].t);
    }
    i = j;
  }
  for (uint32_t i = 0; i < n && ok; ++i)
    Impl::forEachCorner(*this, gone[i], [&](uint32_t q) {
      uint32_t t = q / 3;
      if (triStamp_[t] == triEpoch_) return;
      triStamp_[t] = triEpoch_;
      ok = ok && chRewritten_.push_back(t) && originRw.push_back(t) && paramRw.push_back(-1);
      for (uint32_t c = 0; c < 3; ++c) ok = ok && chRewrittenCorners_.push_back(triangles_[3 * size_t(t) + c]);
    });
  auto fail = [&](Status s) {
    Impl::clearChange(*this);
    return s;
  };
  if (!ok) return fail(detail::oom(kEditArrays));
  for (uint32_t& x : chRewrittenCorners_) x = image(x);
  for (uint32_t& x : chAdded_) x = image(x);
  // Geometry: no new triangle may fold over or become zero-area against its origin.
  const float* P = positions_.data();
  const size_t W = chRewritten_.size(), N = W + chAdded_.size() / 3;
  for (size_t j = 0; j < N; ++j) {
    const uint32_t t = j < W ? originRw[j] : originAdd[j - W];
    if (degenerate_[t]) continue;
    const uint32_t* C = triangles_.data() + 3 * size_t(t);
    const uint32_t* D = j < W ? chRewrittenCorners_.data() + 3 * j : chAdded_.data() + 3 * (j - W);
    if (D[0] == D[1] || D[1] == D[2] || D[0] == D[2]) continue;  // checkJoin refuses it
    const char* why = foldReason(P + 3 * size_t(C[0]), P + 3 * size_t(C[1]), P + 3 * size_t(C[2]), P + 3 * size_t(D[0]),
                                 P + 3 * size_t(D[1]), P + 3 * size_t(D[2]));
    if (why)
      return fail(refused(detail::format(j < W ? "triangle %u would %s" : "a part of triangle %u would %s", t, why)));
  }
  Status s = Impl::checkJoin(*this, allowNonManifold);
  if (!s.ok()) return fail(s);
  Impl::PendingWrites pw;
  for (size_t ai = 0; ai < attributes_.size(); ++ai) {
    const Element el = attributes_[ai].view.element;
    if (el == Element::Vertex) {
      for (uint32_t i = 0; i < n; ++i)
        if (!pw.add(*this, ai, true, Impl::valueOf(*this, ai, keep[i]), Impl::valueOf(*this, ai, gone[i]), 0.5,
                    keep[i]))
          return fail(pw.status());
    } else if (el == Element::Triangle) {
      for (size_t j = 0; j < N; ++j) {
        const double t = j < W ? paramRw[j] : paramAdd[j - W];
        if (t < 0) continue;
        const uint32_t id = j < W ? chRewritten_[j] : nTriangles() + uint32_t(j - W);
        const uint8_t* x = Impl::valueOf(*this, ai, j < W ? originRw[j] : originAdd[j - W]);
        if (!pw.add(*this, ai, false, x, x, t, id)) return fail(pw.status());
      }
    }
  }
  if (!Impl::reserveChange(*this, 0)) return fail(detail::oom(kEditArrays));
  Impl::apply(*this);
  for (uint32_t i = 0; i < n; ++i) {
    vertexDead_[gone[i]] = 1;
    --nLiveVertices_;
  }
  Impl::writePending(*this, pw);
  return Status{};
}

Status EditableMesh::Impl::vertexFans(const M& m, uint32_t v, Array<uint32_t>& corners, Array<uint32_t>& fanOf,
                                      uint32_t& nFans) {
  const uint32_t* tri = m.triangles_.data();
  corners.clear();
  bool ok = true;
  Impl::forEachCorner(m, v, [&](uint32_t q) { ok = ok && corners.push_back(q); });
  const uint32_t n = uint32_t(corners.size());
  Array<uint32_t> parent;
  Array<FanSide> sides;
  if (!ok || !fanOf.assign(n, 0) || !parent.resize(n)) return detail::oom(kEditArrays);
  for (uint32_t i = 0; i < n; ++i) {
    parent[i] = i;
    const uint32_t q = corners[i], t = q / 3, cx = q % 3;
    if (m.degenerate_[t]) continue;
    ok = ok && sides.push_back(FanSide{tri[3 * t + nextCorner(cx)], q, 1, i}) &&
         sides.push_back(FanSide{tri[3 * t + prevCorner(cx)], 3 * t + prevCorner(cx), 0, i});
  }
  if (!ok) return detail::oom(kEditArrays);
  std::sort(sides.begin(), sides.end(), lessFanSide);
  // Fans through the edges with two sides; the pairs of the non-manifold edges, and where
  // each non-manifold edge's sides are.
  struct NmPair {
    uint32_t first, a, b;  // lowest side id of the pair; triangle indices
    uint32_t edge;         // index into nmEdges
  };
  Array<NmPair> pairs;
  Array<uint32_t> nmEdges;  // offsets into sides of each non-manifold edge: begin, end
  Array<uint8_t> claimed;
  for (size_t b = 0; b < sides.size();) {
    size_t e = b;
    while (e < sides.size() && sides[e].other == sides[b].other) ++e;
    const FanSide* S = sides.data() + b;
    if (e - b == 2) {
      uint32_t r = findRoot(parent, S[0].tri), q = findRoot(parent, S[1].tri);
      parent[std::max(r, q)] = std::min(r, q);
    } else if (e - b >= 3) {
      const uint32_t edge = uint32_t(nmEdges.size() / 2);
      ok = ok && nmEdges.push_back(uint32_t(b)) && nmEdges.push_back(uint32_t(e));
      ok = ok && pairByRule(S, e - b, claimed, [&](size_t i, size_t j) {
             ok = ok && pairs.push_back(NmPair{std::min(S[i].side, S[j].side), S[i].tri, S[j].tri, edge});
           });
    }
    b = e;
  }
  if (!ok) return detail::oom(kEditArrays);
  std::sort(pairs.begin(), pairs.end(), [](const NmPair& x, const NmPair& y) { return x.first < y.first; });
  // Join two fans through a pair when every non-manifold edge at v keeps at most two sides
  // in the joined fan, and the pair's own edge exactly the pair.
  for (const NmPair& p : pairs) {
    uint32_t r1 = findRoot(parent, p.a), r2 = findRoot(parent, p.b);
    if (r1 == r2) continue;
    bool join = true;
    for (uint32_t k = 0; k < nmEdges.size() / 2 && join; ++k) {
      uint32_t cnt = 0;
      for (uint32_t i = nmEdges[2 * k]; i < nmEdges[2 * k + 1]; ++i) {
        uint32_t r = findRoot(parent, sides[i].tri);
        cnt += (r == r1 || r == r2) ? 1 : 0;
      }
      if (cnt > 2) join = false;
    }
    if (join) parent[std::max(r1, r2)] = std::min(r1, r2);
  }
  // Number the fans by their lowest triangle id; degenerate triangles stay with fan 0.
  Array<uint32_t> lowest;  // per root: lowest triangle id
  if (!lowest.assign(n, kInvalid)) return detail::oom(kEditArrays);
  for (uint32_t i = 0; i < n; ++i)
    if (!m.degenerate_[corners[i] / 3]) {
      uint32_t r = findRoot(parent, i);
      lowest[r] = std::min(lowest[r], corners[i] / 3);
    }
  Array<uint64_t> order;
  for (uint32_t i = 0; i < n; ++i)
    if (lowest[i] != kInvalid && !order.push_back((uint64_t(lowest[i]) << 32) | i)) return detail::oom(kEditArrays);
  std::sort(order.begin(), order.end());
  Array<uint32_t> fanOfRoot;
  if (!fanOfRoot.assign(n, 0)) return detail::oom(kEditArrays);
  for (uint32_t k = 0; k < order.size(); ++k) fanOfRoot[uint32_t(order[k])] = k;
  for (uint32_t i = 0; i < n; ++i) fanOf[i] = m.degenerate_[corners[i] / 3] ? 0 : fanOfRoot[findRoot(parent, i)];
  nFans = uint32_t(order.size());
  return Status{};
}

Status EditableMesh::Impl::splitVertex(uint32_t v, uint32_t* firstNew, uint32_t* newCount) {
  Status s = Impl::checkVertex(*this, v);
  if (!s.ok()) return s;
  Array<uint32_t> corners, fanOf;
  uint32_t nFans = 0;
  s = Impl::vertexFans(*this, v, corners, fanOf, nFans);
  if (!s.ok()) return s;
  if (nFans <= 1) return refused(detail::format("vertex %u has one fan: nothing to split", v));
  Impl::clearChange(*this);
  const uint32_t base = nVertices();
  bool ok = true;
  for (uint32_t i = 0; i < corners.size() && ok; ++i) {
    if (fanOf[i] == 0) continue;
    const uint32_t t = corners[i] / 3;
    ok = ok && chRewritten_.push_back(t);
    for (uint32_t c = 0; c < 3; ++c) {
      uint32_t w = triangles_[3 * size_t(t) + c];
      ok = ok && chRewrittenCorners_.push_back(c == corners[i] % 3 ? base + fanOf[i] - 1 : w);
    }
  }
  if (!ok || !Impl::reserveChange(*this, nFans - 1)) {
    Impl::clearChange(*this);
    return detail::oom(kEditArrays);
  }
  float p[3] = {positions_[3 * size_t(v)], positions_[3 * size_t(v) + 1], positions_[3 * size_t(v) + 2]};
  for (uint32_t k = 1; k < nFans; ++k) {
    uint32_t w = Impl::appendVertex(*this, p);
    Impl::copySlot(*this, Element::Vertex, v, w);
  }
  Impl::apply(*this);
  if (firstNew) *firstNew = base;
  if (newCount) *newCount = nFans - 1;
  return Status{};
}

}  // namespace stltopo
