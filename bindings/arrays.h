// The tables of what a load's session hands to JS: the result arrays (STLTOPO_JS_ARRAYS; the
// EditableMesh's are in edit_arrays.h). The session serves them by name (array(), upload()),
// each module hands its table to JS (_arrayLayout), and the JS layer (web/src/mesh.js),
// index.d.ts and docs/JS-API.md follow it. The counts that are not array lengths are in
// STLTOPO_TOPOLOGY_COUNTS.
#pragma once

#include <cstddef>

#include "js_values.h"
#include "stltopo/stltopo.h"

namespace stltopo {
// What fromIndexed() returns besides the mesh (the third part of the array table).
struct Indexed {
  Array<uint32_t> inputVertexMap;
};
}  // namespace stltopo

// The result arrays that cross to JS, one line each:
//   STLTOPO_JS_ARRAYS(X, G): X(name, part, group, key, element, width, when, flags, doc)
// for every row, G(...) for the rows of STLTOPO_JS_GEOMETRY_ARRAYS, which only the full module
// fills (it passes X for G; the core, whose table leaves them out, STLTOPO_JS_SKIP).
//   name     the member of stltopo::Mesh or stltopo::Topology (`part`), and the name
//            session.array()/upload() take;
//   group    the mesh property that holds it in JS ("" = the mesh itself), key its name there;
//   element  what its entries are indexed by, width entries per element;
//   when     when it exists: "mesh" always, "normals" with { normals: true }, "colors" when the
//            file has colours, "topology" unless { topology: false }, "indexed" for meshes of
//            fromIndexed(); otherwise JS sets null;
//   flags    kCopied: copied out even for { view: true } meshes (small, so holes never dangle);
//            kDerived: not copied out of wasm for copies, rebuilt in JS on first read
//            (web/src/mesh.js deriveArray) and not built by the core for them (prevAndFace);
//   doc      one line for index.d.ts and docs/JS-API.md (scripts/gen-api-docs.mjs writes them).
// A new array is one line here, then `node scripts/gen-api-docs.mjs`.
// The exact geometry's arrays (mesh.intersections), in the full module only: the core module
// never computes them, and its table (a smaller download) leaves them out.
#define STLTOPO_JS_GEOMETRY_ARRAYS(X)                                                                                  \
  X(zeroArea, TriangleChecks, "intersections", "zeroAreaTriangles", "zero-area triangle", 1, "intersections", kCopied, \
    "The zero-area triangles (three distinct, exactly collinear corners), ascending.")                                 \
  X(duplicateOffsets, TriangleChecks, "intersections", "duplicateOffsets", "duplicate group+1", 1, "intersections",    \
    kCopied, "Duplicate group g is duplicateTriangles[offsets[g] .. offsets[g+1]).")                                   \
  X(duplicateTriangles, TriangleChecks, "intersections", "duplicateTriangles", "group entry", 1, "intersections",      \
    kCopied, "The members of every duplicate group, ascending; groups by lowest member.")                              \
  X(duplicateOrientation, TriangleChecks, "intersections", "duplicateOrientation", "duplicate group", 1,               \
    "intersections", kCopied, "Per group: 0 same, 1 opposite, 2 mixed (DuplicateOrientation).")                        \
  X(pairs, Intersections, "intersections", "pairs", "pair", 2, "intersections", kCopied,                               \
    "Intersecting pair i is triangles [2i] < [2i+1]; ordered by (i, j).")                                              \
  X(kinds, Intersections, "intersections", "kinds", "pair", 1, "intersections", kCopied,                               \
    "Per pair: 0 crossing, 1 touching, 2 coplanar (IntersectionKind).")                                                \
  X(points, Intersections, "intersections", "points", "pair", 3, "intersections", kCopied,                             \
    "Per pair: x,y,z of one point of the intersection (float64, for framing a camera).")                               \
  X(triangleIntersects, Intersections, "intersections", "triangleIntersects", "triangle", 1, "intersections", kCopied, \
    "Per triangle: 1 when it is in an intersecting pair.")
#define STLTOPO_JS_ARRAYS(X, G)                                                                                        \
  X(positions, Mesh, "", "positions", "vertex", 3, "mesh", 0, "x,y,z of vertex v at 3v..3v+2.")                        \
  X(triangles, Mesh, "", "triangles", "triangle", 3, "mesh", 0, "Vertex ids of corner c of triangle t at 3t+c.")       \
  X(attributes, Mesh, "", "attributes", "triangle", 1, "mesh", 0, "Binary attribute word per triangle (0 for ASCII).") \
  X(colors, Mesh, "", "colors", "triangle", 3, "colors", 0,                                                            \
    "sRGB bytes per triangle when colorConvention !== 'none'.")                                                        \
  X(colorValid, Mesh, "", "colorValid", "triangle", 1, "colors", 0, "1 per triangle that has a colour.")               \
  X(normals, Mesh, "", "normals", "triangle", 3, "normals", 0, "Stored facet normals, with { normals: true }.")        \
  X(next, Topology, "halfedges", "next", "halfedge", 1, "topology", 0, "Next half-edge around the same face.")         \
  X(prev, Topology, "halfedges", "prev", "halfedge", 1, "topology", kDerived, "Inverse of next.")                      \
  X(vert, Topology, "halfedges", "vert", "halfedge", 1, "topology", kDerived, "Origin vertex (org).")                  \
  X(face, Topology, "halfedges", "face", "halfedge", 1, "topology", kDerived,                                          \
    "Left face: the triangle id, or nTriangles + h for boundary loop h.")                                              \
  X(triangleHalfedge, Topology, "", "triangleHalfedge", "triangle", 1, "topology", 0,                                  \
    "Per triangle: half-edge of side corner0->corner1, kInvalid if degenerate.")                                       \
  X(vertexHalfedge, Topology, "", "vertexHalfedge", "vertex", 1, "topology", 0,                                        \
    "Per vertex: an outgoing half-edge, kInvalid if unused.")                                                          \
  X(loopHalfedge, Topology, "", "loopHalfedge", "loop", 1, "topology", 0,                                              \
    "Per boundary loop: its lowest-id half-edge.")                                                                     \
  X(vertexWeld, Topology, "", "vertexWeld", "vertex", 1, "topology", 0,                                                \
    "Per vertex: the representative vertex the topology uses (identity for exact weld).")                              \
  X(loopOffsets, Topology, "loops", "offsets", "loop+1", 1, "topology", kCopied,                                       \
    "Loop h is halfedges[offsets[h] .. offsets[h+1]).")                                                                \
  X(loopHalfedges, Topology, "loops", "halfedges", "loop entry", 1, "topology", kCopied,                               \
    "The half-edges of every loop in next order, starting at loopHalfedge[h].")                                        \
  X(loopIsSeam, Topology, "loops", "isSeam", "loop", 1, "topology", kCopied,                                           \
    "1 when the loop contains a cut (inconsistent or non-manifold) side.")                                             \
  X(loopPerimeter, Topology, "loops", "perimeter", "loop", 1, "topology", kCopied, "Sum of the loop's edge lengths.")  \
  X(pairKind, Topology, "problems", "pairKind", "pair", 1, "topology", 0,                                              \
    "Per pair k = e >> 1: 0 interior, 1 boundary, 2 inconsistent, 3 non-manifold (EdgeKind).")                         \
  X(triangleDegenerate, Topology, "problems", "triangleDegenerate", "triangle", 1, "topology", 0,                      \
    "1 when two corners of the triangle weld together.")                                                               \
  X(vertexNonManifold, Topology, "problems", "vertexNonManifold", "vertex", 1, "topology", 0,                          \
    "1 when the vertex's outgoing half-edges form more than one vnext cycle.")                                         \
  X(triangleShell, Topology, "", "triangleShell", "triangle", 1, "shells", 0,                                          \
    "Per triangle: its shell (numbered by lowest triangle id), kInvalid if degenerate.")                               \
  X(nonManifoldEdgeVertices, Defects, "defects", "nonManifoldEdgeVertices", "non-manifold edge", 2, "shells", kCopied, \
    "Non-manifold edge i joins vertices [2i] < [2i+1]; ordered by (smaller, larger) vertex.")                          \
  X(nonManifoldEdgeOffsets, Defects, "defects", "nonManifoldEdgeOffsets", "non-manifold edge+1", 1, "shells", kCopied, \
    "Non-manifold edge i's triangles are nonManifoldEdgeTriangles[offsets[i] .. offsets[i+1]).")                       \
  X(nonManifoldEdgeTriangles, Defects, "defects", "nonManifoldEdgeTriangles", "edge entry", 1, "shells", kCopied,      \
    "Every triangle with a side on each non-manifold edge, ascending.")                                                \
  X(inconsistentEdgeVertices, Defects, "defects", "inconsistentEdgeVertices", "inconsistent edge", 2, "shells",        \
    kCopied, "Inconsistent edge i joins vertices [2i] < [2i+1]; ordered by (smaller, larger) vertex.")                 \
  X(inconsistentEdgeTriangles, Defects, "defects", "inconsistentEdgeTriangles", "inconsistent edge", 2, "shells",      \
    kCopied, "The two triangles of inconsistent edge i, [2i] < [2i+1].")                                               \
  X(nonManifoldVertices, Defects, "defects", "nonManifoldVertices", "non-manifold vertex", 1, "shells", kCopied,       \
    "The non-manifold vertices, ascending.")                                                                           \
  X(nonManifoldVertexCycles, Defects, "defects", "nonManifoldVertexCycles", "non-manifold vertex", 1, "shells",        \
    kCopied, "The number of vnext cycles of each (>= 2).")                                                             \
  X(degenerateTriangles, Defects, "defects", "degenerateTriangles", "degenerate triangle", 1, "shells", kCopied,       \
    "The degenerate triangles, ascending.")                                                                            \
  X(degenerateCorners, Defects, "defects", "degenerateCorners", "degenerate triangle", 1, "shells", kCopied,           \
    "Corners that weld: bit 0 corners 0,1; bit 1 corners 1,2; bit 2 corners 2,0 (7: all three).")                      \
  X(loopShell, Defects, "defects", "loopShell", "loop", 1, "shells", kCopied, "Per boundary loop h: its shell.")       \
  STLTOPO_JS_GEOMETRY_ARRAYS(G)                                                                                        \
  X(inputVertexMap, Indexed, "", "inputVertexMap", "input vertex", 1, "indexed", kCopied,                              \
    "fromIndexed(): per vertex of the input, its vertex in the mesh (kInvalid when no triangle uses it).")

#define STLTOPO_JS_SKIP(...)

// The topology's counts that are not array lengths: meta() hands them to JS as `counts`, and
// setCounts() takes them back for validate() on uploaded arrays. The counts of
// stltopo/counts.h, and the weld's.
#define STLTOPO_TOPOLOGY_COUNTS(X) STLTOPO_COUNTS(X) STLTOPO_OTHER_COUNTS(X) X(nWeldedVertices, weldedVertices, "")

namespace stltopo::js {

constexpr int kCopied = 1;
constexpr int kDerived = 2;

// One row of the table.
struct JsArray {
  const char *name, *group, *key, *element;
  int width;
  const char* when;
  int flags;
  const char *type, *doc;
};
#define STLTOPO_JS_ROW(name, part, group, key, element, width, when, flags, doc) \
  {#name, group, key, element, width, when, flags, js::JsType<decltype(stltopo::part::name)>::js, doc},
// The core module (the smaller download) leaves out the doc lines: only
// scripts/gen-api-docs.mjs reads them, from the full module.
#define STLTOPO_JS_ROW_NO_DOC(name, part, group, key, element, width, when, flags, doc) \
  STLTOPO_JS_ROW(name, part, group, key, element, width, when, flags, "")

// The module's table (bindings/core.cpp or bindings/full.cpp, the one the module links).
extern const JsArray kJsArrays[];
extern const size_t kJsArrayCount;

}  // namespace stltopo::js
