// The repair steps that remove or turn whole triangles: duplicates, zero-area, orient,
// small-shells. The frame is in steps.h.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "predicates.h"
#include "repair/steps.h"
#include "stltopo/geometry.h"
#include "stltopo/shells.h"
#include "stltopo/topology.h"
#include "text_format.h"
#include "try_alloc.h"

namespace stltopo {
namespace repair_detail {

namespace {

constexpr const char* kStepArrays = "the repair step's arrays";

// The mesh and topology the step found (the context's, or a fresh snapshot).
struct Found {
  Mesh mesh;
  Topology topo;
  const Mesh* m = nullptr;
  const Topology* t = nullptr;
  const TriangleChecks* c = nullptr;  // checks()
  // c: the triangle checks of m, the runner's when it has them (m is ctx's then), else
  // made into `own`. After get().
  Status checks(const StepContext& ctx, TriangleChecks& own) {
    c = ctx.mesh && ctx.topo ? ctx.checks : nullptr;
    if (c) return Status{};
    c = &own;
    return checkTriangles(*m, t, own, ctx.options.threads);
  }
  Status get(const StepContext& ctx) {
    if (ctx.mesh && ctx.topo) {
      m = ctx.mesh;
      t = ctx.topo;
      return Status{};
    }
    Status s = snapshot(ctx.em, mesh, topo);
    m = &mesh;
    t = &topo;
    return s;
  }
};

// The mesh now held by em, with the shells (topology with triangleShell).
Status shellsNow(const EditableMesh& em, Mesh& mesh, Topology& topo, Array<Shell>& shells, unsigned threads) {
  Status s = em.toMesh(mesh, nullptr, nullptr);
  if (!s.ok()) return s;
  TopologyOptions o;
  o.triangleShell = true;
  o.prevAndFace = false;
  o.threads = threads;
  s = buildTopology(mesh, topo, o);
  if (!s.ok()) return s;
  return findShellsAndDefects(mesh, topo, &shells, nullptr);
}

std::string idText(const std::vector<uint32_t>& ids, size_t from, size_t maxShown = 8) {
  std::string s;
  for (size_t i = from; i < ids.size() && i < from + maxShown; ++i)
    detail::appendf(s, "%s%u", i > from ? ", " : "", ids[i]);
  if (ids.size() > from + maxShown) detail::appendf(s, " and %zu more", ids.size() - from - maxShown);
  return s;
}

const float* pos(const EditableMesh& em, uint32_t v) { return em.positions().data() + 3 * size_t(v); }

// The half-edge of triangle t from vertex u to vertex w, or kInvalid.
uint32_t sideOf(const EditableMesh& em, uint32_t t, uint32_t u, uint32_t w) {
  uint32_t e = em.triangleHalfedge()[t];
  if (e == kInvalid) return kInvalid;
  for (int i = 0; i < 3; ++i, e = em.next()[e])
    if (em.vert()[e] == u && em.vert()[em.next()[e]] == w) return e;
  return kInvalid;
}

}  // namespace

// ============================================================================ duplicates

Status runDuplicates(StepContext& ctx) {
  Found f;
  Status s = f.get(ctx);
  if (!s.ok()) return s;
  TriangleChecks own;
  s = f.checks(ctx, own);
  if (!s.ok()) return s;
  const TriangleChecks& checks = *f.c;
  ctx.plan.note = ctx.options.removeOppositeDuplicates
                      ? "keeps the lowest id of each group; groups that face both ways are removed whole"
                      : "keeps the lowest id of each group; groups that face both ways (zero-thickness walls) stay";
  for (uint32_t g = 0; g < checks.nDuplicateGroups(); ++g) {
    std::vector<uint32_t> members(checks.duplicateTriangles.data() + checks.duplicateOffsets[g],
                                  checks.duplicateTriangles.data() + checks.duplicateOffsets[g + 1]);
    const bool wall = DuplicateOrientation(checks.duplicateOrientation[g]) != DuplicateOrientation::Same;
    std::string action = wall ? text("remove the %zu triangles of a zero-thickness wall (%s)", members.size(),
                                     idText(members, 0).c_str())
                              : text("remove triangle%s %s, a copy of %u", members.size() > 2 ? "s" : "",
                                     idText(members, 1).c_str(), members[0]);
    ctx.begin(std::move(action), members);
    if (ctx.excluded()) continue;
    if (wall && !ctx.options.removeOppositeDuplicates) {
      ctx.skip("its members face both ways: a zero-thickness wall (removeOppositeDuplicates removes the whole group)");
      continue;
    }
    for (size_t i = wall ? 0 : 1; i < members.size(); ++i) {
      s = ctx.em.removeTriangle(members[i]);
      if (!s.ok()) return s;
    }
  }
  return Status{};
}

// ============================================================================ zero-area

Status runZeroArea(StepContext& ctx) {
  Found f;
  Status s = f.get(ctx);
  if (!s.ok()) return s;
  TriangleChecks own;
  s = f.checks(ctx, own);
  if (!s.ok()) return s;
  const TriangleChecks& checks = *f.c;
  EditableMesh& em = ctx.em;
  ctx.plan.note =
      "flips the longest edge (the neighbour is cut in two at the middle corner: nothing moves), in rounds while "
      "neighbours that are zero-area too get flipped first; else, for a needle (the middle corner within a tenth of "
      "the triangle's length of an end), collapses its shortest edge (that corner moves onto the end); other caps "
      "are skipped";
  // Degenerate triangles first: a repeated corner is a needle whose short edge has collapsed
  // already. They are in no edge of the topology (and cover no area), so removing one changes
  // no other figure and moves nothing.
  for (uint32_t t = 0; t < em.nTriangles(); ++t) {
    if (!em.triangleAlive(t)) continue;
    const uint32_t* c = em.triangles().data() + 3 * size_t(t);
    if (c[0] != c[1] && c[1] != c[2] && c[0] != c[2]) continue;
    if (ctx.plan.items.empty())  // the first one: the note says so
      ctx.plan.note = "removes degenerate triangles (a repeated corner: nothing moves); " + ctx.plan.note;
    const int j = c[0] == c[1] ? 0 : c[0] == c[2] ? 0 : 1, k = c[0] == c[1] ? 1 : 2;  // corners j < k: one vertex
    std::vector<uint32_t> verts = {c[0]};
    for (int i = 1; i < 3; ++i)
      if (std::find(verts.begin(), verts.end(), c[i]) == verts.end()) verts.push_back(c[i]);
    ctx.begin(text("remove degenerate triangle %u (corners %d and %d are vertex %u)", t, j, k, c[k]), {t},
              std::move(verts));
    if (ctx.excluded()) continue;
    s = em.removeTriangle(t);
    if (!s.ok()) return s;
  }
  std::vector<uint32_t> pending(checks.zeroArea.begin(), checks.zeroArea.end());
  // Rounds of flips; a triangle whose neighbour across the longest edge is zero-area too
  // waits for the next round (that neighbour may be flipped away first). When a round
  // flips nothing, the rest is decided for good: a needle collapses, a cap is skipped.
  for (bool final = false;;) {
    std::vector<uint32_t> later;
    bool progress = false;
    for (uint32_t z : pending) {
      // An earlier item may have changed it (a flip rewrites the neighbour).
      if (!em.triangleAlive(z)) continue;
      const uint32_t* c = em.triangles().data() + 3 * size_t(z);
      uint32_t v[3] = {c[0], c[1], c[2]};
      if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
      if (!pred::collinear(pos(em, v[0]), pos(em, v[1]), pos(em, v[2]))) continue;
      // The middle corner, along the axis of the largest extent (where the three
      // projections are distinct, as the points are distinct and collinear).
      int axis = 0;
      float best = -1;
      for (int k = 0; k < 3; ++k) {
        float lo = std::min({pos(em, v[0])[k], pos(em, v[1])[k], pos(em, v[2])[k]});
        float hi = std::max({pos(em, v[0])[k], pos(em, v[1])[k], pos(em, v[2])[k]});
        if (hi - lo > best) {
          best = hi - lo;
          axis = k;
        }
      }
      uint32_t sorted[3] = {v[0], v[1], v[2]};
      std::sort(sorted, sorted + 3, [&](uint32_t a, uint32_t b) { return pos(em, a)[axis] < pos(em, b)[axis]; });
      const uint32_t m = sorted[1], p = sorted[0], q = sorted[2];
      // 1. Flip the longest edge p-q: the neighbour (q, p, d) becomes (m, p, d) + (d, q, m),
      //    its two halves cut at m. Valid when d is off the line.
      uint32_t e = sideOf(em, z, p, q);
      if (e == kInvalid) e = sideOf(em, z, q, p);
      std::string why;
      bool flippable = false;
      if (e != kInvalid && !em.isBoundary(e ^ 1u)) {
        uint32_t d = em.vert()[em.next()[em.next()[e ^ 1u]]];
        if (pred::collinear(pos(em, p), pos(em, q), pos(em, d))) {
          if (!final) {
            later.push_back(z);
            continue;
          }
          why = "the neighbour across the longest edge is zero-area too";
        } else {
          flippable = true;
        }
      } else {
        why = "the longest edge is on a boundary";
      }
      ctx.begin(text("remove zero-area triangle %u (corner %u lies on edge %u-%u)", z, m, p, q), {z}, {m, p, q});
      if (ctx.excluded()) continue;
      if (flippable) {
        s = em.flipEdge(e);
        if (s.ok()) {
          ctx.plan.items.back().action += text(": flip edge %u-%u", p, q);
          progress = true;
          continue;
        }
        if (s.code != Code::EditRefused) return s;
        why = "flip: " + s.message;
      }
      // 2. A needle: collapse the middle corner onto its nearer end (else the farther one,
      //    when that is as near), when it moves by at most a tenth of the triangle's length.
      const double length = distance(pos(em, p), pos(em, q));
      bool done = false;
      uint32_t ends[2] = {p, q};
      if (distance(pos(em, m), pos(em, q)) < distance(pos(em, m), pos(em, p))) std::swap(ends[0], ends[1]);
      for (uint32_t end : ends) {
        double moved = distance(pos(em, m), pos(em, end));
        if (moved > 0.1 * length) {
          why += text(
              "; not a needle: collapsing %u onto %u would move it by %g, more than a tenth of the "
              "triangle's length %g",
              m, end, moved, length);
          break;
        }
        uint32_t h = sideOf(em, z, end, m);
        double t = 0;  // end -> m: m merges into end, which stays
        if (h == kInvalid) {
          h = sideOf(em, z, m, end);
          t = 1;  // m -> end: m moves onto end
        }
        if (h == kInvalid) continue;
        s = em.collapseEdge(h, t);
        if (s.ok()) {
          RepairItem& it = ctx.plan.items.back();
          it.action += text(": collapse edge %u-%u (moves %g)", m, end, moved);
          it.moved = moved;
          done = true;
          progress = true;
          break;
        }
        if (s.code != Code::EditRefused) return s;
        why += "; collapse " + text("%u-%u: ", m, end) + s.message;
      }
      if (!done) ctx.skip(why);
    }
    if (later.empty()) break;
    pending = std::move(later);
    if (!progress) final = true;
  }
  return Status{};
}

// ============================================================================ orient

Status runOrient(StepContext& ctx) {
  Found f;
  Status s = f.get(ctx);
  if (!s.ok()) return s;
  EditableMesh& em = ctx.em;
  const Topology& T = *f.t;
  const uint32_t nt = T.nTriangles;
  ctx.reversedListed = true;  // part 1 lists its reversals; part 2's shells are not listed
  // 1. Consistency. Parity per triangle (flip or not) so that every paired side runs
  //    against its partner: across a pair whose sides run the same way (a cut, inconsistent
  //    edge) the parities differ, across an ordinary pair they are equal. A component
  //    whose constraints conflict cannot be oriented (a Moebius strip).
  //    A union-find with parities: parent[t] and rel[t], t's parity relative to its parent;
  //    a root is its component's lowest triangle (the lower root wins each union), so
  //    parities relative to the root are relative to that triangle.
  if (nt >= (1u << 31)) return Status::error(Code::InvalidArgument, "orient: too many triangles");
  Array<uint32_t> parent;
  Array<uint8_t> rel, flags;  // flags (per root): kConflict, kMixed
  constexpr uint8_t kConflict = 1, kMixed = 2;
  if (!parent.resize(nt) || !rel.assign(nt, 0) || !flags.assign(nt, 0)) return detail::oom(kStepArrays);
  for (uint32_t t = 0; t < nt; ++t) parent[t] = t;
  // The root of t, with t's parity relative to it; compresses the path.
  auto find = [&](uint32_t t, uint8_t& p) {
    uint32_t r = t;
    p = 0;
    while (parent[r] != r) {
      p ^= rel[r];
      r = parent[r];
    }
    uint32_t x = t;
    uint8_t px = p;
    while (x != r && parent[x] != r) {
      const uint32_t up = parent[x];
      const uint8_t pu = uint8_t(px ^ rel[x]);
      parent[x] = r;
      rel[x] = px;
      x = up;
      px = pu;
    }
    return r;
  };
  // Links a and b: their parities differ when `same` (the two sides run the same way).
  auto link = [&](uint32_t a, uint32_t b, uint8_t same) {
    uint8_t pa, pb;
    uint32_t ra = find(a, pa), rb = find(b, pb);
    if (ra == rb) {
      if (uint8_t(pa ^ pb) != same) flags[ra] |= kConflict;
    } else {
      if (rb < ra) {
        std::swap(ra, rb);
        std::swap(pa, pb);
      }
      parent[rb] = ra;
      rel[rb] = uint8_t(pa ^ pb ^ same);
      flags[ra] |= flags[rb];
    }
    if (same) flags[ra] |= kMixed;
  };
  // Links: every pair of two triangle sides (they run opposite ways: equal parity), and
  // the cut sides of each inconsistent edge (two sides running the same way, each paired
  // with a seam half-edge: different parity), found by sorting the few cut sides by edge.
  const uint32_t nPairs = uint32_t(T.next.size() / 2);
  for (uint32_t k = 0; k < nPairs; ++k) {
    uint32_t a = T.face[2 * k], b = T.face[2 * k + 1];
    if (a < nt && b < nt && a != b) link(a, b, 0);
  }
  {
    struct Cut {
      uint64_t key;
      uint32_t t, from;
    };
    std::vector<Cut> cuts;
    STLTOPO_TRY {
      // (By pair first: one byte per pair rules out all but the inconsistent ones.)
      for (uint32_t k = 0; k < nPairs; ++k) {
        if (EdgeKind(T.pairKind[k]) != EdgeKind::Inconsistent) continue;
        for (uint32_t e = 2 * k; e < 2 * k + 2; ++e) {
          if (T.face[e] >= nt || T.face[e ^ 1u] < nt) continue;
          uint32_t u = T.vert[e], v = T.vert[T.next[e]];
          cuts.push_back(Cut{u < v ? (uint64_t(u) << 32) | v : (uint64_t(v) << 32) | u, T.face[e], u});
        }
      }
    }
    STLTOPO_CATCH { return detail::oom(kStepArrays); }
    std::sort(cuts.begin(), cuts.end(),
              [](const Cut& a, const Cut& b) { return a.key < b.key || (a.key == b.key && a.t < b.t); });
    for (size_t i = 0; i + 1 < cuts.size(); ++i)
      if (cuts[i].key == cuts[i + 1].key && (i + 2 >= cuts.size() || cuts[i + 2].key != cuts[i].key) &&
          (i == 0 || cuts[i - 1].key != cuts[i].key) && cuts[i].t != cuts[i + 1].t)
        link(cuts[i].t, cuts[i + 1].t, cuts[i].from == cuts[i + 1].from ? 1 : 0);
  }
  // The components with a cut link (the others are consistent already), in order of their
  // lowest triangle: sizes, parity-1 counts and members (ascending), parities relative to
  // the lowest triangle.
  Array<uint32_t> slot, count1, offsets, members;  // slot: per root, its mixed component
  uint32_t nMixed = 0;
  if (!slot.assign(nt, kInvalid)) return detail::oom(kStepArrays);
  for (uint32_t t = 0; t < nt; ++t) {
    uint8_t p;
    const uint32_t r = find(t, p);
    rel[t] = p;  // now relative to the root (parent[t] is the root, or t is)
    if (r == t && (flags[t] & kMixed) && !T.triangleDegenerate[t]) slot[t] = nMixed++;
  }
  if (!offsets.assign(size_t(nMixed) + 1, 0) || !count1.assign(nMixed, 0)) return detail::oom(kStepArrays);
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t c = slot[parent[t]];
    if (c == kInvalid) continue;
    ++offsets[c + 1];
    count1[c] += rel[t];
  }
  for (uint32_t c = 0; c < nMixed; ++c) offsets[c + 1] += offsets[c];
  if (!members.resize(offsets[nMixed])) return detail::oom(kStepArrays);
  {
    Array<uint32_t> fill;
    if (!fill.resize(nMixed)) return detail::oom(kStepArrays);
    for (uint32_t c = 0; c < nMixed; ++c) fill[c] = offsets[c];
    for (uint32_t t = 0; t < nt; ++t) {
      const uint32_t c = slot[parent[t]];
      if (c != kInvalid) members[fill[c]++] = t;
    }
  }
  for (uint32_t c = 0; c < nMixed; ++c) {
    const uint32_t seed = members[offsets[c]];
    const bool conflict = flags[seed] & kConflict;
    const uint32_t n = offsets[c + 1] - offsets[c], n1 = count1[c], n0 = n - n1;
    // Flip the smaller side; on a tie, the side without the component's lowest triangle
    // (whose parity is 0).
    const uint8_t flipParity = n1 < n0 ? 1 : n0 < n1 ? 0 : 1;
    std::vector<uint32_t> flip;
    if (!conflict) {
      STLTOPO_TRY {
        for (uint32_t i = offsets[c]; i < offsets[c + 1]; ++i)
          if (rel[members[i]] == flipParity) flip.push_back(members[i]);
      }
      STLTOPO_CATCH { return detail::oom(kStepArrays); }
    }
    const uint32_t kept = n - uint32_t(flip.size());
    ctx.begin(conflict ? text("orient the shell of triangle %u consistently", seed)
                       : text("flip %zu triangle%s of the shell of triangle %u to match the other %u", flip.size(),
                              flip.size() == 1 ? "" : "s", seed, kept),
              conflict ? std::vector<uint32_t>{seed} : flip);
    if (ctx.excluded()) continue;
    if (conflict) {
      ctx.skip("it cannot be oriented consistently (a non-orientable surface, such as a Moebius strip)");
      continue;
    }
    // In edits of up to kFlipChunk triangles (in increasing id, nearby on most meshes): one
    // call and one re-pairing per chunk instead of per triangle, with the edges of a chunk
    // still close together in memory.
    constexpr size_t kFlipChunk = 64;
    for (size_t i = 0; i < flip.size(); i += kFlipChunk) {
      const uint32_t n = uint32_t(std::min(kFlipChunk, flip.size() - i));
      s = em.reverseTriangles(flip.data() + i, n);
      if (!s.ok()) return s;
      // (Each triangle is in one component's list: reversed once. Without room for the
      // list, the runner compares the whole mesh instead.)
      for (uint32_t j = 0; j < n && ctx.reversedListed; ++j)
        if (!ctx.reversed.push_back(flip[i + j])) {
          ctx.reversedListed = false;
          ctx.reversed = Array<uint32_t>{};
        }
    }
  }
  // 2. Closed shells outward, or inward at odd nesting depth (a cavity stays a cavity).
  ctx.plan.note =
      !ctx.options.intersections
          ? "closed shells are oriented by volume sign only (outward): the intersection pass is off"
          : "closed shells outward, inward at odd nesting depth (a cavity stays a cavity); shells that overlap "
            "others are oriented by volume sign only";
  //    Without a closed shell there is nothing to do, and with at most one shell the
  //    editor's counts say so (every edge counts in exactly one shell, so a single shell's
  //    edge counts are the mesh's): no rebuild then.
  {
    const EditStats& st = em.stats();
    if (st.shells == 0 || (st.shells == 1 && st.boundaryEdges + st.nonManifoldEdges + st.inconsistentEdges > 0))
      return Status{};
  }
  //    The mesh now, with its shells: built where the runner rebuilds the mesh after the
  //    step (toMesh's topology equals a fresh build's, triangleShell included), which it
  //    keeps when no shell is reversed below.
  Mesh ownMesh;
  Topology ownTopo;
  const bool intoNext = ctx.next && ctx.nextTopo && ctx.maps;
  Mesh& mesh = intoNext ? *ctx.next : ownMesh;
  Topology& topo = intoNext ? *ctx.nextTopo : ownTopo;
  Array<Shell> shells;
  s = em.toMesh(mesh, &topo, intoNext ? ctx.maps : nullptr, true);
  if (s.ok()) s = findShellsAndDefects(mesh, topo, &shells, nullptr);
  if (!s.ok()) return s;
  ctx.rebuilt = intoNext;
  // The compacted ids of em's live triangles are its slot ids (the step only reversed
  // triangles, which keeps every id), so shell triangles are em's.
  uint32_t closedShells = 0;
  for (const Shell& sh : shells) closedShells += sh.closed() && sh.manifold();
  ShellNesting nesting;
  bool nested = false;
  if (ctx.options.intersections && closedShells >= 2) {
    TriangleChecks checks;
    Intersections found;
    IntersectionOptions io;
    io.maxPairs = ctx.options.maxPairs;
    io.threads = ctx.options.threads;
    s = checkTriangles(mesh, &topo, checks, ctx.options.threads);
    if (s.ok()) s = findIntersections(mesh, topo, checks, found, io);
    if (s.ok()) s = findShellNesting(mesh, topo, shells, found, nesting);
    if (!s.ok()) return s;
    nested = true;
  }
  for (uint32_t k = 0; k < shells.size(); ++k) {
    const Shell& sh = shells[k];
    if (!sh.closed() || !sh.manifold()) continue;
    uint32_t depth = nested ? nesting.depth[k] : kInvalid;
    const bool inward = depth != kInvalid && (depth & 1u);
    if (sh.volumeSign == 0 || (sh.volumeSign < 0) == inward) continue;
    std::vector<uint32_t> tris;
    STLTOPO_TRY {
      for (uint32_t t = 0; t < mesh.nTriangles(); ++t)
        if (topo.triangleShell[t] == k) tris.push_back(t);
    }
    STLTOPO_CATCH { return detail::oom(kStepArrays); }
    std::string why = depth == kInvalid ? (nested ? "it overlaps another shell; by volume sign" : "by volume sign")
                                        : text("at nesting depth %u", depth);
    ctx.begin(text("reverse shell %u (%u triangles): it faces %s, should face %s (%s)", k, sh.triangles,
                   sh.volumeSign < 0 ? "inward" : "outward", inward ? "inward" : "outward", why.c_str()),
              std::move(tris));
    if (ctx.excluded()) continue;
    ctx.rebuilt = false;  // the mesh changes after the rebuild
    ctx.reversedListed = false;
    s = em.reverseShell(sh.firstTriangle);
    if (!s.ok()) return s;
  }
  return Status{};
}

// ============================================================================ small shells

Status runSmallShells(StepContext& ctx) {
  Mesh mesh;
  Topology topo;
  Array<Shell> shells;
  Status s = shellsNow(ctx.em, mesh, topo, shells, ctx.options.threads);
  if (!s.ok()) return s;
  const RepairOptions& o = ctx.options;
  ctx.plan.note = text("removes shells of fewer than %u triangles", o.minShellTriangles);
  if (o.minShellVolume > 0) ctx.plan.note += text(" or less than %g volume", o.minShellVolume);
  ctx.plan.note += "; the largest shell always stays";
  uint32_t largest = kInvalid;
  for (uint32_t k = 0; k < shells.size(); ++k)
    if (largest == kInvalid || shells[k].triangles > shells[largest].triangles) largest = k;
  Array<uint32_t> offsets, members;
  if (!offsets.assign(shells.size() + 1, 0)) return detail::oom(kStepArrays);
  for (uint32_t t = 0; t < mesh.nTriangles(); ++t)
    if (topo.triangleShell[t] != kInvalid) ++offsets[topo.triangleShell[t] + 1];
  for (size_t k = 0; k < shells.size(); ++k) offsets[k + 1] += offsets[k];
  if (!members.resize(offsets[shells.size()])) return detail::oom(kStepArrays);
  {
    Array<uint32_t> fill;
    if (!fill.resize(shells.size())) return detail::oom(kStepArrays);
    for (size_t k = 0; k < shells.size(); ++k) fill[k] = offsets[k];
    for (uint32_t t = 0; t < mesh.nTriangles(); ++t)
      if (topo.triangleShell[t] != kInvalid) members[fill[topo.triangleShell[t]]++] = t;
  }
  for (uint32_t k = 0; k < shells.size(); ++k) {
    const Shell& sh = shells[k];
    const bool fewTriangles = sh.triangles < o.minShellTriangles;
    const bool smallVolume = o.minShellVolume > 0 && std::fabs(sh.volume) < o.minShellVolume;
    if (!fewTriangles && !smallVolume) continue;
    std::vector<uint32_t> tris;
    STLTOPO_TRY { tris.assign(members.data() + offsets[k], members.data() + offsets[k + 1]); }
    STLTOPO_CATCH { return detail::oom(kStepArrays); }
    ctx.begin(text("remove shell %u (%u triangles, volume %g)", k, sh.triangles, sh.volume), std::move(tris));
    if (ctx.excluded()) continue;
    if (k == largest) {
      ctx.skip("it is the largest shell");
      continue;
    }
    for (uint32_t i = offsets[k]; i < offsets[k + 1]; ++i) {
      s = ctx.em.removeTriangle(members[i]);
      if (!s.ok()) return s;
    }
  }
  return Status{};
}

}  // namespace repair_detail
}  // namespace stltopo
