// stltopo/topology.h: half-edges, boundary loops and problem flags of a Mesh.
#pragma once

#include <cstdint>

#include "stltopo/array.h"
#include "stltopo/counts.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"

namespace stltopo {

struct TopologyOptions {
  // 0 = exact weld (default). > 0: vertices within this absolute distance are
  // merged for the topology only (see README: deterministic, grid-based).
  double tolerance = 0;
  // false: leave Topology::prev and Topology::face empty; every other array, every count
  // and every loop is the same. For callers that only need the report (the CLIs): 8 fewer
  // bytes per half-edge, about 24 per triangle. Navigation through prev or face (lPrev,
  // oNext, lFace, rFace, ...) and validate() need them.
  bool prevAndFace = true;
  // true (with prevAndFace): when prev and face cannot be allocated (they are the last arrays
  // of the pass that peaks), go on without them, as prevAndFace = false would, instead of
  // failing with out-of-memory. The caller tells by prev.size() != nHalfedges(). For callers
  // that can derive them later (the wasm bindings, near the 4 GB heap's end).
  bool prevAndFaceIfRoom = false;
  // true: also build Topology::triangleShell (the shell of each triangle, for the shell
  // report and extractShell): 4 more bytes per triangle in the result, and at the peak.
  bool triangleShell = false;
  // Threads for the passes that split (ReadOptions::threads): 1 = one thread (the default),
  // 0 = the machine's hardware threads. Every array, count and loop is the same for every
  // value. The wasm build always uses one.
  unsigned threads = 1;
};

// Edge classes per half-edge pair (index k = e >> 1).
enum class EdgeKind : uint8_t {
  Interior = 0,      // paired: the edge is used by exactly two opposite sides
  Boundary = 1,      // edge used by exactly one triangle side
  Inconsistent = 2,  // edge used by two sides running the same way (cut)
  NonManifold = 3,   // edge used by three or more sides (paired or cut)
};

// The counts (nTriangles, nEdges, ..., nShells, nDegenerate, nUsedVertices) and the figures
// derived from them (eulerCharacteristic(), watertight(), manifold()) are TopologyCounts'
// (stltopo/counts.h); undirected-edge counts: an undirected edge may hold several pairs when cut.
struct Topology : TopologyCounts {
  uint32_t nVertices = 0;

  // Half-edges: length nHalfedges() = 2 * number of pairs.
  Array<uint32_t> next;     // next half-edge around the same face (triangle or boundary loop)
  Array<uint32_t> prev;     // inverse of next (O(1) lPrev on long boundary loops)
  Array<uint32_t> vert;     // origin vertex
  Array<uint32_t> face;     // triangle id, or nTriangles + loop id
  Array<uint8_t> pairKind;  // per pair k: EdgeKind of the side(s) in the pair

  // Lookups.
  Array<uint32_t> triangleHalfedge;  // per triangle: half-edge of side corner0->corner1, kInvalid if degenerate
  Array<uint32_t> vertexHalfedge;    // per vertex: an outgoing half-edge (kInvalid if unused); on a
                                     // boundary it is the lowest-id boundary half-edge leaving it
  Array<uint32_t> vertexWeld;        // per vertex: representative vertex used by the topology
                                     // (identity for exact weld)

  // Boundary loops ("hole faces"): loop h is face nTriangles + h.
  Array<uint32_t> loopHalfedge;   // per loop: its lowest-id half-edge
  Array<uint32_t> loopOffsets;    // nLoops + 1: loop h's half-edges are loopHalfedges[off[h]..off[h+1])
  Array<uint32_t> loopHalfedges;  // in next order, starting at loopHalfedge[h]
  Array<uint8_t> loopIsSeam;      // 1 when the loop contains a cut (inconsistent/non-manifold) side
  Array<double> loopPerimeter;    // per loop: sum of edge lengths

  // Per-element problem flags.
  Array<uint8_t> triangleDegenerate;  // per triangle: 1 if two corners weld together
  Array<uint8_t> vertexNonManifold;   // per vertex: 1 if its outgoing half-edges form > 1 vnext cycle

  // Shells (edge-connected components of the non-degenerate triangles), numbered in the
  // order of their lowest triangle id. Built when TopologyOptions::triangleShell, else empty.
  Array<uint32_t> triangleShell;  // per triangle: its shell, kInvalid if degenerate

  // The weld the topology was built with: TopologyOptions::tolerance, and the number of
  // representatives (vertices v with vertexWeld[v] == v; = nVertices for the exact weld).
  double tolerance = 0;
  uint32_t nWeldedVertices = 0;

  uint32_t nHalfedges() const { return uint32_t(next.size()); }
  uint32_t nLoops() const { return uint32_t(loopHalfedge.size()); }
  uint32_t nFaces() const { return nTriangles + nLoops(); }
  bool isLoopFace(uint32_t f) const { return f >= nTriangles; }
};

// Builds the half-edge topology of `mesh` (passes and invariants: src/topology.cpp).
// Returns Ok, too-large (3 * triangles does not fit the 30-bit side ids), out-of-memory,
// or invalid (an internal walk did not close: a defect of the library, never of the
// input). `out` is reset first; on failure it holds a partly built topology that must not
// be navigated or reported (only destroyed or built again). `mesh` is only read and may
// be reused by another buildTopology at the same time.
Status buildTopology(const Mesh& mesh, Topology& out, const TopologyOptions& options = {});

// Checks the invariants of `topo` against `mesh`: array lengths, next a permutation with
// prev its inverse, faces and triangles, vertex and loop lookups, pairKind against the
// sides of each pair, loopIsSeam, vertexNonManifold, every count (edges by kind, holes,
// seams, used vertices, degenerate triangles, shells), triangleShell when it was built.
// Returns Ok, the first violation as invalid (message names the check; Status::element
// the half-edge, vertex, face, loop or count), or out-of-memory for its work arrays.
// Needs prev and face (an empty topology of prevAndFace = false is reported as invalid).
// Reads only; O(n).
Status validate(const Mesh& mesh, const Topology& topo);

// Navigation. face[e] is the left face of e.
inline uint32_t twin(uint32_t e) { return e ^ 1u; }
inline uint32_t sym(uint32_t e) { return e ^ 1u; }
inline uint32_t org(const Topology& t, uint32_t e) { return t.vert[e]; }
inline uint32_t dst(const Topology& t, uint32_t e) { return t.vert[e ^ 1u]; }
inline uint32_t lFace(const Topology& t, uint32_t e) { return t.face[e]; }
inline uint32_t rFace(const Topology& t, uint32_t e) { return t.face[e ^ 1u]; }
inline uint32_t lNext(const Topology& t, uint32_t e) { return t.next[e]; }
inline uint32_t lPrev(const Topology& t, uint32_t e) { return t.prev[e]; }
inline uint32_t vnext(const Topology& t, uint32_t e) { return t.next[e ^ 1u]; }
inline uint32_t oPrev(const Topology& t, uint32_t e) { return t.next[e ^ 1u]; }    // = vnext
inline uint32_t oNext(const Topology& t, uint32_t e) { return t.prev[e] ^ 1u; }    // sym(lPrev e)
inline uint32_t rPrev(const Topology& t, uint32_t e) { return oNext(t, e ^ 1u); }  // oNext(sym e)
inline uint32_t rNext(const Topology& t, uint32_t e) { return oPrev(t, e) ^ 1u; }  // sym(oPrev e)
inline uint32_t dNext(const Topology& t, uint32_t e) { return rPrev(t, e) ^ 1u; }  // sym(rPrev e)
inline uint32_t dPrev(const Topology& t, uint32_t e) { return t.next[e] ^ 1u; }    // sym(lNext e)

// Visit the half-edges of face f (triangle or loop) in next order.
template <class F>
void forEachFaceHalfedge(const Topology& t, uint32_t e0, F&& f) {
  uint32_t e = e0;
  do {
    f(e);
    e = t.next[e];
  } while (e != e0);
}
// Visit the outgoing half-edges of the vnext cycle that contains e0.
template <class F>
void forEachOutgoing(const Topology& t, uint32_t e0, F&& f) {
  uint32_t e = e0;
  do {
    f(e);
    e = vnext(t, e);
  } while (e != e0);
}

}  // namespace stltopo
