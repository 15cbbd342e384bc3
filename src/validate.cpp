// validate(): checks every invariant of a Topology against its Mesh.
#include <cstdio>

#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"
#include "text_format.h"
#include "try_alloc.h"

namespace stltopo {
namespace {
Status bad(const char* what, uint32_t element) {
  Status s = Status::error(Code::Invalid, detail::format("%s (element %u)", what, element));
  s.element = element;
  return s;
}
// What out-of-memory says could not be allocated.
constexpr const char* kWorkArrays = "validate()'s work arrays";
Status badCount(const char* what, uint32_t expected) {
  Status s = Status::error(Code::Invalid, detail::format("%s (expected %u)", what, expected));
  s.element = expected;
  return s;
}

// Triangles joined by union-find with path halving, for the shell count.
uint32_t findRoot(uint32_t* parent, uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}
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
  if (t.triangleHalfedge.size() != nt || t.triangleDegenerate.size() != nt)
    return bad("per-triangle arrays have the wrong length", nt);
  if (t.vertexHalfedge.size() != nv || t.vertexNonManifold.size() != nv || t.vertexWeld.size() != nv)
    return bad("per-vertex arrays have the wrong length", nv);
  if (t.loopOffsets.size() != size_t(nl) + 1 || t.loopIsSeam.size() != nl || t.loopPerimeter.size() != nl)
    return bad("per-loop arrays have the wrong length", nl);
  if (t.nHoles + t.nSeams != nl) return bad("holes + seams differ from the number of loops", nl);
  // The arrays as raw pointers (their lengths are checked above): in wasm this file is compiled
  // for size (-Oz), which kept every Array accessor a call, one per element read; on pointers,
  // validate() of the 1M tori took about 0.7x its time (bench/PROFILE.md, *Stop 60*).
  const uint32_t *next = t.next.data(), *prev = t.prev.data(), *vert = t.vert.data(), *face = t.face.data();
  const uint8_t* pairKind = t.pairKind.data();
  const uint32_t *triangleHalfedge = t.triangleHalfedge.data(), *vertexHalfedge = t.vertexHalfedge.data();
  const uint32_t* vertexWeld = t.vertexWeld.data();
  const uint8_t *triangleDegenerate = t.triangleDegenerate.data(), *vertexNonManifold = t.vertexNonManifold.data();
  const uint32_t *loopHalfedge = t.loopHalfedge.data(), *loopOffsets = t.loopOffsets.data();
  const uint32_t* loopHalfedges = t.loopHalfedges.data();
  const uint8_t* loopIsSeam = t.loopIsSeam.data();
  const uint32_t* corners = mesh.triangles.data();

  for (uint32_t e = 0; e < nh; ++e) {
    uint32_t n = next[e];
    if (n >= nh) return bad("next out of range", e);
    if (prev[n] != e) return bad("next is not a permutation (prev[next[e]] != e)", e);
    if (vert[e] >= nv) return bad("vert out of range", e);
    if (face[e] >= nf) return bad("face out of range", e);
    if (face[n] != face[e]) return bad("next leaves the face", e);
    if (vert[n] != vert[e ^ 1u]) return bad("vert[next[e]] != vert[twin(e)]", e);
    if (vert[e] == vert[e ^ 1u]) return bad("half-edge is a self-loop", e);
  }
  // vnext stays at the vertex, so its cycles partition each vertex's outgoing half-edges.
  // (A second pass: next[e ^ 1] is known to be in range only now.)
  for (uint32_t e = 0; e < nh; ++e)
    if (vert[next[e ^ 1u]] != vert[e]) return bad("vnext leaves the vertex", e);
  // Every triangle has its 3 half-edges; next cycles are exactly the faces.
  Array<uint32_t> perFaceArray;
  if (!perFaceArray.assign(nf, 0)) {
    return detail::oom(kWorkArrays);
  }
  uint32_t* perFace = perFaceArray.data();
  for (uint32_t e = 0; e < nh; ++e) ++perFace[face[e]];
  for (uint32_t f = 0; f < nt; ++f) {
    uint32_t h = triangleHalfedge[f];
    bool degen = triangleDegenerate[f] != 0;
    if (degen) {
      if (h != kInvalid || perFace[f] != 0) return bad("degenerate triangle has half-edges", f);
      continue;
    }
    if (h >= nh || face[h] != f) return bad("triangle half-edge does not belong to the triangle", f);
    if (next[next[next[h]]] != h || perFace[f] != 3) return bad("triangle is not a 3-cycle", f);
    for (int c = 0; c < 3; ++c) {
      uint32_t e = h;
      for (int k = 0; k < c; ++k) e = next[e];
      if (vert[e] != vertexWeld[corners[3 * size_t(f) + c]])
        return bad("triangle half-edge vertex differs from its corner", f);
    }
  }
  // The loop offsets span the listing in order (so every index below is in range).
  if (loopOffsets[0] != 0 || loopOffsets[nl] != t.loopHalfedges.size())
    return bad("loop offsets do not span the loop listing", nl);
  for (uint32_t l = 0; l < nl; ++l)
    if (loopOffsets[l + 1] < loopOffsets[l]) return bad("loop offsets decrease", nt + l);
  uint64_t loopTotal = 0;
  for (uint32_t l = 0; l < nl; ++l) {
    uint32_t h = loopHalfedge[l], len = loopOffsets[l + 1] - loopOffsets[l];
    if (h >= nh || face[h] != nt + l) return bad("loop half-edge does not belong to the loop", nt + l);
    uint32_t x = h, steps = 0;
    do {
      if (steps >= len) return bad("loop is longer than listed", nt + l);
      if (loopHalfedges[loopOffsets[l] + steps] != x) return bad("loop listing differs from next order", nt + l);
      x = next[x];
      ++steps;
    } while (x != h);
    if (steps != len || perFace[nt + l] != len) return bad("loop cycle differs from the loop's half-edges", nt + l);
    if (len < 2) return bad("loop shorter than 2 half-edges", nt + l);
    loopTotal += len;
  }
  if (loopTotal != t.loopHalfedges.size()) return bad("loop listing length differs", nl);
  // Vertex lookups.
  Array<uint8_t> usedArray;
  if (!usedArray.assign(nv, 0)) {
    return detail::oom(kWorkArrays);
  }
  uint8_t* used = usedArray.data();
  for (uint32_t e = 0; e < nh; ++e) used[vert[e]] = 1;
  uint32_t nUsed = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    uint32_t h = vertexHalfedge[v];
    if (used[v]) {
      ++nUsed;
      if (h >= nh || vert[h] != v) return bad("vertexHalfedge does not leave its vertex", v);
    } else if (h != kInvalid) {
      return bad("unused vertex has a half-edge", v);
    }
  }
  if (nUsed != t.nUsedVertices) return bad("used-vertex count differs", nUsed);

  // Degenerate triangles: two corners on one vertex of the weld.
  uint32_t nDegenerate = 0;
  for (uint32_t f = 0; f < nt; ++f) {
    const uint32_t* c = corners + 3 * size_t(f);
    uint32_t a = vertexWeld[c[0]], b = vertexWeld[c[1]], d = vertexWeld[c[2]];
    if (a >= nv || b >= nv || d >= nv) return bad("vertexWeld out of range", f);
    bool degen = a == b || b == d || a == d;
    if (degen != (triangleDegenerate[f] != 0)) return bad("triangleDegenerate differs from the welded corners", f);
    nDegenerate += degen;
  }
  if (nDegenerate != t.nDegenerate) return badCount("degenerate-triangle count differs", nDegenerate);
  uint32_t nReps = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    uint32_t r = vertexWeld[v];
    if (r > v || vertexWeld[r] != r) return bad("vertexWeld is not a lowest-id representative", v);
    nReps += r == v;
  }
  if (nReps != t.nWeldedVertices) return badCount("welded-vertex count differs", nReps);

  // Undirected edges: pair k joins the smaller and the larger of its two vertices. The
  // pairs are bucketed by the smaller one, and within a bucket an edge id is given per
  // larger vertex (stamp[b] = the bucket that last saw b): O(n).
  const uint32_t np = nh / 2;
  Array<uint32_t> offArray, byLowArray, edgeOfArray, stampArray, edgeAtArray;
  if (!offArray.assign(size_t(nv) + 1, 0) || !byLowArray.resize(np) || !edgeOfArray.resize(np) ||
      !stampArray.assign(nv, kInvalid) || !edgeAtArray.resize(nv))
    return detail::oom(kWorkArrays);
  uint32_t *off = offArray.data(), *byLow = byLowArray.data(), *edgeOf = edgeOfArray.data();
  uint32_t *stamp = stampArray.data(), *edgeAt = edgeAtArray.data();
  // (Not std::min and std::max, which -Oz kept out of line.)
  auto lo = [&](uint32_t k) { return vert[2 * k] < vert[2 * k + 1] ? vert[2 * k] : vert[2 * k + 1]; };
  auto hi = [&](uint32_t k) { return vert[2 * k] < vert[2 * k + 1] ? vert[2 * k + 1] : vert[2 * k]; };
  for (uint32_t k = 0; k < np; ++k) ++off[lo(k) + 1];
  for (uint32_t v = 0; v < nv; ++v) off[v + 1] += off[v];
  for (uint32_t k = 0; k < np; ++k) byLow[off[lo(k)]++] = k;  // off[v] now ends bucket v
  uint32_t nEdges = 0;
  for (uint32_t v = 0, begin = 0; v < nv; begin = off[v++]) {
    for (uint32_t i = begin; i < off[v]; ++i) {
      uint32_t k = byLow[i], b = hi(k);
      if (stamp[b] != v) {
        stamp[b] = v;
        edgeAt[b] = nEdges++;
      }
      edgeOf[k] = edgeAt[b];
    }
  }
  // Per edge: its triangle sides and whether a side of it is cut (unpaired).
  Array<uint32_t> sidesArray;
  Array<uint8_t> cutArray;
  if (!sidesArray.assign(nEdges, 0) || !cutArray.assign(nEdges, 0)) return detail::oom(kWorkArrays);
  uint32_t* sides = sidesArray.data();
  uint8_t* cut = cutArray.data();
  for (uint32_t k = 0; k < np; ++k) {
    bool left = face[2 * k] < nt, right = face[2 * k + 1] < nt;
    if (!left && !right) return bad("pair has no triangle side", 2 * k);
    sides[edgeOf[k]] += uint32_t(left) + uint32_t(right);
    if (!left || !right) cut[edgeOf[k]] = 1;
  }
  uint32_t nBoundary = 0, nInconsistent = 0, nNonManifold = 0;
  for (uint32_t g = 0; g < nEdges; ++g) {
    if (sides[g] == 1)
      ++nBoundary;
    else if (sides[g] == 2 && cut[g])
      ++nInconsistent;
    else if (sides[g] >= 3)
      ++nNonManifold;
  }
  for (uint32_t k = 0; k < np; ++k) {
    uint32_t m = sides[edgeOf[k]];
    bool paired = face[2 * k] < nt && face[2 * k + 1] < nt;
    EdgeKind want = m == 1   ? EdgeKind::Boundary
                    : m == 2 ? (paired ? EdgeKind::Interior : EdgeKind::Inconsistent)
                             : EdgeKind::NonManifold;
    if (pairKind[k] != uint8_t(want)) return bad("pairKind differs from the sides of its edge", k);
  }
  if (nEdges != t.nEdges) return badCount("edge count differs", nEdges);
  if (nBoundary != t.nBoundaryEdges) return badCount("boundary-edge count differs", nBoundary);
  if (nInconsistent != t.nInconsistentEdges) return badCount("inconsistent-edge count differs", nInconsistent);
  if (nNonManifold != t.nNonManifoldEdges) return badCount("non-manifold-edge count differs", nNonManifold);

  // Loops: a seam holds a cut side of an inconsistent or non-manifold edge.
  uint32_t nSeams = 0;
  for (uint32_t l = 0; l < nl; ++l) {
    bool seam = false;
    for (uint32_t i = loopOffsets[l]; i < loopOffsets[l + 1]; ++i)
      seam |= pairKind[loopHalfedges[i] >> 1] != uint8_t(EdgeKind::Boundary);
    if (seam != (loopIsSeam[l] != 0)) return bad("loopIsSeam differs from the loop's edges", nt + l);
    nSeams += seam;
  }
  if (nSeams != t.nSeams || nl - nSeams != t.nHoles) return badCount("hole or seam count differs", nl - nSeams);

  // Vertices: non-manifold when the vnext cycle through vertexHalfedge misses an outgoing
  // half-edge (vnext is a permutation: next is one, checked above).
  Array<uint32_t> degreeArray;
  if (!degreeArray.assign(nv, 0)) return detail::oom(kWorkArrays);
  uint32_t* degree = degreeArray.data();
  for (uint32_t e = 0; e < nh; ++e) ++degree[vert[e]];
  uint32_t nNonManifoldVertices = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    uint32_t e0 = vertexHalfedge[v];
    bool nm = false;
    if (e0 != kInvalid) {
      uint32_t x = e0, steps = 0;
      do {
        x = next[x ^ 1u];
        ++steps;
      } while (x != e0 && steps <= degree[v]);
      nm = steps != degree[v];
    }
    if (nm != (vertexNonManifold[v] != 0)) return bad("vertexNonManifold differs from the vertex's cycles", v);
    nNonManifoldVertices += nm;
  }
  if (nNonManifoldVertices != t.nNonManifoldVertices)
    return badCount("non-manifold-vertex count differs", nNonManifoldVertices);

  // Shells: the triangles that share an undirected edge are one shell.
  Array<uint32_t> parentArray, firstTriangleArray;
  if (!parentArray.resize(nt) || !firstTriangleArray.assign(nEdges, kInvalid)) return detail::oom(kWorkArrays);
  uint32_t *parent = parentArray.data(), *firstTriangle = firstTriangleArray.data();
  for (uint32_t f = 0; f < nt; ++f) parent[f] = f;
  for (uint32_t e = 0; e < nh; ++e) {
    uint32_t f = face[e];
    if (f >= nt) continue;
    uint32_t& first = firstTriangle[edgeOf[e >> 1]];
    if (first == kInvalid) {
      first = f;
      continue;
    }
    uint32_t a = findRoot(parent, first), b = findRoot(parent, f);
    if (a < b) parent[b] = a;
    if (b < a) parent[a] = b;
  }
  uint32_t nShells = 0;
  for (uint32_t f = 0; f < nt; ++f) nShells += !triangleDegenerate[f] && findRoot(parent, f) == f;
  if (nShells != t.nShells) return badCount("shell count differs", nShells);
  if (!t.triangleShell.empty()) {
    // The shells numbered by their lowest triangle: the first triangle met of each root.
    if (t.triangleShell.size() != nt) return bad("triangleShell has the wrong length", nt);
    Array<uint32_t> numberArray;
    if (!numberArray.assign(nt, kInvalid)) return detail::oom(kWorkArrays);
    uint32_t* number = numberArray.data();
    const uint32_t* triangleShell = t.triangleShell.data();
    uint32_t n = 0;
    for (uint32_t f = 0; f < nt; ++f) {
      uint32_t want = kInvalid;
      if (!triangleDegenerate[f]) {
        uint32_t& r = number[findRoot(parent, f)];
        if (r == kInvalid) r = n++;
        want = r;
      }
      if (triangleShell[f] != want) return bad("triangleShell differs from the shells", f);
    }
  }
  return Status{};
}

}  // namespace stltopo
