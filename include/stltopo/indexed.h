// stltopo/indexed.h: a Mesh from any indexed triangle list (a three.js geometry, OBJ, PLY...).
#pragma once

#include <cstddef>
#include <cstdint>

#include "stltopo/array.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"

namespace stltopo {

enum class Weld : uint8_t {
  Exact,  // equal positions are one vertex, as reading welds them (-0 == +0); the ids
          // follow first appearance in corner order
  None,   // the caller's vertices as they are: duplicated positions stay separate vertices
};

// The caller's arrays, borrowed for the call. The lengths count values, not elements.
struct IndexedMesh {
  const float* positions = nullptr;  // x, y, z per vertex
  size_t positionsLength = 0;
  const uint32_t* triangles = nullptr;  // 3 vertex ids per triangle
  size_t trianglesLength = 0;
  const uint16_t* attributes = nullptr;  // per triangle, or null (zero words)
  const uint8_t* colors = nullptr;       // RGB per triangle, or null
  const uint8_t* colorValid = nullptr;   // per triangle 0/1, or null (all coloured); only with colors
  const Solid* solids = nullptr;         // named stretches of triangles, in order, not overlapping
  size_t nSolids = 0;
};

struct IndexedOptions {
  Weld weld = Weld::Exact;
};

// Builds `out` as reading an STL file of these triangles builds it: the same vertex ids
// (Weld::Exact), figures (area, volume, bounding box), solids (the given ones, and unnamed
// ones for the stretches no solid covers; one unnamed solid when none is given) and colour
// decoding of the attribute words (bit 15 = a VisCAM colour). Mesh::format is Unknown.
// With `colors`, the mesh has VisCAM colours: Mesh::colors holds the given bytes and the
// attribute words are their VisCAM words (5 bits per channel, what writing stores).
// buildTopology, validate, infoJson and writeStl then take `out` as they take a read mesh.
//
// vertexMap (may be null) receives, per caller vertex, its vertex in `out`: kInvalid for a
// vertex no triangle uses (Weld::Exact); the identity with Weld::None.
//
// Codes: invalid-argument (a length that is not a multiple of 3, a null array with a
// length, attributes and colors together, colorValid without colors, solids that overlap,
// are out of order or run past the last triangle); too-large (more than 2^32 - 2 vertices
// or triangles); non-finite (a NaN or infinite coordinate; Status::element = the vertex);
// invalid-index (a vertex id >= the number of vertices; Status::triangle = the triangle);
// out-of-memory. On failure `out` and `vertexMap` are untouched.
Status meshFromIndexed(const IndexedMesh& in, Mesh& out, Array<uint32_t>* vertexMap = nullptr,
                       const IndexedOptions& options = {});

}  // namespace stltopo
