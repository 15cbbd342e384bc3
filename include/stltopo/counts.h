// The topology's counts, listed once: the Topology members, the EditStats and Shell members,
// the keys of the JSON reports (infoJson, a shell's object, the repair's figures), the counts
// the wasm session hands to JS and takes back for validate(), and the TopologyCounts keys of
// web/src/index.d.ts are all written from the lists below. A new count is one line here
// (CONTRIBUTING.md, "A new count").
#pragma once

#include <cstdint>

// One line per count: X(count, name, doc), in the order the JSON reports write them.
//   count  the Topology member (Topology::nEdges), and its key in the `counts` the wasm
//          session's meta() gives JS and setCounts() takes back (STLTOPO_TOPOLOGY_COUNTS, bindings/);
//   name   the EditStats member, the key in infoJson and in the repair's figures, and the key
//          of TopologyCounts in web/src/index.d.ts (scripts/gen-api-docs.mjs writes it);
//   doc    one line for index.d.ts.
// The surface counts are also Shell members and keys of a shell's JSON object (each counted
// in that shell).
#define STLTOPO_SURFACE_COUNTS(X)                                                                            \
  X(nEdges, edges, "Undirected edges (an edge may hold several half-edge pairs when it is cut).")            \
  X(nBoundaryEdges, boundaryEdges, "Edges with one triangle side.")                                          \
  X(nNonManifoldEdges, nonManifoldEdges, "Edges with three or more triangle sides.")                         \
  X(nInconsistentEdges, inconsistentEdges, "Edges whose two sides run the same way (a flipped face).")       \
  X(nNonManifoldVertices, nonManifoldVertices, "Vertices whose outgoing half-edges form more than one fan.") \
  X(nHoles, holes, "Boundary loops without a cut side.")                                                     \
  X(nSeams, seams, "Boundary loops that contain a cut (inconsistent or non-manifold) side.")
#define STLTOPO_COUNTS(X)   \
  STLTOPO_SURFACE_COUNTS(X) \
  X(nShells, shells, "Shells: edge-connected components of the non-degenerate triangles.")
// The counts the reports write under another key ("degenerateTriangles") or not at all.
#define STLTOPO_OTHER_COUNTS(X)                                               \
  X(nDegenerate, degenerate, "Triangles two of whose corners weld together.") \
  X(nUsedVertices, usedVertices, "Vertices that a non-degenerate triangle uses.")

namespace stltopo {

// The counts of a topology and the figures derived from them: the base of Topology, and what
// EditableMesh::stats() derives its figures with.
struct TopologyCounts {
  uint32_t nTriangles = 0;  // = mesh.nTriangles(); boundary face h has id nTriangles + h
#define STLTOPO_COUNT_MEMBER(count, name, doc) uint32_t count = 0;
  STLTOPO_COUNTS(STLTOPO_COUNT_MEMBER)
  STLTOPO_OTHER_COUNTS(STLTOPO_COUNT_MEMBER)
#undef STLTOPO_COUNT_MEMBER

  // V - E + F over the non-degenerate triangles and the vertices they use.
  int64_t eulerCharacteristic() const {
    return int64_t(nUsedVertices) - int64_t(nEdges) + int64_t(nTriangles - nDegenerate);
  }
  // At least one non-degenerate triangle and no boundary, non-manifold or inconsistent edge.
  bool watertight() const {
    return nTriangles > nDegenerate && nBoundaryEdges == 0 && nNonManifoldEdges == 0 && nInconsistentEdges == 0;
  }
  bool manifold() const { return nNonManifoldEdges == 0 && nNonManifoldVertices == 0; }
};

}  // namespace stltopo
