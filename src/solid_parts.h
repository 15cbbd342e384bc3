// Solids as stretches of triangles, for the writer and the indexed-mesh builder. Not installed.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stltopo/array.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"

namespace stltopo::detail {

// One solid of the output: `count` triangles from `first`.
struct SolidPart {
  uint32_t first, count;
  uint32_t solid;  // index in the solid list, kInvalid for triangles no solid covers
};

// The solids in order, with a part for each stretch of triangles that none covers (a list
// without solids gives one part, of all nTriangles, even 0). invalid-argument when a solid
// starts before the end of the one before it or runs past nTriangles (nothing appended);
// out-of-memory when `out` cannot grow.
Status solidParts(const Solid* solids, size_t nSolids, uint64_t nTriangles, Array<SolidPart>& out);

}  // namespace stltopo::detail
