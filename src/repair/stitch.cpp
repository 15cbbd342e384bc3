// The repair step "stitch" (steps.h): closes cracks along boundary loops.
//
// Phase 1, with RepairOptions::stitchTolerance > 0: boundary vertices at most the tolerance
// apart (Euclidean, decided exactly: pred::withinDistance) that are not joined by an edge are
// matched, closest pairs first (the distance in double orders them; ties by vertex ids), each
// vertex at most once. Matched pairs that follow each other
// along both boundaries (u1-u2 and v1-v2 are boundary edges) form one crack, and so do
// pairs joined by a T-junction: an unmatched boundary vertex on a boundary edge (or within
// the tolerance of it) whose ends are matched (a crack between different tessellations).
// Each crack is one item, done by one EditableMesh::stitch (all its pairs and T-junctions
// or none; the lower id of each pair stays where it is). When a crack with T-junctions is
// refused, its pairs are tried again crack by crack without them (phase 2 retries the
// T-junctions). A single pair whose edges do not join would pinch two fans together: the
// editor refuses it, and so it is skipped with that reason.
//
// Phase 2: T-junctions. A boundary vertex v that lies on a boundary edge a-b it is not an
// end of: exactly (v collinear with a and b by the exact predicates and strictly between
// them), or, with a tolerance, within that distance of the segment (its projection strictly
// inside, and farther than the tolerance from both ends, which phase 1 handles), each decided
// exactly (pred::withinDistance, dotSign, withinLineDistance). Each is
// one item: EditableMesh::splitEdgeAt(a-b, v), the same as splitEdge at v's projection and
// merging the new vertex into v (v stays). Rounds repeat while they close something (an
// edge split at one vertex may carry the next T-junction on one of its parts).
//
// Never worse: mergeVertices and splitEdgeAt refuse any change that would add boundary,
// non-manifold or inconsistent edges, or non-manifold vertices (an edge may only gain
// sides by two boundary sides pairing up), or fold a triangle over; refused items are
// skipped with the editor's reason and change nothing. The step checks the figures at the
// end as well and fails (the runner then restores the mesh) if they grew.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "predicates.h"
#include "repair/steps.h"
#include "text_format.h"
#include "try_alloc.h"

namespace stltopo {
namespace repair_detail {
namespace {

constexpr const char* kStitchArrays = "the stitch step's work arrays";

inline uint64_t keyOf(uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a; }

bool sortedHas(const Array<uint64_t>& a, uint64_t k) { return std::binary_search(a.begin(), a.end(), k); }

// The editor's message without its "edit-refused: " prefix.
std::string reasonOf(const Status& s) {
  const std::string prefix = std::string(codeName(s.code)) + ": ";
  return s.message.compare(0, prefix.size(), prefix) == 0 ? s.message.substr(prefix.size()) : s.message;
}

// A uniform grid over points: cell coordinates floor(x / cell), clamped so that huge
// ratios stay finite (clamping is monotone: points within one cell of each other stay
// within one cell).
struct CellKey {
  int64_t c[3];
  bool operator<(const CellKey& o) const {
    return c[0] != o.c[0] ? c[0] < o.c[0] : c[1] != o.c[1] ? c[1] < o.c[1] : c[2] < o.c[2];
  }
  bool operator==(const CellKey& o) const { return c[0] == o.c[0] && c[1] == o.c[1] && c[2] == o.c[2]; }
};
inline int64_t cellOf(double x, double cell) {
  double q = std::floor(x / cell);
  if (!(q > -1e15)) q = -1e15;
  if (q > 1e15) q = 1e15;
  return int64_t(q);
}
struct Entry {
  CellKey key;
  uint32_t id;
};

// Statistics the step must not make worse.
struct Figures {
  uint32_t badEdges, nonManifoldVertices, nonManifoldEdges, inconsistentEdges;
};
Figures figures(EditableMesh& em) {
  const EditStats& s = em.stats();
  return {s.boundaryEdges + s.nonManifoldEdges + s.inconsistentEdges, s.nonManifoldVertices, s.nonManifoldEdges,
          s.inconsistentEdges};
}

// The boundary edges (kind Boundary) in the loops: for each, its loop half-edge.
Status boundaryHalfedges(EditableMesh& em, Array<uint32_t>& out) {
  out.clear();
  const EditLoops& L = em.loops();
  const Array<uint8_t>& kind = em.pairKind();
  for (uint32_t i = 0; i < L.loopHalfedges.size(); ++i) {
    uint32_t x = L.loopHalfedges[i];
    if (kind[x >> 1] == uint8_t(EdgeKind::Boundary) && !out.push_back(x)) return detail::oom(kStitchArrays);
  }
  return Status{};
}

// A T-junction candidate: boundary vertex v at distance d from boundary edge a-b (loop
// half-edge he, a = its origin), its projection strictly inside the edge.
struct TCand {
  double d;
  uint32_t v, he, a, b;
};
bool lessTCand(const TCand& x, const TCand& y) {
  if (x.d != y.d) return x.d < y.d;
  if (x.v != y.v) return x.v < y.v;
  return keyOf(x.a, x.b) < keyOf(y.a, y.b);
}

// Every T-junction candidate among the boundary half-edges bh, sorted by (distance, vertex,
// edge): exactly on the edge (collinear by the exact predicates, strictly between its
// ends), or, with tol > 0, within tol of it and farther than tol from both ends. A grid of
// the edges (cell: the mean edge length, at least tol; an edge goes into every cell its
// box, grown by tol, meets, up to 64 cells; longer edges are checked against every vertex).
Status tCandidates(EditableMesh& em, const Array<uint32_t>& bh, double tol, Array<TCand>& cands) {
  cands.clear();
  const Array<float>& P = em.positions();
  const Array<uint32_t>& vert = em.vert();
  Array<uint32_t> bverts;
  double total = 0;
  for (uint32_t x : bh) {
    if (!bverts.push_back(vert[x])) return detail::oom(kStitchArrays);
    total += distance(P.data() + 3 * size_t(vert[x]), P.data() + 3 * size_t(vert[x ^ 1u]));
  }
  if (bh.empty()) return Status{};
  std::sort(bverts.begin(), bverts.end());
  bverts.shrink(size_t(std::unique(bverts.begin(), bverts.end()) - bverts.begin()));
  // Boxes grow by 2 tol: a vertex within tol of an edge lies in its box grown by tol, and the
  // margin covers the rounding of the box's sides (rounding is monotone, and a float within
  // tol of a side is farther than its rounding error from it).
  const double margin = 2 * tol, tol2 = tol * tol;
  double cell = std::max(total / double(bh.size()), margin);
  if (!(cell > 0) || !std::isfinite(cell)) cell = 1;
  Array<Entry> grid;
  Array<uint32_t> big;
  for (uint32_t i = 0; i < bh.size(); ++i) {
    const float* a = P.data() + 3 * size_t(vert[bh[i]]);
    const float* b = P.data() + 3 * size_t(vert[bh[i] ^ 1u]);
    int64_t lo[3], hi[3], n = 1;
    for (int k = 0; k < 3; ++k) {
      lo[k] = cellOf(std::min(a[k], b[k]) - margin, cell);
      hi[k] = cellOf(std::max(a[k], b[k]) + margin, cell);
      n *= (hi[k] - lo[k] + 1);
      if (n > 64) break;
    }
    if (n > 64) {
      if (!big.push_back(i)) return detail::oom(kStitchArrays);
      continue;
    }
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z)
          if (!grid.push_back(Entry{{{x, y, z}}, i})) return detail::oom(kStitchArrays);
  }
  std::sort(grid.begin(), grid.end(),
            [](const Entry& a, const Entry& b) { return a.key < b.key || (a.key == b.key && a.id < b.id); });
  auto consider = [&](uint32_t v, uint32_t i) {
    const uint32_t x = bh[i], a = vert[x], b = vert[x ^ 1u];
    if (v == a || v == b) return true;
    const float *pa = P.data() + 3 * size_t(a), *pb = P.data() + 3 * size_t(b), *pv = P.data() + 3 * size_t(v);
    double d;
    if (pred::collinear(pa, pb, pv)) {
      // Strictly between, exactly: along the axis where a and b differ most.
      int k = 0;
      for (int j = 1; j < 3; ++j)
        if (std::fabs(double(pb[j]) - pa[j]) > std::fabs(double(pb[k]) - pa[k])) k = j;
      float lo = std::min(pa[k], pb[k]), hi = std::max(pa[k], pb[k]);
      if (!(lo < pv[k] && pv[k] < hi)) return true;
      d = 0;
    } else {
      if (!(tol > 0)) return true;
      // Exactly (predicates.h): farther than tol from both ends, its projection strictly
      // inside the edge, within tol of the edge's line.
      if (pred::withinDistance(pv, pa, tol, tol2) || pred::withinDistance(pv, pb, tol, tol2)) return true;
      if (pred::dotSign(pv, pa, pb) <= 0 || pred::dotSign(pv, pb, pa) <= 0) return true;
      if (!pred::withinLineDistance(pv, pa, pb, tol, tol2)) return true;
      // The distance, in double, only orders the candidates.
      double ab[3], av[3], ab2 = 0, t = 0;
      for (int k = 0; k < 3; ++k) {
        ab[k] = double(pb[k]) - pa[k];
        av[k] = double(pv[k]) - pa[k];
        ab2 += ab[k] * ab[k];
        t += av[k] * ab[k];
      }
      t /= ab2;
      double q[3] = {pa[0] + t * ab[0], pa[1] + t * ab[1], pa[2] + t * ab[2]};
      d = std::sqrt((pv[0] - q[0]) * (pv[0] - q[0]) + (pv[1] - q[1]) * (pv[1] - q[1]) +
                    (pv[2] - q[2]) * (pv[2] - q[2]));
    }
    return cands.push_back(TCand{d, v, x, a, b});
  };
  for (uint32_t v : bverts) {
    const float* p = P.data() + 3 * size_t(v);
    CellKey k{{cellOf(p[0], cell), cellOf(p[1], cell), cellOf(p[2], cell)}};
    const Entry* it =
        std::lower_bound(grid.begin(), grid.end(), k, [](const Entry& a, const CellKey& b) { return a.key < b; });
    for (; it != grid.end() && it->key == k; ++it)
      if (!consider(v, it->id)) return detail::oom(kStitchArrays);
    for (uint32_t i : big)
      if (!consider(v, i)) return detail::oom(kStitchArrays);
  }
  std::sort(cands.begin(), cands.end(), lessTCand);
  return Status{};
}

// ---------------------------------------------------------------------------- phase 1
Status mergePairs(StepContext& ctx) {
  EditableMesh& em = ctx.em;
  const double tol = ctx.options.stitchTolerance;
  const Array<float>& P = em.positions();
  const Array<uint32_t>& vert = em.vert();
  const Array<uint32_t>& T = em.triangles();
  Array<uint32_t> bh;
  Status s = boundaryHalfedges(em, bh);
  if (!s.ok()) return s;
  if (bh.empty()) return Status{};
  // Boundary vertices, boundary edges (both directions, for neighbours), every edge.
  Array<uint32_t> bverts;
  Array<uint64_t> bnbr, bedges, edges;
  for (uint32_t x : bh) {
    uint32_t a = vert[x], b = vert[x ^ 1u];
    if (!bverts.push_back(a) || !bverts.push_back(b) || !bnbr.push_back((uint64_t(a) << 32) | b) ||
        !bnbr.push_back((uint64_t(b) << 32) | a) || !bedges.push_back(keyOf(a, b)))
      return detail::oom(kStitchArrays);
  }
  for (uint32_t t = 0; t < em.nTriangles(); ++t) {
    if (!em.triangleAlive(t)) continue;
    for (uint32_t c = 0; c < 3; ++c)
      if (!edges.push_back(keyOf(T[3 * t + c], T[3 * t + (c + 1) % 3]))) return detail::oom(kStitchArrays);
  }
  std::sort(bverts.begin(), bverts.end());
  bverts.shrink(size_t(std::unique(bverts.begin(), bverts.end()) - bverts.begin()));
  std::sort(bnbr.begin(), bnbr.end());
  std::sort(bedges.begin(), bedges.end());
  std::sort(edges.begin(), edges.end());
  // Candidate pairs within the tolerance (exactly: pred::withinDistance), found through a grid
  // of cells 2 tol wide and their neighbours: two points within tol are within half a cell on
  // each axis, and the quotients' rounding (below a quarter cell up to the clamp at 1e15 cells)
  // cannot put them two cells apart, as it could with cells tol wide.
  const double cellSize = 2 * tol, tol2 = tol * tol;
  Array<Entry> grid;
  for (uint32_t v : bverts) {
    const float* p = P.data() + 3 * size_t(v);
    if (!grid.push_back(Entry{{{cellOf(p[0], cellSize), cellOf(p[1], cellSize), cellOf(p[2], cellSize)}}, v}))
      return detail::oom(kStitchArrays);
  }
  std::sort(grid.begin(), grid.end(),
            [](const Entry& a, const Entry& b) { return a.key < b.key || (a.key == b.key && a.id < b.id); });
  struct Cand {
    double d;
    uint32_t u, v;
  };
  Array<Cand> cands;
  for (const Entry& e : grid) {
    const float* p = P.data() + 3 * size_t(e.id);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          CellKey k{{e.key.c[0] + dx, e.key.c[1] + dy, e.key.c[2] + dz}};
          const Entry* it =
              std::lower_bound(grid.begin(), grid.end(), k, [](const Entry& a, const CellKey& b) { return a.key < b; });
          for (; it != grid.end() && it->key == k; ++it) {
            if (it->id <= e.id) continue;
            const float* q = P.data() + 3 * size_t(it->id);
            if (!pred::withinDistance(p, q, tol, tol2) || sortedHas(edges, keyOf(e.id, it->id))) continue;
            const double d = distance(p, q);  // the order only
            if (!cands.push_back(Cand{d, e.id, it->id})) return detail::oom(kStitchArrays);
          }
        }
  }
  if (cands.empty()) return Status{};
  std::sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) {
    return a.d != b.d ? a.d < b.d : a.u != b.u ? a.u < b.u : a.v < b.v;
  });
  // Greedy matching, closest first; partner[v] for matched vertices.
  Array<uint32_t> partner;
  if (!partner.assign(em.nVertices(), kInvalid)) return detail::oom(kStitchArrays);
  Array<uint32_t> pu, pv;  // the matched pairs (u < v)
  Array<double> pd;
  for (const Cand& c : cands) {
    if (partner[c.u] != kInvalid || partner[c.v] != kInvalid) continue;
    partner[c.u] = c.v;
    partner[c.v] = c.u;
    if (!pu.push_back(c.u) || !pv.push_back(c.v) || !pd.push_back(c.d)) return detail::oom(kStitchArrays);
  }
  // Cracks: pairs (u1, v1), (u2, v2) with boundary edges u1-u2 and v1-v2 (or u1-v2, v1-u2).
  const uint32_t np = uint32_t(pu.size());
  Array<uint32_t> pairOf, parent;
  if (!pairOf.assign(em.nVertices(), kInvalid) || !parent.resize(np)) return detail::oom(kStitchArrays);
  for (uint32_t i = 0; i < np; ++i) {
    pairOf[pu[i]] = pairOf[pv[i]] = i;
    parent[i] = i;
  }
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (uint32_t i = 0; i < np; ++i) {
    const uint32_t u = pu[i], v = pv[i];
    for (const uint64_t* it = std::lower_bound(bnbr.begin(), bnbr.end(), uint64_t(u) << 32);
         it != bnbr.end() && uint32_t(*it >> 32) == u; ++it) {
      uint32_t w = uint32_t(*it), j = pairOf[w];
      if (j == kInvalid || j == i) continue;
      if (sortedHas(bedges, keyOf(v, partner[w]))) {
        uint32_t a = find(i), b = find(j);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
  }
  // T-junctions beside the pairs: an unmatched boundary vertex on (or within tol of) a
  // boundary edge with a matched end (its nearest such edge) joins the crack of that end's
  // pair, and joins the cracks of both ends (a crack whose sides have different vertices).
  Array<uint32_t> parentA;  // the cracks by adjacency alone (the fallback)
  if (!parentA.resize(np)) return detail::oom(kStitchArrays);
  for (uint32_t i = 0; i < np; ++i) parentA[i] = find(i);
  Array<TCand> all, ts;
  s = tCandidates(em, bh, tol, all);
  if (!s.ok()) return s;
  Array<uint8_t> hasT;  // one edge per vertex: its nearest (`all` is sorted by distance)
  if (!hasT.assign(em.nVertices(), 0)) return detail::oom(kStitchArrays);
  for (const TCand& c : all) {
    if (partner[c.v] != kInvalid || (pairOf[c.a] == kInvalid && pairOf[c.b] == kInvalid) || hasT[c.v]) continue;
    hasT[c.v] = 1;
    if (!ts.push_back(c)) return detail::oom(kStitchArrays);
    if (pairOf[c.a] != kInvalid && pairOf[c.b] != kInvalid) {
      uint32_t a = find(pairOf[c.a]), b = find(pairOf[c.b]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  auto groupOfT = [&](const TCand& c) { return find(pairOf[c.a] != kInvalid ? pairOf[c.a] : pairOf[c.b]); };
  // Items in order of their lowest pair (pairs are in matching order: closest first).
  Array<uint32_t> order;
  for (uint32_t i = 0; i < np; ++i)
    if (!order.push_back(i)) return detail::oom(kStitchArrays);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return find(a) < find(b); });
  // Triangles at each vertex (CSR), for the items' element lists.
  Array<uint32_t> off, triAt;
  if (!off.assign(size_t(em.nVertices()) + 1, 0)) return detail::oom(kStitchArrays);
  for (uint32_t t = 0; t < em.nTriangles(); ++t)
    if (em.triangleAlive(t))
      for (uint32_t c = 0; c < 3; ++c) ++off[T[3 * t + c] + 1];
  for (uint32_t v = 0; v < em.nVertices(); ++v) off[v + 1] += off[v];
  if (!triAt.resize(off[em.nVertices()])) return detail::oom(kStitchArrays);
  {
    Array<uint32_t> fill;
    if (!fill.resize(em.nVertices())) return detail::oom(kStitchArrays);
    std::memcpy(fill.data(), off.data(), size_t(em.nVertices()) * 4);
    for (uint32_t t = 0; t < em.nTriangles(); ++t)
      if (em.triangleAlive(t))
        for (uint32_t c = 0; c < 3; ++c) triAt[fill[T[3 * t + c]]++] = t;
  }
  const Array<uint32_t>& faces = em.faceWords();
  // One item: the pairs order[b, e) and the T-junctions tsOf, as one edit. Returns the
  // edit's status (a refusal is listed as skipped).
  auto item = [&](size_t b, size_t e, const std::vector<const TCand*>& tsOf) -> Status {
    std::vector<uint32_t> keep, gone, tris, verts, edgesT, vertsT;
    std::string action =
        tsOf.empty()
            ? (e - b == 1 ? std::string("merge vertex") : text("close a crack: merge %u vertices:", uint32_t(e - b)))
            : text("close a crack: merge %u vertices and split %u boundary edges at T-junctions:", uint32_t(e - b),
                   uint32_t(tsOf.size()));
    double maxD = 0;
    for (size_t i = b; i < e; ++i) {
      const uint32_t k = order[i];
      keep.push_back(pu[k]);
      gone.push_back(pv[k]);
      maxD = std::max(maxD, pd[k]);
      if (i - b < 8) detail::appendf(action, "%s %u into %u (%.9g apart)", i == b ? "" : ",", pv[k], pu[k], pd[k]);
      for (uint32_t x = off[pv[k]]; x < off[pv[k] + 1]; ++x) tris.push_back(triAt[x]);
      verts.push_back(pu[k]);
      verts.push_back(pv[k]);
    }
    if (e - b > 8) detail::appendf(action, ", and %u more (all at most %.9g apart)", uint32_t(e - b - 8), maxD);
    for (size_t i = 0; i < tsOf.size(); ++i) {
      const TCand& c = *tsOf[i];
      edgesT.push_back(c.he);
      vertsT.push_back(c.v);
      tris.push_back(faces[c.he ^ 1u]);
      verts.push_back(c.v);
      if (i < 8)
        detail::appendf(action, "%s edge %u-%u at %u (%.9g from it)", i == 0 ? " then" : ",", c.a, c.b, c.v, c.d);
    }
    if (tsOf.size() > 8) detail::appendf(action, ", and %u more", uint32_t(tsOf.size() - 8));
    std::sort(tris.begin(), tris.end());
    tris.erase(std::unique(tris.begin(), tris.end()), tris.end());
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    ctx.begin(std::move(action), std::move(tris), std::move(verts));
    if (ctx.excluded()) return Status{};
    Status st = em.stitch(keep.data(), gone.data(), uint32_t(keep.size()), edgesT.data(), vertsT.data(),
                          uint32_t(edgesT.size()), false);
    // The editor refuses (edit-refused), or finds the T-junctions inconsistent
    // (invalid-argument: a vertex splitting an edge twice): either way nothing changed.
    if (st.code == Code::EditRefused || st.code == Code::InvalidArgument) {
      ctx.skip(reasonOf(st));
      return Status::error(Code::EditRefused, st.message);
    }
    return st;
  };
  for (size_t b = 0; b < order.size();) {
    size_t e = b;
    while (e < order.size() && find(order[e]) == find(order[b])) ++e;
    std::vector<const TCand*> tsOf;
    for (const TCand& c : ts)
      if (groupOfT(c) == find(order[b])) tsOf.push_back(&c);
    Status st = item(b, e, tsOf);
    if (!st.ok() && st.code != Code::EditRefused) return st;
    if (st.code == Code::EditRefused && !tsOf.empty() && e - b > 0) {
      // The pairs alone, crack by crack (the T-junctions wait for phase 2).
      std::stable_sort(order.begin() + long(b), order.begin() + long(e),
                       [&](uint32_t x, uint32_t y) { return parentA[x] < parentA[y]; });
      for (size_t c = b; c < e;) {
        size_t d = c;
        while (d < e && parentA[order[d]] == parentA[order[c]]) ++d;
        st = item(c, d, {});
        if (!st.ok() && st.code != Code::EditRefused) return st;
        c = d;
      }
    }
    b = e;
  }
  return Status{};
}

// ---------------------------------------------------------------------------- phase 2
Status closeTJunctions(StepContext& ctx) {
  EditableMesh& em = ctx.em;
  const double tol = ctx.options.stitchTolerance;
  // The T-junctions tried in earlier rounds (vertex, edge), sorted; a round tries each
  // candidate once (a vertex meets each edge in one grid cell only).
  struct Tried {
    uint32_t v;
    uint64_t edge;
    bool operator<(const Tried& o) const { return v != o.v ? v < o.v : edge < o.edge; }
  };
  Array<Tried> done, roundDone;
  auto wasTried = [&](uint32_t v, uint32_t a, uint32_t b) {
    return std::binary_search(done.begin(), done.end(), Tried{v, keyOf(a, b)});
  };
  Array<uint8_t> busy;  // per vertex: its edges changed in this round
  for (int round = 0; round < 64; ++round) {
    Array<uint32_t> bh;
    Status s = boundaryHalfedges(em, bh);
    if (!s.ok()) return s;
    if (bh.empty()) return Status{};
    Array<TCand> all, cands;
    s = tCandidates(em, bh, tol, all);
    if (!s.ok()) return s;
    for (const TCand& c : all)
      if (!wasTried(c.v, c.a, c.b) && !cands.push_back(c)) return detail::oom(kStitchArrays);
    if (cands.empty()) return Status{};
    // One item per T-junction; an edge or vertex changed in this round waits for the next.
    if (!busy.assign(em.nVertices(), 0)) return detail::oom(kStitchArrays);
    roundDone.clear();
    bool progress = false;
    for (const TCand& c : cands) {
      if (busy[c.v] || busy[c.a] || busy[c.b]) continue;
      // The edge as found (an edit of this round may have moved it: then the next round).
      if (!em.halfedgeAlive(c.he) || !em.isBoundary(c.he) || em.vert()[c.he] != c.a || em.vert()[c.he ^ 1u] != c.b)
        continue;
      if (!roundDone.push_back(Tried{c.v, keyOf(c.a, c.b)})) return detail::oom(kStitchArrays);
      const uint32_t tri = em.faceWords()[c.he ^ 1u];
      const uint32_t* C = em.triangles().data() + 3 * size_t(tri);
      const uint32_t o = C[0] != c.a && C[0] != c.b ? C[0] : C[1] != c.a && C[1] != c.b ? C[1] : C[2];
      std::string action =
          c.d == 0
              ? text("close T-junction: split boundary edge %u-%u at vertex %u (on the edge)", c.a, c.b, c.v)
              : text("close T-junction: split boundary edge %u-%u at vertex %u (%.9g from it)", c.a, c.b, c.v, c.d);
      ctx.begin(std::move(action), {tri}, {c.v, c.a, c.b});
      if (ctx.excluded()) continue;
      Status st = em.splitEdgeAt(c.he, c.v, false);
      if (st.code == Code::EditRefused || st.code == Code::InvalidArgument) {
        ctx.skip(reasonOf(st));
        continue;
      }
      if (!st.ok()) return st;
      progress = true;
      busy[c.v] = busy[c.a] = busy[c.b] = busy[o] = 1;
    }
    for (const Tried& t : roundDone)
      if (!done.push_back(t)) return detail::oom(kStitchArrays);
    std::sort(done.begin(), done.end());
    if (!progress) return Status{};
  }
  return Status{};
}

}  // namespace

Status runStitch(StepContext& ctx) {
  const double tol = ctx.options.stitchTolerance;
  if (!(tol >= 0) || !std::isfinite(tol))
    return Status::error(Code::InvalidArgument,
                         detail::format("the stitch tolerance must be a finite distance >= 0, not %g", tol));
  const Figures before = figures(ctx.em);
  Status s;
  if (tol > 0) s = mergePairs(ctx);
  if (s.ok()) s = closeTJunctions(ctx);
  if (!s.ok()) return s;
  const Figures after = figures(ctx.em);
  if (after.badEdges > before.badEdges || after.nonManifoldVertices > before.nonManifoldVertices ||
      after.nonManifoldEdges > before.nonManifoldEdges || after.inconsistentEdges > before.inconsistentEdges)
    return Status::error(Code::Invalid, "stitch made the figures worse (a defect of the library): the step is undone");
  return Status{};
}

}  // namespace repair_detail
}  // namespace stltopo
