// EditStats from counts: what EditableMesh::stats() gives, and what the repair runner
// takes from the topology of a mesh instead of asking an EditableMesh of it.
#pragma once

#include <cstdint>

#include "stltopo/counts.h"
#include "stltopo/edit.h"

namespace stltopo {
namespace edit_detail {

// The stats of a mesh whose counts are `c` (an EditableMesh's, as a fresh build of its
// compacted mesh has them, or that build's Topology) and of which `vertices` vertices are
// used by some triangle.
inline EditStats statsOf(const TopologyCounts& c, uint32_t vertices) {
  EditStats s;
  s.triangles = c.nTriangles;
  s.vertices = vertices;
#define STLTOPO_STATS_COUNT(count, name, doc) s.name = c.count;
  STLTOPO_COUNTS(STLTOPO_STATS_COUNT)
  STLTOPO_OTHER_COUNTS(STLTOPO_STATS_COUNT)
#undef STLTOPO_STATS_COUNT
  s.eulerCharacteristic = c.eulerCharacteristic();
  s.watertight = c.watertight();
  s.manifold = c.manifold();
  return s;
}

}  // namespace edit_detail
}  // namespace stltopo
