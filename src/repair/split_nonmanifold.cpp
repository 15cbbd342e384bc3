// The repair step "split-nonmanifold" (steps.h): one vertex per fan at non-manifold
// vertices, and non-manifold edges taken apart into manifold pairs. Positions stay.
//
// The reading of "what manifold-3d does on import": manifold-3d pairs the half-edges of an
// edge with more than two sides forward with backward (as buildTopology does: first
// unpaired with first unpaired of the other direction), which leaves an edge duplicated;
// it then gives duplicated edges and pinched vertices (several fans) their own vertex
// copies. Here the unit of work is EditableMesh::splitVertex(v): v's fans are its
// triangles joined through the edges at v with two sides, and through the pairs of its
// non-manifold edges where joining keeps each edge at v at two sides at most. Splitting
// both ends of a non-manifold edge leaves each pair on its own edge (two opposite sides:
// interior) and each unpaired side on its own edge (a boundary); fans stay together
// wherever they share a manifold edge, so nothing is disconnected more than the
// non-manifold elements need.
//
// Items: one per vertex split (the vertices that are non-manifold or on a non-manifold
// edge, in id order), in rounds until nothing is left to split (splitting one end of an
// edge can change what the other end needs). A vertex with one fan is not split: it is
// listed as skipped only if it is still non-manifold at the end (its fans are joined
// through inconsistent edges: the orient step fixes those).
#include <algorithm>
#include <string>
#include <vector>

#include "repair/steps.h"
#include "text_format.h"
#include "try_alloc.h"

namespace stltopo {
namespace repair_detail {
namespace {

constexpr const char* kSplitArrays = "the split-nonmanifold step's work arrays";

// The vertices to look at: non-manifold, or an end of a non-manifold edge. `why`: bit 1
// non-manifold vertex, bit 2 on a non-manifold edge.
Status candidates(EditableMesh& em, Array<uint32_t>& out, Array<uint8_t>& why) {
  out.clear();
  if (!why.assign(em.nVertices(), 0)) return detail::oom(kSplitArrays);
  const Array<uint8_t>& nm = em.vertexNonManifoldFlags();
  for (uint32_t v = 0; v < em.nVertices(); ++v)
    if (em.vertexAlive(v) && nm[v]) why[v] |= 1;
  const Array<uint8_t>& kind = em.pairKind();
  const Array<uint32_t>& vert = em.vert();
  for (uint32_t k = 0; k < kind.size(); ++k)
    if (vert[2 * k] != kInvalid && kind[k] == uint8_t(EdgeKind::NonManifold)) {
      why[vert[2 * k]] |= 2;
      why[vert[2 * k + 1]] |= 2;
    }
  for (uint32_t v = 0; v < em.nVertices(); ++v)
    if (why[v] && !out.push_back(v)) return detail::oom(kSplitArrays);
  return Status{};
}

const char* describe(uint8_t why) {
  return why == 3 ? "non-manifold, on a non-manifold edge" : why == 1 ? "non-manifold" : "on a non-manifold edge";
}

std::string reasonOf(const Status& s) {
  const std::string prefix = std::string(codeName(s.code)) + ": ";
  return s.message.compare(0, prefix.size(), prefix) == 0 ? s.message.substr(prefix.size()) : s.message;
}

}  // namespace

Status runSplitNonManifold(StepContext& ctx) {
  EditableMesh& em = ctx.em;
  Array<uint32_t> cand;
  Array<uint8_t> why;
  Array<uint8_t> handled;  // per vertex: listed (split, or left out by the user)
  for (int round = 0; round < 64; ++round) {
    Status s = candidates(em, cand, why);
    if (!s.ok()) return s;
    while (handled.size() < em.nVertices())
      if (!handled.push_back(0)) return detail::oom(kSplitArrays);
    // Triangles at each candidate (for the items' element lists).
    Array<uint32_t> slot;
    if (!slot.assign(em.nVertices(), kInvalid)) return detail::oom(kSplitArrays);
    std::vector<std::vector<uint32_t>> trisAt;
#if defined(__cpp_exceptions)
    try {
#endif
      trisAt.resize(cand.size());
#if defined(__cpp_exceptions)
    } catch (...) {
      return detail::oom(kSplitArrays);
    }
#endif
    for (uint32_t i = 0; i < cand.size(); ++i) slot[cand[i]] = i;
    const Array<uint32_t>& T = em.triangles();
    for (uint32_t t = 0; t < em.nTriangles(); ++t)
      if (em.triangleAlive(t))
        for (uint32_t c = 0; c < 3; ++c) {
          uint32_t i = slot[T[3 * t + c]];
          if (i != kInvalid && (trisAt[i].empty() || trisAt[i].back() != t)) trisAt[i].push_back(t);
        }
    bool progress = false;
    for (uint32_t i = 0; i < cand.size(); ++i) {
      const uint32_t v = cand[i];
      if (v < handled.size() && handled[v]) continue;
      ctx.begin(text("split vertex %u (%s) into one vertex per fan", v, describe(why[v])), trisAt[i], {v});
      if (ctx.excluded()) {
        handled[v] = 1;
        continue;
      }
      uint32_t first = kInvalid, count = 0;
      s = em.splitVertex(v, &first, &count);
      if (s.code == Code::EditRefused) {
        ctx.plan.items.pop_back();  // one fan: perhaps after its neighbours are split; listed at the end if not
        continue;
      }
      if (!s.ok()) return s;
      RepairItem& item = ctx.plan.items.back();
      item.action = count == 1 ? text("split vertex %u (%s) into 2 fans: new vertex %u at the same position", v,
                                      describe(why[v]), first)
                               : text("split vertex %u (%s) into %u fans: new vertices %u-%u at the same position", v,
                                      describe(why[v]), count + 1, first, first + count - 1);
      for (uint32_t k = 0; k < count; ++k) item.vertices.push_back(first + k);
      progress = true;
    }
    if (!progress) break;
  }
  // What is left: listed as skipped, with the reason.
  Status s = candidates(em, cand, why);
  if (!s.ok()) return s;
  for (uint32_t v : cand) {
    if (v < handled.size() && handled[v]) continue;
    ctx.begin(text("split vertex %u (%s) into one vertex per fan", v, describe(why[v])), {}, {v});
    if (ctx.excluded()) continue;
    Status r = em.splitVertex(v);
    if (r.ok())
      return Status::error(Code::Invalid,
                           "split-nonmanifold: a vertex split after the last round (a defect of the library)");
    if (r.code != Code::EditRefused) return r;
    ctx.skip(reasonOf(r) + ((why[v] & 1) ? " (its fans are joined through inconsistent edges: orient first)" : ""));
  }
  const EditStats& st = em.stats();
  if (st.nonManifoldVertices > 0 || st.nonManifoldEdges > 0)
    ctx.plan.note =
        text("%u non-manifold vertices and %u non-manifold edges remain", st.nonManifoldVertices, st.nonManifoldEdges);
  return Status{};
}

}  // namespace repair_detail
}  // namespace stltopo
