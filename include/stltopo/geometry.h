// stltopo/geometry.h: the exact geometric checks: zero-area and duplicate triangles,
// self-intersections, and how closed shells nest.
//
// Everything here is on the welded mesh: a triangle's corners are its vertices'
// representatives (Topology::vertexWeld; the identity for the exact weld), and a corner's
// position is its representative's float32 position, taken exactly. Every predicate is
// exact (a floating-point filter with an exact fallback, no epsilon). Nothing here
// changes the mesh. The definitions are part of the report's contract (README,
// "Geometry").
#pragma once

#include <cstdint>

#include "stltopo/array.h"
#include "stltopo/mesh.h"
#include "stltopo/shells.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"

namespace stltopo {

// How the members of a duplicate group run.
enum class DuplicateOrientation : uint8_t {
  Same = 0,      // "same": all members run the same way
  Opposite = 1,  // "opposite": two members that run opposite ways
  Mixed = 2,     // "mixed": three or more members that do not all run the same way
};
const char* duplicateOrientationName(DuplicateOrientation o);

// Zero-area triangles and duplicate groups: the cheap checks every report has.
//  - Zero-area: three distinct welded corners whose positions are exactly collinear
//    (disjoint from the degenerate triangles, which repeat a welded corner).
//  - Duplicates: non-degenerate triangles (zero-area ones too) with the same set of three
//    welded corners, in either orientation. Groups are ordered by their lowest triangle.
struct TriangleChecks {
  Array<uint32_t> zeroArea;             // ascending triangle ids
  Array<uint32_t> duplicateOffsets;     // groups + 1: group g is duplicateTriangles[off[g]..off[g + 1])
  Array<uint32_t> duplicateTriangles;   // each group's members, ascending
  Array<uint8_t> duplicateOrientation;  // per group: DuplicateOrientation
  uint32_t nDuplicateTriangles = 0;     // members that are not the lowest of their group

  uint32_t nDuplicateGroups() const { return duplicateOffsets.empty() ? 0 : uint32_t(duplicateOffsets.size() - 1); }
};

// Finds the zero-area triangles and the duplicate groups of `mesh`, welded by `topo`
// (null: the mesh's own vertex ids, which are the exact weld). Returns Ok, OutOfMemory or
// InvalidArgument (a topology of another mesh); `out` is reset first. O(n) expected time
// (a hash of the corner sets) and 12 bytes per triangle of work memory.
Status checkTriangles(const Mesh& mesh, const Topology* topo, TriangleChecks& out);
// The same on `threads` threads (ReadOptions::threads: 0 = the machine's hardware threads):
// the same result for every value.
Status checkTriangles(const Mesh& mesh, const Topology* topo, TriangleChecks& out, unsigned threads);

// The kind of an intersecting pair.
enum class IntersectionKind : uint8_t {
  Crossing = 0,  // "crossing": the triangles pass through each other
  Touching = 1,  // "touching": one has no corner strictly on each side of the other's plane
                 //             (and they share no area when coplanar)
  Coplanar = 2,  // "coplanar": both lie in one plane and share an area
};
const char* intersectionKindName(IntersectionKind k);

struct IntersectionOptions {
  // Work limit: the pass stops once it has found this many intersecting pairs, or has
  // tested 8 * maxPairs + 64 * triangles pairs of overlapping bounding boxes (the pairs
  // inside a certified patch, see findIntersections, are not tested and not counted). Past the
  // limit, Intersections::complete is false and the counts are lower bounds.
  uint64_t maxPairs = 4000000;
  // Called now and then with the fraction done (0..1); return false to stop: the result
  // is then Code::Aborted. Null: never called.
  bool (*progress)(void* user, double fraction) = nullptr;
  void* user = nullptr;
  // Threads (ReadOptions::threads): 1 = one thread (the default), 0 = the machine's
  // hardware threads. The result is the same for every value.
  unsigned threads = 1;
};

// Self-intersections: pairs (i < j) of triangles, neither degenerate nor zero-area nor in
// one duplicate group, that share a point outside the convex hull of the welded corners
// they share (CGAL's "share more than their common sub-face"): with no shared corner, any
// common point; with one shared corner a, the side of either opposite a meets the other
// triangle; with a shared side ab, (a, b, c) and (a, b, d) coplanar with c and d strictly
// on the same side of ab.
struct Intersections {
  Array<uint32_t> pairs;              // 2 per pair: i < j, pairs ordered by (i, j)
  Array<uint8_t> kinds;               // per pair: IntersectionKind
  Array<double> points;               // 3 per pair: one point of their intersection (float64,
                                      // computed in floating point: for framing a camera)
  Array<uint8_t> triangleIntersects;  // per triangle: 1 when it is in a pair
  uint64_t nCrossing = 0, nTouching = 0, nCoplanar = 0;
  uint32_t nIntersectingTriangles = 0;
  bool complete = true;  // false: the work limit stopped the pass
  uint64_t work = 0;     // the pair tests counted toward the work limit (the same on any number of threads)

  uint64_t nPairs() const { return pairs.size() / 2; }
};

// Finds every intersecting pair of `mesh` welded by `topo` (any topology built from this
// mesh), skipping what `checks` (checkTriangles of the same mesh and topology) lists.
// Returns Ok, OutOfMemory, Aborted or InvalidArgument (arrays of another mesh); `out`
// is reset first. Cost: a bounding-volume hierarchy over the triangles (built in O(n) by
// a radix sort of Morton codes) and a self-join of it, so O(n log n) for meshes whose
// triangles' boxes overlap a bounded number of others; the work limit bounds the rest. The
// pairs that share corners (nearly all of a mesh's) take a few exact signs each, and none
// when they share a certified vertex: one whose triangles form a single closed fan (interior
// sides only, none zero-area) that, projected along a coordinate axis, turns one way and
// winds exactly once around it (exact signs; one O(n) pass over the triangles before the
// join), so that no two of them intersect. Such pairs still count toward the work limit. On
// a clean closed mesh every vertex is certified and the exact tests run only for the pairs
// that share no corner. Before them, whole nodes of the hierarchy (64 to 8192 triangles) are
// certified as patches: their triangles all face one strict way along a coordinate axis (or
// all but at most 1 in 8, which are then taken wound the other way: a triangle's points do
// not depend on its winding), and
// the sides that do not cancel inside the node, projected along it, form loops that do not
// cross and cover each point at most once (exact signs; the proof is in geometry.cpp). The
// join skips the pairs inside a patch without visiting them, so they do not count toward the
// work limit; when patches hold all but at most 1/16 of the triangles, the vertex
// certificates are not made (the pairs left are few). On a smooth mesh (the 1M torus) every triangle is in a
// patch and the join tests only the pairs between patches. Memory: about 52 bytes per
// triangle while it runs (ids 4, boxes 24, corners 12, nodes about 9, flags 1, certificates
// 1, sign masks 1, patch flags under 1), 2 bytes per vertex while certifying vertices, about
// 1 MB per thread for the patch test, plus 33 bytes per pair found. With options.threads
// other than 1, the certificates' flags per triangle are set by ranges and the join is split
// into tasks (pairs of subtrees, in the serial join's order) that the threads take in turn,
// and the pairs found are sorted as always: the result is the same. Should the work
// or pair limit be reached, the pass runs again on one thread, whose truncated list depends
// on the order of the tests (the threaded attempt stops once the limit is seen, so this at
// most doubles the bounded work). Progress is reported from the calling thread only.
Status findIntersections(const Mesh& mesh, const Topology& topo, const TriangleChecks& checks, Intersections& out,
                         const IntersectionOptions& options = {});

// How the closed shells nest, and what each shell intersects. For shell s:
//  - selfIntersects[s]: 1 when two of its triangles intersect;
//  - intersectsOffsets/intersectsShells: the other shells it intersects, ascending
//    (shell s's are intersectsShells[off[s]..off[s + 1]));
//  - parent[s], depth[s]: for a closed shell that intersects no other shell, the innermost
//    such shell whose solid strictly contains its vertices (kInvalid: none) and the number
//    of shells around it (0 at the top level); kInvalid for the other shells.
struct ShellNesting {
  Array<uint8_t> selfIntersects;
  Array<uint32_t> intersectsOffsets;
  Array<uint32_t> intersectsShells;
  Array<uint32_t> parent;
  Array<uint32_t> depth;

  // Whether this is the nesting of a list of `shells` shells: the reports write it beside a
  // shell list only then (an empty nesting, of a mesh not checked, is of the empty list only).
  bool isOf(size_t shells) const { return depth.size() == shells; }
};

// Needs Topology::triangleShell, `shells` from findShellsAndDefects and `found` from
// findIntersections, all of this mesh. A shell B contains a shell A when a vertex of A
// lies strictly inside B (one ray, exact parity with symbolic perturbation); as A meets
// no other shell, all of its vertices are then inside. Shells sharing a vertex are not
// nested. Returns Ok, OutOfMemory or InvalidArgument.
Status findShellNesting(const Mesh& mesh, const Topology& topo, const Array<Shell>& shells, const Intersections& found,
                        ShellNesting& out);

// Whether the mesh bounds a volume without ambiguity: watertight and manifold, no
// zero-area, duplicate or intersecting triangles (with a complete pass), and every shell
// outward at even depth and inward at odd depth.
bool isSolid(const Topology& topo, const TriangleChecks& checks, const Intersections& found, const Array<Shell>& shells,
             const ShellNesting& nesting);

// Everything above in one call, for a report: the checks, the intersections, the shells
// (findShellsAndDefects, without the defects) and their nesting, and `solid`. Needs
// Topology::triangleShell. Returns the first failure of the steps.
struct GeometryReport {
  TriangleChecks checks;
  Intersections intersections;
  Array<Shell> shells;
  ShellNesting nesting;
  bool solid = false;
};
Status analyzeGeometry(const Mesh& mesh, const Topology& topo, GeometryReport& out,
                       const IntersectionOptions& options = {});
// The same, with `shellList` false for a report that lists no shells: out.shells and
// out.nesting stay empty, and `solid` (the same as above) costs a pass over the shells'
// volumes only, or nothing when the mesh is not watertight and manifold or has zero-area,
// duplicate or intersecting triangles.
Status analyzeGeometry(const Mesh& mesh, const Topology& topo, GeometryReport& out, const IntersectionOptions& options,
                       bool shellList);
// analyzeGeometry(mesh, topo, out, options, shellList) after its first step: `out.checks` must
// hold checkTriangles(mesh, &topo, ...) of this mesh and topology, and is kept. Without the
// shell list the rest reads of the topology only its counts, vertexWeld, triangleDegenerate,
// triangleShell, vert, pairKind and vertexNonManifold, so a caller that needs nothing else
// afterwards may release next, prev, face, triangleHalfedge and vertexHalfedge (which the
// checks read) before this call, and the pass reuses their memory (`stltopo info
// --intersections` does: 18 MB at 1M triangles). With `shellList` the topology must be whole.
Status analyzeGeometryAfterChecks(const Mesh& mesh, const Topology& topo, GeometryReport& out,
                                  const IntersectionOptions& options, bool shellList);

}  // namespace stltopo
