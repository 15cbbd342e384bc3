// EditableMesh output: the loops and stats when read, infoJson, toMesh, compact, validate.
// See impl.h.
#include "edit/impl.h"
#include "edit/stats.h"
#include "stltopo/report.h"
#include "triangle_figures.h"

namespace stltopo {
using Impl = EditableMesh::Impl;

// ============================================================================ reading

const EditLoops& EditableMesh::Impl::loops() {
  if (loopsStale_) {
    if (!Impl::labelLoops(*this, loops_, face_.data())) {
      loops_ = EditLoops{};  // out of memory: no loops listed; stays stale
      return loops_;
    }
    loopsStale_ = false;
  }
  return loops_;
}

uint32_t EditableMesh::Impl::face(uint32_t e) {
  if (!Impl::boundaryFace(face_[e])) return face_[e];
  loops();
  return face_[e] == kStaleLoopFace ? kInvalid : nTriangles() + (face_[e] & ~kLoopFaceBit);
}

const EditStats& EditableMesh::Impl::stats() {
  if (!statsStale_) return stats_;
  // The counts as a fresh build of the compacted mesh has them; the figures are Topology's.
  TopologyCounts c;
  uint32_t vertices = 0;
  c.nTriangles = nLiveTriangles_;
  c.nDegenerate = nDegenerate_;
  for (uint32_t v = 0; v < nVertices(); ++v) {
    if (vertexCornerCount_[v] > 0) ++vertices;
    if (vertexHalfedge_[v] != kInvalid) ++c.nUsedVertices;
  }
  c.nEdges = nEdges_;
  c.nBoundaryEdges = nBoundaryEdges_;
  c.nNonManifoldEdges = nNonManifoldEdges_;
  c.nInconsistentEdges = nInconsistentEdges_;
  c.nNonManifoldVertices = nNonManifoldVertices_;
  const EditLoops& l = loops();
  for (uint32_t h = 0; h < l.nLoops(); ++h) (l.loopIsSeam[h] ? c.nSeams : c.nHoles) += 1;
  uint32_t shells = knownShells_ != kInvalid ? knownShells_ : Impl::countShells(*this);
  c.nShells = shells == kInvalid ? 0 : shells;
  stats_ = edit_detail::statsOf(c, vertices);
  statsStale_ = shells == kInvalid || loopsStale_;
  return stats_;
}

std::string EditableMesh::Impl::infoJson(const std::string& file) {
  Mesh m;
  Topology t;
  if (!toMesh(m, &t).ok()) return "";
  return stltopo::infoJson(file, m, &t);
}

// ============================================================================ output

Status EditableMesh::Impl::toMesh(Mesh& out, Topology* topo, CompactMaps* maps, bool triangleShell,
                                  bool figures) const {
  // out and the maps start as Mesh{} and CompactMaps{}, but their arrays keep their memory
  // (emptied()).
  {
    Mesh fresh;
    fresh.positions = emptied(out.positions);
    fresh.triangles = emptied(out.triangles);
    fresh.attributes = emptied(out.attributes);
    fresh.normals = emptied(out.normals);
    fresh.colors = emptied(out.colors);
    fresh.colorValid = emptied(out.colorValid);
    out = std::move(fresh);
  }
  CompactMaps local;
  CompactMaps& mp = maps ? *maps : local;
  mp.vertices.clear();
  mp.triangles.clear();
  mp.halfedges.clear();
  const uint32_t nvSlots = nVertices(), ntSlots = nTriangles(), nhSlots = nHalfedges();
  if (!mp.vertices.assign(nvSlots, kInvalid) || !mp.triangles.assign(ntSlots, kInvalid) ||
      ((topo || maps) && !mp.halfedges.assign(nhSlots, kInvalid)))
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
  }
  STLTOPO_CATCH { return detail::oom(kEditArrays); }
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
    const float* n = normal ? static_cast<const float*>(normal->data) + 3 * size_t(t) : nullptr;
    if (n) std::memcpy(out.normals.data() + 3 * size_t(w), n, 3 * sizeof(float));
    if (!figures) continue;
    // Figures, as the reader computes them.
    const detail::TriangleFigures fig = detail::triangleFigures(P[0], P[1], P[2]);
    out.area += fig.area;
    out.volume += fig.volume;
    if (n && detail::normalMismatch(n, fig, P[0], P[1], P[2])) ++out.normalMismatches;
  }
  uint32_t first = 0;
  for (Solid& s : out.solids) {
    s.firstTriangle = first;
    first += s.triangleCount;
  }
  // Half-edges: pairs numbered in order of their first side in (triangle, corner) order;
  // that side's half-edge becomes even. Only for a topology or the caller's maps (the
  // repair asks for the plain mesh several times per step).
  if (!topo && !maps) return Status{};
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
  {
    // Topology{}, but its arrays keep their memory (emptied(), as `out`'s above).
    Topology fresh;
    fresh.next = emptied(T.next);
    fresh.prev = emptied(T.prev);
    fresh.vert = emptied(T.vert);
    fresh.face = emptied(T.face);
    fresh.pairKind = emptied(T.pairKind);
    fresh.triangleHalfedge = emptied(T.triangleHalfedge);
    fresh.vertexHalfedge = emptied(T.vertexHalfedge);
    fresh.vertexWeld = emptied(T.vertexWeld);
    fresh.loopHalfedge = emptied(T.loopHalfedge);
    fresh.loopOffsets = emptied(T.loopOffsets);
    fresh.loopHalfedges = emptied(T.loopHalfedges);
    fresh.loopIsSeam = emptied(T.loopIsSeam);
    fresh.loopPerimeter = emptied(T.loopPerimeter);
    fresh.triangleDegenerate = emptied(T.triangleDegenerate);
    fresh.vertexNonManifold = emptied(T.vertexNonManifold);
    fresh.triangleShell = emptied(T.triangleShell);
    T = std::move(fresh);
  }
  const uint32_t nh = 2 * nPairs;
  T.nTriangles = nt;
  T.nVertices = nv;
  // The editable mesh is welded already (a tolerance weld was applied by init()): its
  // compacted form has the exact weld.
  T.tolerance = 0;
  T.nWeldedVertices = nv;
  EditLoops L;
  if (!Impl::labelLoops(*this, L, nullptr)) return detail::oom(kEditArrays);
  if (!T.next.resize(nh) || !T.prev.resize(nh) || !T.vert.resize(nh) || !T.face.resize(nh) ||
      !T.pairKind.resize(nPairs) || !T.triangleHalfedge.resize(nt) || !T.vertexHalfedge.assign(nv, kInvalid) ||
      !T.vertexWeld.resize(nv) || !T.triangleDegenerate.resize(nt) || !T.vertexNonManifold.resize(nv))
    return detail::oom(kEditArrays);
  for (uint32_t e = 0; e < nhSlots; ++e) {
    uint32_t y = mp.halfedges[e];
    if (y == kInvalid) continue;
    T.next[y] = mp.halfedges[next_[e]];
    T.prev[y] = mp.halfedges[prev_[e]];
    T.vert[y] = mp.vertices[vert_[e]];
    T.face[y] = Impl::boundaryFace(face_[e]) ? nt : mp.triangles[face_[e]];  // a loop's: set below
    if (!(y & 1u)) T.pairKind[y >> 1] = pairKind_[e >> 1];
  }
  for (uint32_t h = 0; h < L.nLoops(); ++h)
    for (uint32_t i = L.loopOffsets[h]; i < L.loopOffsets[h + 1]; ++i)
      T.face[mp.halfedges[L.loopHalfedges[i]]] = nt + h;
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
  if (triangleShell) {
    if (!Impl::labelShells(*this, mp.triangles, T.triangleShell, T.nShells)) return detail::oom(kEditArrays);
    return Status{};
  }
  uint32_t shells = Impl::countShells(*this);
  if (shells == kInvalid) return detail::oom(kEditArrays);
  T.nShells = shells;
  return Status{};
}

Status EditableMesh::Impl::compact(CompactMaps* maps) {
  CompactMaps local;
  CompactMaps& mp = maps ? *maps : local;
  Mesh m;
  Topology t;
  Status s = toMesh(m, &t, &mp);
  if (!s.ok()) return s;
  Impl fresh;
  s = fresh.init(m, t);
  if (!s.ok()) return s;
  // Every attribute, renumbered (init made the file's ones again; these replace them).
  std::vector<Attribute> renumbered;
  STLTOPO_TRY { renumbered.resize(attributes_.size()); }
  STLTOPO_CATCH { return detail::oom(kEditArrays); }
  for (size_t i = 0; i < attributes_.size(); ++i) {
    Attribute& a = attributes_[i];
    Attribute& x = renumbered[i];
    const size_t st = Impl::stride(a);
    const Array<uint32_t>* map = nullptr;
    size_t n = 0, step = 1;
    switch (a.view.element) {
      case Element::Vertex:
        map = &mp.vertices;
        n = t.nVertices;
        break;
      case Element::Triangle:
        map = &mp.triangles;
        n = t.nTriangles;
        break;
      case Element::Edge:
        map = &mp.halfedges;
        n = t.nHalfedges() / 2;
        step = 2;
        break;
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
    }
    STLTOPO_CATCH { return detail::oom(kEditArrays); }
    x.view = a.view;
    x.view.data = x.bytes.data();
    x.view.count = n;
  }
  fresh.attributes_ = std::move(renumbered);
  *this = std::move(fresh);
  return Status{};
}

// ============================================================================ validate

Status EditableMesh::Impl::validate() const {
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
      if (h >= nh || vert_[h] != triangles_[3 * size_t(t) + c] || face_[h] != t)
        return bad("side half-edge differs from its side", t);
      if (next_[h] != sideHalfedge_[3 * size_t(t) + nextCorner(c)])
        return bad("triangle next differs from its sides", t);
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
    if (Impl::boundaryFace(face_[e]) && Impl::boundaryFace(face_[e + 1]))
      return bad("pair of two boundary half-edges", e);
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

}  // namespace stltopo
