// validate(): checks every invariant of a Topology against its Mesh.
#include <cstdio>

#include "detail.h"

namespace stltopo {
namespace {
Status bad(const char* what, uint32_t element) {
  Status s = Status::error(Code::Invalid, detail::format("%s (element %u)", what, element));
  s.element = element;
  return s;
}
Status oom() { return Status::error(Code::OutOfMemory, "could not allocate validate()'s work arrays"); }
}  // namespace

Status validate(const Mesh& mesh, const Topology& t) {
  const uint32_t nh = t.nHalfedges(), nt = mesh.nTriangles(), nv = mesh.nVertices();
  const uint32_t nl = t.nLoops(), nf = nt + nl;
  // The counts agree with the arrays.
  if (t.nTriangles != nt || t.nVertices != nv) return bad("triangle/vertex counts differ from the mesh", 0);
  if (nh % 2 != 0) return bad("odd number of half-edges", nh);
  if (nh > 0 && t.prev.empty() && t.face.empty())
    return bad("prev and face were not built (TopologyOptions::prevAndFace = false)", nh);
  if (t.prev.size() != nh || t.vert.size() != nh || t.face.size() != nh || t.pairKind.size() != nh / 2)
    return bad("half-edge arrays differ in length", nh);
  if (t.triangleHalfedge.size() != nt || t.triangleDegenerate.size() != nt) return bad("per-triangle arrays have the wrong length", nt);
  if (t.vertexHalfedge.size() != nv || t.vertexNonManifold.size() != nv || t.vertexWeld.size() != nv)
    return bad("per-vertex arrays have the wrong length", nv);
  if (t.loopOffsets.size() != size_t(nl) + 1 || t.loopIsSeam.size() != nl || t.loopPerimeter.size() != nl)
    return bad("per-loop arrays have the wrong length", nl);
  if (t.nHoles + t.nSeams != nl) return bad("holes + seams differ from the number of loops", nl);

  for (uint32_t e = 0; e < nh; ++e) {
    uint32_t n = t.next[e];
    if (n >= nh) return bad("next out of range", e);
    if (t.prev[n] != e) return bad("next is not a permutation (prev[next[e]] != e)", e);
    if (t.vert[e] >= nv) return bad("vert out of range", e);
    if (t.face[e] >= nf) return bad("face out of range", e);
    if (t.face[n] != t.face[e]) return bad("next leaves the face", e);
    if (t.vert[n] != t.vert[e ^ 1u]) return bad("vert[next[e]] != vert[twin(e)]", e);
    if (t.vert[e] == t.vert[e ^ 1u]) return bad("half-edge is a self-loop", e);
    if (((e ^ 1u) ^ 1u) != e || (e ^ 1u) >= nh) return bad("twin is not an involution", e);
  }
  // vnext stays at the vertex, so its cycles partition each vertex's outgoing half-edges.
  // (A second pass: next[e ^ 1] is known to be in range only now.)
  for (uint32_t e = 0; e < nh; ++e)
    if (t.vert[t.next[e ^ 1u]] != t.vert[e]) return bad("vnext leaves the vertex", e);
  // Every triangle has its 3 half-edges; next cycles are exactly the faces.
  Array<uint32_t> perFace;
  if (!perFace.assign(nf, 0)) {
    return oom();
  }
  for (uint32_t e = 0; e < nh; ++e) ++perFace[t.face[e]];
  for (uint32_t f = 0; f < nt; ++f) {
    uint32_t h = t.triangleHalfedge[f];
    bool degen = t.triangleDegenerate[f] != 0;
    if (degen) {
      if (h != kInvalid || perFace[f] != 0) return bad("degenerate triangle has half-edges", f);
      continue;
    }
    if (h >= nh || t.face[h] != f) return bad("triangle half-edge does not belong to the triangle", f);
    if (t.next[t.next[t.next[h]]] != h || perFace[f] != 3) return bad("triangle is not a 3-cycle", f);
    for (int c = 0; c < 3; ++c) {
      uint32_t e = h;
      for (int k = 0; k < c; ++k) e = t.next[e];
      if (t.vert[e] != t.vertexWeld[mesh.triangles[3 * size_t(f) + c]]) return bad("triangle half-edge vertex differs from its corner", f);
    }
  }
  // The loop offsets span the listing in order (so every index below is in range).
  if (t.loopOffsets[0] != 0 || t.loopOffsets[nl] != t.loopHalfedges.size())
    return bad("loop offsets do not span the loop listing", nl);
  for (uint32_t l = 0; l < nl; ++l)
    if (t.loopOffsets[l + 1] < t.loopOffsets[l]) return bad("loop offsets decrease", nt + l);
  uint64_t loopTotal = 0;
  for (uint32_t l = 0; l < nl; ++l) {
    uint32_t h = t.loopHalfedge[l], len = t.loopOffsets[l + 1] - t.loopOffsets[l];
    if (h >= nh || t.face[h] != nt + l) return bad("loop half-edge does not belong to the loop", nt + l);
    uint32_t x = h, steps = 0;
    do {
      if (steps >= len) return bad("loop is longer than listed", nt + l);
      if (t.loopHalfedges[t.loopOffsets[l] + steps] != x) return bad("loop listing differs from next order", nt + l);
      x = t.next[x];
      ++steps;
    } while (x != h);
    if (steps != len || perFace[nt + l] != len) return bad("loop cycle differs from the loop's half-edges", nt + l);
    if (len < 2) return bad("loop shorter than 2 half-edges", nt + l);
    loopTotal += len;
  }
  if (loopTotal != t.loopHalfedges.size()) return bad("loop listing length differs", nl);
  // Vertex lookups.
  Array<uint8_t> used;
  if (!used.assign(nv, 0)) {
    return oom();
  }
  for (uint32_t e = 0; e < nh; ++e) used[t.vert[e]] = 1;
  uint32_t nUsed = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    uint32_t h = t.vertexHalfedge[v];
    if (used[v]) {
      ++nUsed;
      if (h >= nh || t.vert[h] != v) return bad("vertexHalfedge does not leave its vertex", v);
    } else if (h != kInvalid) {
      return bad("unused vertex has a half-edge", v);
    }
  }
  if (nUsed != t.nUsedVertices) return bad("used-vertex count differs", nUsed);
  return Status{};
}

}  // namespace stltopo
