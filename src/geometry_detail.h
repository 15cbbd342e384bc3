// Private helpers of the geometric checks (geometry.cpp, triangle_checks.cpp).
#pragma once

#include "stltopo/geometry.h"
#include "try_alloc.h"

namespace stltopo::geometry_detail {

using detail::oom;  // "out-of-memory: could not allocate <what>"

// The welded corners of a mesh: the topology's representatives, or the mesh's own ids.
struct Welded {
  const Mesh& mesh;
  const uint32_t* weld;  // null: identity
  uint32_t v(uint32_t t, int c) const {
    uint32_t id = mesh.triangles[3 * size_t(t) + size_t(c)];
    return weld ? weld[id] : id;
  }
  const float* p(uint32_t vertex) const { return mesh.positions.data() + 3 * size_t(vertex); }
};

// The weld array a Welded needs: none for the exact weld (vertexWeld is the identity there,
// and skipping it saves a random read per corner).
inline const uint32_t* weldOf(const Topology* topo) {
  return topo && topo->tolerance > 0 ? topo->vertexWeld.data() : nullptr;
}

// The pass's work limit (IntersectionOptions::maxPairs): 8 * maxPairs + 64 * nTriangles pair
// tests, saturated (a huge maxPairs must not wrap to a small limit).
inline uint64_t workLimit(uint64_t maxPairs, uint32_t nTriangles) {
  const uint64_t minWork = 64 * uint64_t(nTriangles);
  return maxPairs > (~uint64_t(0) - minWork) / 8 ? ~uint64_t(0) : 8 * maxPairs + minWork;
}

// analyzeGeometry after its pass: the shells, their nesting and `solid`, from out.checks and
// out.intersections (of this mesh and topology, which has triangleShell).
Status finishGeometry(const Mesh& mesh, const Topology& topo, GeometryReport& out);

// analyzeGeometry without the shell list (shellList false): out.solid only, with out.shells
// and out.nesting left empty. No shell pass when the mesh cannot be solid, else
// watertightShells instead of findShellsAndDefects; `solid` is the same as finishGeometry's.
Status finishSolid(const Mesh& mesh, const Topology& topo, GeometryReport& out);

// The shells of a watertight, manifold mesh as far as findShellNesting and isSolid read
// them (shells.cpp): triangles, firstTriangle and volume (the same to the bit as
// findShellsAndDefects's), and no boundary, cut or non-manifold edge (there is none in such
// a mesh); the other figures are left 0. InvalidArgument for another mesh.
Status watertightShells(const Mesh& mesh, const Topology& topo, Array<Shell>& out);

// Counts pair (a, b) of `kind`, already appended to out.pairs/kinds, in out's per-kind
// counts and per-triangle flags (out.triangleIntersects covers both).
inline void countPair(Intersections& out, uint32_t a, uint32_t b, uint8_t kind) {
  switch (IntersectionKind(kind)) {
    case IntersectionKind::Crossing: ++out.nCrossing; break;
    case IntersectionKind::Touching: ++out.nTouching; break;
    case IntersectionKind::Coplanar: ++out.nCoplanar; break;
  }
  out.nIntersectingTriangles += !out.triangleIntersects[a];
  out.triangleIntersects[a] = 1;
  out.nIntersectingTriangles += !out.triangleIntersects[b];
  out.triangleIntersects[b] = 1;
}

// A triangle for the exact pair test: its three vertex ids (corners that are one vertex
// have one id) and positions. Its corners must be distinct and not collinear.
struct Tri {
  uint32_t v[3];
  const float* p[3];
};

// The exact test of one pair (geometry.cpp, the one the intersection pass runs): -1 when
// the closed triangles do not meet, or meet only in the corners and the side they share
// (by id), or share all three corners; else the IntersectionKind. `point` gets a point of
// the intersection (floating point, decides nothing).
int trianglePairTest(const Tri& a, const Tri& b, double point[3]);

// Test hooks of the intersection pass's fan certificates (geometry.cpp): the certified
// vertices of a mesh (1 each; the pass's own rule, on the triangles of the pass); and the
// vertices certified and the candidate pairs skipped for sharing one, summed over every pass
// since the start.
Status fanCertificatesForTesting(const Mesh& mesh, const Topology& topo, const TriangleChecks& checks,
                                 Array<uint8_t>& certified);
uint64_t fanCertifiedVerticesForTesting();
uint64_t fanSkippedPairsForTesting();
// The patch certificates (geometry.cpp): the positions found in certified nodes so far, and
// a switch that turns them off (the pass is then what it was before them).
uint64_t patchCertifiedPositionsForTesting();
void setPatchCertificatesForTesting(bool on);
// The smallest node the patch certificates try (0: the default, 64 positions); tests set 2
// so that small meshes exercise them.
void setPatchMinimumForTesting(uint32_t positions);
// The largest node tried top down within the budget (0: the default, 8192 positions), and the
// tasks' size as a multiple of it (0: the default, 4; 1: no node above it is tried from its
// triangles); above it, nodes are tried as unions of certified children, and inside a task
// also from their triangles when these all turn one way. Tests set a few positions so that
// small meshes exercise both; the unions and the large nodes certified from their triangles
// so far; and a switch that turns the unions off.
void setPatchTaskSizeForTesting(uint32_t positions, uint32_t scale = 0);
uint64_t patchUnionsForTesting();
uint64_t patchLargeNodesForTesting();
void setPatchUnionsForTesting(bool on);
// The hierarchy's Morton code of each triangle of a mesh (the cell of its centroid in a
// 1024^3 grid over the mesh's box), as the pass computes it (`fast`: SIMD where the build
// has it) and by the scalar formula (`scalar`). Tests compare the two.
Status mortonCodesForTesting(const Mesh& mesh, Array<uint32_t>& fast, Array<uint32_t>& scalar);

inline Status checkWeld(const Mesh& mesh, const Topology* topo) {
  if (topo && (topo->nTriangles != mesh.nTriangles() || topo->nVertices != mesh.nVertices() ||
               topo->vertexWeld.size() != mesh.nVertices()))
    return Status::error(Code::InvalidArgument, "the topology was not built from this mesh");
  return {};
}

}  // namespace stltopo::geometry_detail
