// The repair steps' frame: items, exclusions, snapshots (steps.h).
#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <limits>

#include "repair/steps.h"
#include "stltopo/topology.h"

namespace stltopo {
namespace repair_detail {

RepairItem& StepContext::begin(std::string action, std::vector<uint32_t> triangles, std::vector<uint32_t> vertices,
                               std::vector<uint32_t> loops) {
  RepairItem item;
  item.action = std::move(action);
  float lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<float>::infinity();
    hi[k] = -std::numeric_limits<float>::infinity();
  }
  const Array<float>& P = em.positions();
  const Array<uint32_t>& T = em.triangles();
  auto addVertex = [&](uint32_t v) {
    if (v >= em.nVertices()) return;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], P[3 * size_t(v) + k]);
      hi[k] = std::max(hi[k], P[3 * size_t(v) + k]);
    }
  };
  for (uint32_t t : triangles)
    if (em.triangleAlive(t))
      for (int c = 0; c < 3; ++c) addVertex(T[3 * size_t(t) + c]);
  for (uint32_t v : vertices) addVertex(v);
  if (!loops.empty()) {
    const EditLoops& L = em.loops();
    const Array<uint32_t>& vert = em.vert();
    for (uint32_t h : loops)
      if (h < L.nLoops())
        for (uint32_t i = L.loopOffsets[h]; i < L.loopOffsets[h + 1]; ++i) addVertex(vert[L.loopHalfedges[i]]);
  }
  if (lo[0] <= hi[0])
    for (int k = 0; k < 3; ++k) {
      item.bbox[k] = lo[k];
      item.bbox[3 + k] = hi[k];
    }
  item.triangles = std::move(triangles);
  item.vertices = std::move(vertices);
  item.loops = std::move(loops);
  plan.items.push_back(std::move(item));
  return plan.items.back();
}

bool StepContext::excluded() {
  uint32_t index = uint32_t(plan.items.size()) - 1;
  for (const RepairOptions::Exclusion& x : options.exclude)
    if (x.step == plan.kind && x.item == index) {
      skip("left out by the user");
      return true;
    }
  return false;
}

std::string text(const char* f, ...) {
  char buf[256];
  va_list ap, again;
  va_start(ap, f);
  va_copy(again, ap);
  const int n = std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  std::string out;
  if (n >= 0 && size_t(n) < sizeof buf) {
    out.assign(buf, size_t(n));
  } else if (n >= 0) {
    out.resize(size_t(n));
    std::vsnprintf(out.data(), size_t(n) + 1, f, again);
  }
  va_end(again);
  return out;
}

Status snapshot(const EditableMesh& em, Mesh& mesh, Topology& topo) { return em.toMesh(mesh, &topo, nullptr); }

}  // namespace repair_detail
}  // namespace stltopo
