// The EditableMesh's arrays that cross to JS: the sibling of STLTOPO_JS_ARRAYS
// (arrays.h), one line each. bindings/edit.cpp serves them by name (array()), hands the
// table to JS (_editArrayLayout), and web/src/edit.js makes one getter per row; index.d.ts
// and docs/JS-API.md follow it (node scripts/gen-api-docs.mjs).
//   X(name, source, group, key, element, width, doc)
//   source   the array, as a member access on the EditSession (edit.cpp): em() is the
//            EditableMesh;
//   group    the EditableMesh property that holds it in JS ("" = the mesh itself), key its
//            name there;
//   element  what its entries are indexed by (slots: dead ones included), width per element.
// A new array is one line here, then `node scripts/gen-api-docs.mjs`.
#pragma once

#define STLTOPO_JS_EDIT_ARRAYS(X)                                                                                  \
  X(positions, em().positions(), "", "positions", "vertex", 3,                                                     \
    "x,y,z of vertex v at 3v..3v+2 (a dead vertex keeps its last position).")                                      \
  X(triangles, em().triangles(), "", "triangles", "triangle", 3,                                                   \
    "Vertex ids of corner c of triangle t at 3t+c; kInvalid for a dead triangle.")                                 \
  X(next, em().next(), "halfedges", "next", "halfedge", 1, "Next half-edge around the same face.")                 \
  X(prev, em().prev(), "halfedges", "prev", "halfedge", 1, "Inverse of next.")                                     \
  X(vert, em().vert(), "halfedges", "vert", "halfedge", 1, "Origin vertex (org).")                                 \
  X(face, faceIds(), "halfedges", "face", "halfedge", 1,                                                           \
    "Left face: the triangle id, or nTriangles + h for boundary loop h (as a Mesh).")                              \
  X(triangleHalfedge, em().triangleHalfedge(), "", "triangleHalfedge", "triangle", 1,                              \
    "Per triangle: half-edge of side corner0->corner1, kInvalid if degenerate or dead.")                           \
  X(vertexHalfedge, em().vertexHalfedge(), "", "vertexHalfedge", "vertex", 1,                                      \
    "Per vertex: an outgoing half-edge, kInvalid if unused.")                                                      \
  X(loopHalfedge, em().loops().loopHalfedge, "", "loopHalfedge", "loop", 1,                                        \
    "Per boundary loop: the twin of its earliest triangle side.")                                                  \
  X(loopOffsets, em().loops().loopOffsets, "loops", "offsets", "loop+1", 1,                                        \
    "Loop h is halfedges[offsets[h] .. offsets[h+1]).")                                                            \
  X(loopHalfedges, em().loops().loopHalfedges, "loops", "halfedges", "loop entry", 1,                              \
    "The half-edges of every loop in next order, starting at loopHalfedge[h].")                                    \
  X(loopIsSeam, em().loops().loopIsSeam, "loops", "isSeam", "loop", 1,                                             \
    "1 when the loop contains a cut (inconsistent or non-manifold) side.")                                         \
  X(loopPerimeter, em().loops().loopPerimeter, "loops", "perimeter", "loop", 1, "Sum of the loop's edge lengths.") \
  X(pairKind, em().pairKind(), "problems", "pairKind", "pair", 1,                                                  \
    "Per pair k = e >> 1: 0 interior, 1 boundary, 2 inconsistent, 3 non-manifold (EdgeKind).")                     \
  X(triangleDegenerate, em().triangleDegenerateFlags(), "problems", "triangleDegenerate", "triangle", 1,           \
    "1 when two corners of the triangle weld together.")                                                           \
  X(vertexNonManifold, em().vertexNonManifoldFlags(), "problems", "vertexNonManifold", "vertex", 1,                \
    "1 when the vertex's outgoing half-edges form more than one vnext cycle.")

// The arrays of the mesh to edit that JS uploads before init(): members of stltopo::Mesh
// (rows of STLTOPO_JS_ARRAYS).
#define STLTOPO_JS_EDIT_UPLOADS(X) X(positions) X(triangles) X(attributes) X(colors) X(colorValid) X(normals)
