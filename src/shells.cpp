// The per-shell report and the defect lists, from a mesh, its topology and the shell of
// each triangle. Uses next, vert, pairKind and the per-element arrays, never prev or face.
#include "stltopo/shells.h"

#include <algorithm>
#include <cmath>

#include "detail.h"

namespace stltopo {
namespace {

Status bad(const char* msg) { return Status::error(Code::InvalidArgument, msg); }
Status oom() { return Status::error(Code::OutOfMemory, "could not allocate the shell and defect lists"); }

// A triangle side on a cut (inconsistent or non-manifold) edge.
struct CutSide {
  uint32_t a, b;  // the edge's vertices, a < b
  uint32_t triangle;
  uint8_t kind;   // EdgeKind
  bool operator<(const CutSide& o) const {
    return a != o.a ? a < o.a : b != o.b ? b < o.b : triangle < o.triangle;
  }
};

// A triangle half-edge leaving a non-manifold vertex, with the shell of its triangle.
struct Outgoing {
  uint32_t halfedge, shell;
  bool visited;
  bool operator<(const Outgoing& o) const { return halfedge < o.halfedge; }
};

// One vnext cycle of a non-manifold vertex and the shell it lies in.
struct Cycle {
  uint32_t vertex, shell;
  bool operator<(const Cycle& o) const { return vertex != o.vertex ? vertex < o.vertex : shell < o.shell; }
};

// The triangle half-edge that is the twin of loop h's first half-edge, and h.
struct LoopTwin {
  uint32_t halfedge, loop;
  bool operator<(const LoopTwin& o) const { return halfedge < o.halfedge; }
};

bool testBit(const Array<uint64_t>& bits, uint32_t i) { return (bits[i >> 6] >> (i & 63)) & 1u; }
void setBit(Array<uint64_t>& bits, uint32_t i) { bits[i >> 6] |= uint64_t(1) << (i & 63); }

// Which corners of a triangle with welded corners a, b, c coincide (Defects::degenerateCorners).
uint8_t cornerMask(uint32_t a, uint32_t b, uint32_t c) {
  return uint8_t((a == b ? 1 : 0) | (b == c ? 2 : 0) | (c == a ? 4 : 0));
}

}  // namespace

const char* orientationName(Orientation o) {
  switch (o) {
    case Orientation::Inconsistent: return "inconsistent";
    case Orientation::Open: return "open";
    case Orientation::Outward: return "outward";
    case Orientation::Inward: return "inward";
    case Orientation::Flat: return "flat";
  }
  return "unknown";
}

Orientation Shell::orientation() const {
  if (inconsistentEdges > 0) return Orientation::Inconsistent;
  if (boundaryEdges > 0) return Orientation::Open;
  if (volume > 0) return Orientation::Outward;
  if (volume < 0) return Orientation::Inward;
  return Orientation::Flat;
}

Status findShellsAndDefects(const Mesh& mesh, const Topology& topo, Array<Shell>* shellsOut, Defects* defectsOut) {
  if (shellsOut) *shellsOut = Array<Shell>{};
  if (defectsOut) *defectsOut = Defects{};
  const uint32_t nt = mesh.nTriangles(), nv = mesh.nVertices(), nh = topo.nHalfedges(), nl = topo.nLoops();
  const uint32_t nShells = topo.nShells;
  if (topo.nTriangles != nt || topo.nVertices != nv || topo.triangleHalfedge.size() != nt ||
      topo.triangleDegenerate.size() != nt || topo.vertexNonManifold.size() != nv || topo.vertexWeld.size() != nv ||
      topo.vert.size() != nh || topo.pairKind.size() != nh / 2 || topo.loopOffsets.size() != size_t(nl) + 1 ||
      topo.loopIsSeam.size() != nl)
    return bad("the topology was not built from this mesh");
  if (topo.triangleShell.size() != nt)
    return bad("the topology has no triangleShell (TopologyOptions::triangleShell = false)");
  const uint32_t* triangleShell = topo.triangleShell.data();

  Array<Shell> shells;
  Defects d;
  Array<uint64_t> seen;        // per vertex: counted in its (only) shell; manifold vertices only
  Array<uint64_t> loopTwinBit;  // per half-edge: the twin of a loop's first half-edge
  Array<LoopTwin> loopTwins;
  Array<CutSide> cuts;
  Array<Outgoing> outgoing;
  if (!shells.assign(nShells, Shell{}) || !seen.assign((size_t(nv) + 63) / 64, 0) ||
      !loopTwinBit.assign((size_t(nh) + 63) / 64, 0) || !loopTwins.resize(nl) || !d.loopShell.assign(nl, kInvalid))
    return oom();
  for (uint32_t h = 0; h < nl; ++h) {
    uint32_t e = twin(topo.loopHalfedge[h]);  // a loop half-edge's twin is a triangle side
    if (e >= nh) return bad("the topology was not built from this mesh");
    loopTwins[h] = {e, h};
    setBit(loopTwinBit, e);
  }
  std::sort(loopTwins.begin(), loopTwins.end());

  // One pass over the triangles in file order: the shells' triangles, figures, edges that
  // are not cut, vertices that are manifold and loops; the cut sides, the half-edges leaving
  // non-manifold vertices and the degenerate triangles are collected for the passes below.
  const uint32_t* next = topo.next.data();
  const uint32_t* vert = topo.vert.data();
  const float* P = mesh.positions.data();
  const std::vector<Solid>& solids = mesh.solids;
  size_t solid = 0;
  uint32_t nextShell = 0;
  const bool exactWeld = !(topo.tolerance > 0);
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t* corner = mesh.triangles.data() + size_t(t) * 3;
    uint32_t s = triangleShell[t];
    if (topo.triangleDegenerate[t]) {
      if (s != kInvalid) return bad("triangleShell: a degenerate triangle has a shell");
      if (defectsOut) {
        const uint32_t* w = topo.vertexWeld.data();
        if (!d.degenerateTriangles.push_back(t) ||
            !d.degenerateCorners.push_back(cornerMask(w[corner[0]], w[corner[1]], w[corner[2]])))
          return oom();
      }
      continue;
    }
    if (s >= nShells) return bad("triangleShell: a shell id out of range");
    Shell& S = shells[s];
    while (solid < solids.size() && t >= uint64_t(solids[solid].firstTriangle) + solids[solid].triangleCount) ++solid;
    uint32_t solidOfT = solid < solids.size() && t >= solids[solid].firstTriangle ? uint32_t(solid) : kInvalid;
    if (S.triangles == 0) {
      if (s != nextShell++) return bad("triangleShell: shells are not numbered by their lowest triangle id");
      S.firstTriangle = t;
      S.solid = solidOfT;
      for (int k = 0; k < 3; ++k) S.bboxMin[k] = S.bboxMax[k] = P[size_t(corner[0]) * 3 + k];
    } else if (S.solid != solidOfT) {
      S.solid = kMixedSolid;
    }
    ++S.triangles;

    const float* A = P + size_t(corner[0]) * 3;
    const float* B = P + size_t(corner[1]) * 3;
    const float* C = P + size_t(corner[2]) * 3;
    detail::TriangleFigures fig = detail::triangleFigures(A, B, C);
    S.area += fig.area;
    S.volume += fig.volume;
    for (const float* Q : {A, B, C})
      for (int k = 0; k < 3; ++k) {
        S.bboxMin[k] = std::min(S.bboxMin[k], Q[k]);
        S.bboxMax[k] = std::max(S.bboxMax[k], Q[k]);
      }

    // The corners as the topology sees them: vert[] of the triangle's half-edges, read from
    // the triangle (in order) instead of through next (at random places on shuffled files).
    uint32_t wc[3];
    for (int c = 0; c < 3; ++c) wc[c] = exactWeld ? corner[c] : topo.vertexWeld[corner[c]];
    uint32_t e = topo.triangleHalfedge[t];
    for (int c = 0; c < 3; ++c, e = next[e]) {
      uint32_t v = wc[c];
      if (topo.vertexNonManifold[v]) {
        if (!outgoing.push_back({e, s, false})) return oom();
      } else if (!testBit(seen, v)) {
        setBit(seen, v);
        ++S.vertices;
      }
      auto kind = EdgeKind(topo.pairKind[e >> 1]);
      if (kind == EdgeKind::Interior) {
        if (!(e & 1u)) ++S.edges;  // both sides are triangle half-edges: count the pair once
      } else if (kind == EdgeKind::Boundary) {
        ++S.edges;
        ++S.boundaryEdges;
      } else {
        uint32_t w = wc[c == 2 ? 0 : c + 1];
        if (!cuts.push_back({std::min(v, w), std::max(v, w), t, uint8_t(kind)})) return oom();
      }
      if (kind != EdgeKind::Interior && testBit(loopTwinBit, e)) {
        const LoopTwin* it = std::lower_bound(loopTwins.begin(), loopTwins.end(), LoopTwin{e, 0});
        d.loopShell[it->loop] = s;
      }
    }
  }
  if (nextShell != nShells) return bad("triangleShell: fewer shells than Topology::nShells");
  seen.release();
  loopTwinBit.release();
  loopTwins.release();
  for (uint32_t h = 0; h < nl; ++h) {
    if (d.loopShell[h] == kInvalid) return bad("the topology was not built from this mesh");
    if (topo.loopIsSeam[h]) ++shells[d.loopShell[h]].seams; else ++shells[d.loopShell[h]].holes;
  }

  // Cut edges: the sides of one undirected edge are adjacent once sorted.
  std::sort(cuts.begin(), cuts.end());
  if (defectsOut && !d.nonManifoldEdgeOffsets.push_back(0)) return oom();
  for (size_t i = 0; i < cuts.size();) {
    size_t j = i + 1;
    while (j < cuts.size() && cuts[j].a == cuts[i].a && cuts[j].b == cuts[i].b) ++j;
    Shell& S = shells[triangleShell[cuts[i].triangle]];
    ++S.edges;
    bool nonManifold = cuts[i].kind == uint8_t(EdgeKind::NonManifold);
    if (nonManifold) ++S.nonManifoldEdges; else ++S.inconsistentEdges;
    if (defectsOut) {
      Array<uint32_t>& vertices = nonManifold ? d.nonManifoldEdgeVertices : d.inconsistentEdgeVertices;
      Array<uint32_t>& triangles = nonManifold ? d.nonManifoldEdgeTriangles : d.inconsistentEdgeTriangles;
      if (!vertices.push_back(cuts[i].a) || !vertices.push_back(cuts[i].b)) return oom();
      for (size_t k = i; k < j; ++k)
        if (!triangles.push_back(cuts[k].triangle)) return oom();
      if (nonManifold && !d.nonManifoldEdgeOffsets.push_back(uint32_t(triangles.size()))) return oom();
    }
    i = j;
  }
  cuts.release();

  // Non-manifold vertices: walk each vnext cycle once, from a triangle half-edge (every
  // cycle has one: the next of a loop half-edge's twin is a triangle half-edge), and note
  // its shell (a cycle never leaves its fan).
  std::sort(outgoing.begin(), outgoing.end());
  Array<Cycle> cycles;
  for (Outgoing& o : outgoing) {
    if (o.visited) continue;
    uint32_t x = o.halfedge, steps = 0;
    do {
      Outgoing* it = std::lower_bound(outgoing.begin(), outgoing.end(), Outgoing{x, 0, false});
      if (it != outgoing.end() && it->halfedge == x) it->visited = true;
      x = next[twin(x)];
      if (++steps > nh) return bad("the topology was not built from this mesh");
    } while (x != o.halfedge);
    if (!cycles.push_back({vert[x], o.shell})) return oom();
  }
  outgoing.release();
  std::sort(cycles.begin(), cycles.end());
  for (size_t i = 0; i < cycles.size();) {
    size_t j = i;
    while (j < cycles.size() && cycles[j].vertex == cycles[i].vertex) {
      size_t k = j;
      while (k < cycles.size() && cycles[k].vertex == cycles[j].vertex && cycles[k].shell == cycles[j].shell) ++k;
      Shell& S = shells[cycles[j].shell];
      ++S.vertices;
      if (k - j > 1) ++S.nonManifoldVertices;
      j = k;
    }
    if (defectsOut && (!d.nonManifoldVertices.push_back(cycles[i].vertex) ||
                       !d.nonManifoldVertexCycles.push_back(uint32_t(j - i))))
      return oom();
    i = j;
  }

  if (shellsOut) *shellsOut = std::move(shells);
  if (defectsOut) *defectsOut = std::move(d);
  return Status{};
}

}  // namespace stltopo
