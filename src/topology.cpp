// buildTopology: the half-edge topology of a welded mesh, as a sequence of passes.
//
//   weldCorners       vertexWeld and the corner vertices the topology sees
//   groupSidesByEdge  degenerate flags; the sides bucketed by undirected edge (CSR)
//   pairSides         partner words, edge kinds and counts; triangle unions (shells)
//   numberShells      nShells and (TopologyOptions::triangleShell) triangleShell from the
//                     union-find
//   numberHalfedges   half-edge ids in file order; next, prev, vert, face, pairKind,
//                     triangleHalfedge; the boundary half-edges; per-vertex records
//   linkBoundaryLoops next of the boundary half-edges by the fan rule
//   labelLoops        loops, their listing, perimeter, seam flag; nHoles, nSeams
//   classifyVertices  vertexHalfedge, vertexNonManifold, nUsedVertices
//
// Each pass states what it needs and what it leaves. Terms: side s = 3t + c runs from
// corner c of triangle t to corner (c + 1) % 3; a live side belongs to a non-degenerate
// triangle; file order is the order of side ids.
#include <algorithm>
#include <cmath>

#include "parallel.h"
#include "prefetch.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"
#include "try_alloc.h"
#include "weld_tolerance.h"

namespace stltopo {
namespace {

Status fail(Code c, const char* msg) { return Status::error(c, msg); }
// What out-of-memory says could not be allocated.
constexpr const char* kArrays = "the topology arrays";

// "No partner": the 30-bit side field of a partner word when the side is unpaired.
constexpr uint32_t kNone = 0x3FFFFFFFu;

// A partner word, one per side while the topology is built: tag << 30 | payload.
//   paired(kind, later)  the earlier side of a pair: tag = the pair's EdgeKind (Interior or
//                        NonManifold), payload = the later side
//   unpaired(kind)       a side without partner: tag = Boundary, Inconsistent or
//                        NonManifold, payload = kNone
//   later(kind)          the later side of a pair until its partner is numbered: payload
//                        kLater (no side or pair id: both are < kNone - 1, as 3 nt < kNone)
//   pushed(k)            the later side of a pair, after its partner was numbered: payload
//                        = the pair id k. Tag kPushedTag with a payload other than kNone
//                        (the tag value is Boundary's, which is otherwise only ever
//                        stored with kNone).
namespace partner {
constexpr uint32_t kLater = kNone - 1;
constexpr uint32_t kPushedTag = uint32_t(EdgeKind::Boundary);
constexpr uint32_t paired(EdgeKind kind, uint32_t later) { return (uint32_t(kind) << 30) | later; }
constexpr uint32_t unpaired(EdgeKind kind) { return (uint32_t(kind) << 30) | kNone; }
constexpr uint32_t pushed(uint32_t pairId) { return (kPushedTag << 30) | pairId; }
constexpr uint32_t tag(uint32_t w) { return w >> 30; }
constexpr uint32_t payload(uint32_t w) { return w & kNone; }
constexpr bool isPushed(uint32_t w) { return tag(w) == kPushedTag && payload(w) != kNone; }
constexpr uint32_t later(EdgeKind kind) { return (uint32_t(kind) << 30) | kLater; }
constexpr bool isLater(uint32_t w) { return payload(w) == kLater; }
}  // namespace partner

struct UnionFind {
  Array<uint32_t> parent;
  bool init(uint32_t n) {
    if (!parent.resize(n)) return false;
    for (uint32_t i = 0; i < n; ++i) parent[i] = i;
    return true;
  }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b)
      parent[b] = a;
    else
      parent[a] = b;
  }

  // uniteLater queues a union; the queue is done in batches of kBatch whose parent
  // entries are loaded first (a prefetch natively; plain loads kept alive through
  // touchSink in wasm, which has no prefetch). flush() does the rest; find() is only
  // meaningful after it.
  static constexpr uint32_t kBatch = 64;
  uint32_t pending[2 * kBatch];
  uint32_t nPending = 0;
  uint32_t touchSink = 0;
  void uniteLater(uint32_t a, uint32_t b) {
    pending[2 * nPending] = a;
    pending[2 * nPending + 1] = b;
    if (++nPending == kBatch) flush();
  }
  void flush() {
    const uint32_t* p = parent.data();
#if defined(__EMSCRIPTEN__)
    uint32_t acc = 0;
    for (uint32_t i = 0; i < 2 * nPending; ++i) acc |= p[pending[i]];
    touchSink += acc;
#else
    for (uint32_t i = 0; i < 2 * nPending; ++i) __builtin_prefetch(p + pending[i]);
#endif
    for (uint32_t i = 0; i < nPending; ++i) unite(pending[2 * i], pending[2 * i + 1]);
    nPending = 0;
  }
};

// The arrays one pass leaves for the next; each is released by the last pass that reads it.
struct Work {
  const uint32_t* C = nullptr;  // corner vertices as the topology sees them (3 per triangle)
  Array<uint32_t> remapped;     // their storage for a tolerance weld (else C = the mesh's)
  uint32_t nLive = 0;           // live sides
  Array<uint32_t> offsets;      // nv + 1: the CSR of edge keys by smaller vertex
  Array<uint64_t> keys;         // nLive: larger vertex << 31 | side << 1 | runs-low-to-high
  Array<uint32_t> partner;      // 3 nt partner words
  UnionFind uf;                 // over the triangles
  uint32_t nCouples = 0;        // pairs of two sides
  Array<uint32_t> boundary;     // the boundary-loop half-edges, increasing
  struct VertexInfo {
    uint32_t he, deg;  // chosen outgoing half-edge (kBoundaryBit: a boundary one), out-degree
  };
  Array<VertexInfo> vinfo;     // nv
  Array<uint64_t> unlabelled;  // a bit per half-edge: boundary-loop half-edge without loop yet
};

constexpr uint32_t kBoundaryBit = 0x80000000u;  // half-edge ids are < 2^31 (sides < 2^30)

inline uint32_t dstSide(uint32_t s) { return s % 3 == 2 ? s - 2 : s + 1; }

// Pass weldCorners. Leaves out.vertexWeld (the identity for the exact weld, else the
// tolerance weld's representatives), out.nWeldedVertices and w.C, the corner vertices
// through vertexWeld. Every later pass sees only w.C: welded vertices are one vertex.
Status weldCorners(const Mesh& mesh, const TopologyOptions& options, Topology& out, Work& w) {
  const uint32_t nt = mesh.nTriangles(), nv = mesh.nVertices();
  const uint32_t* tri = mesh.triangles.data();
  w.C = tri;
  if (!(options.tolerance > 0)) {
    if (!out.vertexWeld.resize(nv)) return detail::oom(kArrays);
    for (uint32_t v = 0; v < nv; ++v) out.vertexWeld[v] = v;
    out.nWeldedVertices = nv;
    return Status{};
  }
  uint32_t nReps = detail::toleranceWeld(mesh, options.tolerance, out.vertexWeld);
  if (nReps == kInvalid) return detail::oom(kArrays);
  out.nWeldedVertices = nReps;
  if (!w.remapped.resize(size_t(nt) * 3)) return detail::oom(kArrays);
  for (size_t i = 0; i < size_t(nt) * 3; ++i) w.remapped[i] = out.vertexWeld[tri[i]];
  w.C = w.remapped.data();
  return Status{};
}

// Pass groupSidesByEdge. Needs w.C. Leaves out.triangleDegenerate (two corners on one
// vertex), out.nDegenerate, w.nLive and the CSR w.offsets/w.keys: the live sides bucketed
// by their smaller vertex, entry (larger vertex << 31 | side << 1 | runs-low-to-high), in
// file order within a bucket. Sorting a bucket thus groups its undirected edges with their
// sides in file order.
template <bool kChunked>
Status groupSidesByEdge(uint32_t nt, uint32_t nv, unsigned threads, Topology& out, Work& w) {
  const uint32_t* C = w.C;
  if (!out.triangleDegenerate.resize(nt) || !w.offsets.assign(size_t(nv) + 1, 0)) return detail::oom(kArrays);
  uint8_t* degen = out.triangleDegenerate.data();
  Array<uint32_t>& offsets = w.offsets;
  // Threaded: each part takes a range of triangles, counts its sides per bucket in an array
  // of its own, and then puts them at its own cursors: a bucket holds part 0's sides, then
  // part 1's, and so on, each in file order, which is the file order of the one-part pass.
  // A part's array is 4 B a vertex: when one cannot be allocated, the pass runs in as many
  // parts as got theirs (on one part, the one-part pass below), with the same result.
  unsigned n = detail::partsFor(threads, nt, detail::parallelGrain(65536));
  Array<uint32_t> counts[detail::kMaxThreads];  // per part: its sides per bucket, then its cursors
  for (unsigned part = 0; part < n && n > 1; ++part)
    if (!counts[part].assign(nv, 0)) {
      n = part;
      if (n == 1) counts[0].release();  // the one-part pass needs none
    }
  if (n > 1) {
    uint32_t live[detail::kMaxThreads] = {}, degenerate[detail::kMaxThreads] = {};
    detail::runParts(n, [&](unsigned part) {
      const uint32_t t0 = uint32_t(detail::partBegin(nt, n, part)), t1 = uint32_t(detail::partBegin(nt, n, part + 1));
      uint32_t* o = counts[part].data();
      uint32_t nLive = 0, nDegenerate = 0;
      for (uint32_t t = t0; t < t1; ++t) {
        uint32_t a = C[3 * t], b = C[3 * t + 1], c = C[3 * t + 2];
        bool d = a == b || b == c || a == c;
        degen[t] = d;
        if (d) {
          ++nDegenerate;
          continue;
        }
        ++o[std::min(a, b)];
        ++o[std::min(b, c)];
        ++o[std::min(c, a)];
        nLive += 3;
      }
      live[part] = nLive;
      degenerate[part] = nDegenerate;
    });
    uint32_t nLive = 0;
    for (unsigned part = 0; part < n; ++part) {
      nLive += live[part];
      out.nDegenerate += degenerate[part];
    }
    w.nLive = nLive;
    if (!w.keys.resize(nLive)) return detail::oom(kArrays);
    // The bucket starts and each part's cursors, by ranges of vertices: each range's total,
    // then the prefix sums from the range's start.
    uint32_t total[detail::kMaxThreads + 1] = {};
    const unsigned nr = detail::partsFor(threads, nv, detail::parallelGrain(65536));
    detail::runParts(nr, [&](unsigned range) {
      const uint32_t v0 = uint32_t(detail::partBegin(nv, nr, range)), v1 = uint32_t(detail::partBegin(nv, nr, range + 1));
      uint32_t sum = 0;
      for (unsigned part = 0; part < n; ++part) {
        const uint32_t* c = counts[part].data();
        for (uint32_t v = v0; v < v1; ++v) sum += c[v];
      }
      total[range + 1] = sum;
    });
    for (unsigned range = 0; range < nr; ++range) total[range + 1] += total[range];
    detail::runParts(nr, [&](unsigned range) {
      const uint32_t v0 = uint32_t(detail::partBegin(nv, nr, range)), v1 = uint32_t(detail::partBegin(nv, nr, range + 1));
      uint32_t* o = offsets.data();
      uint32_t at = total[range];
      for (uint32_t v = v0; v < v1; ++v) {
        o[v] = at;
        for (unsigned part = 0; part < n; ++part) {
          const uint32_t k = counts[part][v];
          counts[part][v] = at;
          at += k;
        }
      }
    });
    offsets[nv] = nLive;
    uint64_t* K = w.keys.data();
    detail::runParts(n, [&](unsigned part) {
      const uint32_t t0 = uint32_t(detail::partBegin(nt, n, part)), t1 = uint32_t(detail::partBegin(nt, n, part + 1));
      uint32_t* cur = counts[part].data();
      auto put = [K, cur](uint32_t s, uint32_t a, uint32_t b) {
        if (a < b)
          K[cur[a]++] = (uint64_t(b) << 31) | (uint64_t(s) << 1) | 1u;
        else
          K[cur[b]++] = (uint64_t(a) << 31) | (uint64_t(s) << 1);
      };
      for (uint32_t t = t0; t < t1; ++t) {
        if (degen[t]) continue;
        uint32_t a = C[3 * t], b = C[3 * t + 1], c = C[3 * t + 2];
        put(3 * t, a, b);
        put(3 * t + 1, b, c);
        put(3 * t + 2, c, a);
      }
    });
    return Status{};
  }
  uint32_t nLive = 0, nDegenerate = 0;
  detail::forChunksIf<kChunked>(0, nt, [&](size_t t0, size_t t1) {
    uint32_t* o = offsets.data();
    uint32_t live = nLive, degenerate = nDegenerate;
    for (uint32_t t = uint32_t(t0); t < t1; ++t) {
      uint32_t a = C[3 * t], b = C[3 * t + 1], c = C[3 * t + 2];
      bool d = a == b || b == c || a == c;
      degen[t] = d;
      if (d) {
        ++degenerate;
        continue;
      }
      ++o[std::min(a, b) + 1];
      ++o[std::min(b, c) + 1];
      ++o[std::min(c, a) + 1];
      live += 3;
    }
    nLive = live;
    nDegenerate = degenerate;
  });
  out.nDegenerate += nDegenerate;
  for (uint32_t v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
  w.nLive = nLive;
  if (!w.keys.resize(nLive)) return detail::oom(kArrays);
  Array<uint32_t> cursor;
  if (!cursor.resize(nv)) return detail::oom(kArrays);
  if (nv > 0) std::memcpy(cursor.data(), offsets.data(), size_t(nv) * sizeof(uint32_t));
  detail::forChunksIf<kChunked>(0, nt, [&](size_t t0, size_t t1) {
    uint64_t* K = w.keys.data();
    uint32_t* cur = cursor.data();
    auto put = [K, cur](uint32_t s, uint32_t a, uint32_t b) {
      if (a < b)
        K[cur[a]++] = (uint64_t(b) << 31) | (uint64_t(s) << 1) | 1u;
      else
        K[cur[b]++] = (uint64_t(a) << 31) | (uint64_t(s) << 1);
    };
    for (uint32_t t = uint32_t(t0); t < t1; ++t) {
      if (degen[t]) continue;
      uint32_t a = C[3 * t], b = C[3 * t + 1], c = C[3 * t + 2];
      put(3 * t, a, b);
      put(3 * t + 1, b, c);
      put(3 * t + 2, c, a);
    }
  });
  return Status{};
}

// Pass pairSides. Needs the CSR. Sorts each bucket, then per undirected edge with m sides:
// m = 1 boundary; m = 2 interior when the sides run opposite ways, else inconsistent (both
// unpaired); m >= 3 non-manifold, where the first unpaired side pairs with the first
// unpaired side running the other way, in file order. Leaves the partner words of every
// live side (later(kind) for the later side of each pair, which numberHalfedges replaces by
// pushed(k) before it reads it), w.nCouples, the edge counts in `out`, and the unions of the triangles that
// share an edge queued or done in w.uf (flushed at the end). Frees the CSR.
// The counts of pairSides over a range of vertices.
struct PairCounts {
  uint32_t nCouples = 0, nEdges = 0, nBoundaryEdges = 0, nInconsistentEdges = 0, nNonManifoldEdges = 0;
};

// The union-find of pairSides on several threads: links by compare-and-swap (the larger
// root under the smaller, so the roots and parent[t] <= t are those of UnionFind whatever
// the order), path halving by compare-and-swap. Each thread queues its unions in batches
// whose parent entries it prefetches, as UnionFind does.
struct SharedUnionFind {
  explicit SharedUnionFind(uint32_t* p) : parent(p) {}
  uint32_t* parent;
  static constexpr uint32_t kBatch = UnionFind::kBatch;
  uint32_t pending[2 * kBatch];
  uint32_t nPending = 0;
  // The GCC/Clang atomic builtins (Emscripten's libc++ has no std::atomic_ref).
  uint32_t load(uint32_t x) const { return __atomic_load_n(parent + x, __ATOMIC_RELAXED); }
  bool swap(uint32_t x, uint32_t& expected, uint32_t desired) const {
    return __atomic_compare_exchange_n(parent + x, &expected, desired, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED);
  }
  uint32_t find(uint32_t x) const {
    for (;;) {
      uint32_t px = load(x);
      if (px == x) return x;
      uint32_t gx = load(px);
      if (gx != px) swap(x, px, gx);
      x = gx;
    }
  }
  void unite(uint32_t a, uint32_t b) const {
    for (;;) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a > b) std::swap(a, b);
      uint32_t expected = b;
      if (swap(b, expected, a)) return;
    }
  }
  void uniteLater(uint32_t a, uint32_t b) {
    pending[2 * nPending] = a;
    pending[2 * nPending + 1] = b;
    if (++nPending == kBatch) flush();
  }
  void flush() {
#if !defined(__EMSCRIPTEN__)
    for (uint32_t i = 0; i < 2 * nPending; ++i) __builtin_prefetch(parent + pending[i]);
#endif
    for (uint32_t i = 0; i < nPending; ++i) unite(pending[2 * i], pending[2 * i + 1]);
    nPending = 0;
  }
};

// pairSides over the buckets of vertices [v0, v1): sorts them, writes the partner words of
// their sides, queues the unions in `uf`, adds to `c`. False when a queue cannot grow.
// (Always inlined: GCC left it out of line once it was called from a lambda, which cost
// the topology 2% natively.)
// kMarkLater: pairSides' markLater (a template parameter: a run-time flag cost the one-thread
// pairing 10% on the 4M torus).
template <bool kMarkLater, class UF>
#if defined(__GNUC__)
__attribute__((always_inline)) inline
#endif
bool pairRange(uint32_t v0, uint32_t v1, const uint32_t* offsets, uint64_t* keys, uint32_t* P, UF& uf,
               PairCounts& counts, Array<uint32_t> (&queue)[2]) {
  PairCounts c = counts;  // a local copy: stores through P could alias `counts`
  for (uint32_t v = v0; v < v1; ++v) {
    uint64_t* k0 = keys + offsets[v];
    uint32_t k = offsets[v + 1] - offsets[v];
    if (k == 0) continue;
    if (k <= 32) {
      for (uint32_t i = 1; i < k; ++i) {
        uint64_t x = k0[i];
        uint32_t j = i;
        while (j > 0 && k0[j - 1] > x) {
          k0[j] = k0[j - 1];
          --j;
        }
        k0[j] = x;
      }
    } else {
      std::sort(k0, k0 + k);
    }
    for (uint32_t g0 = 0; g0 < k;) {
      uint32_t g1 = g0 + 1;
      while (g1 < k && (k0[g1] >> 31) == (k0[g0] >> 31)) ++g1;
      uint32_t m = g1 - g0;
      ++c.nEdges;
      auto side = [&](uint32_t i) { return uint32_t(k0[i] >> 1) & kNone; };
      auto dir = [&](uint32_t i) { return int(k0[i] & 1u); };
      uint32_t s0 = side(g0);
      for (uint32_t i = g0 + 1; i < g1; ++i) uf.uniteLater(s0 / 3, side(i) / 3);
      if (m == 1) {
        ++c.nBoundaryEdges;
        P[s0] = partner::unpaired(EdgeKind::Boundary);
      } else if (m == 2) {
        uint32_t s1 = side(g0 + 1);
        if (dir(g0) != dir(g0 + 1)) {
          P[s0] = partner::paired(EdgeKind::Interior, s1);  // s0 < s1 (a group is sorted by side)
          if constexpr (kMarkLater) P[s1] = partner::later(EdgeKind::Interior);
          ++c.nCouples;
        } else {
          ++c.nInconsistentEdges;
          P[s0] = P[s1] = partner::unpaired(EdgeKind::Inconsistent);
        }
      } else {
        ++c.nNonManifoldEdges;
        queue[0].clear();
        queue[1].clear();
        size_t head[2] = {0, 0};
        for (uint32_t i = g0; i < g1; ++i) {
          uint32_t s = side(i);
          int d = dir(i);
          P[s] = partner::unpaired(EdgeKind::NonManifold);  // until paired: then the push replaces it
          if (head[1 - d] < queue[1 - d].size()) {
            uint32_t o = queue[1 - d][head[1 - d]++];
            P[o] = partner::paired(EdgeKind::NonManifold, s);  // o < s (a group is sorted by side)
            if constexpr (kMarkLater) P[s] = partner::later(EdgeKind::NonManifold);
            ++c.nCouples;
          } else if (!queue[d].push_back(s)) {
            return false;
          }
        }
      }
      g0 = g1;
    }
  }
  counts = c;
  return true;
}

// markLater: write later(kind) into the later side of each pair, which numberHalfedges needs
// only when it runs in parts (the one-thread numbering pushes into that word before it reads it).
template <bool kChunked>
Status pairSides(uint32_t nt, uint32_t nv, unsigned threads, bool markLater, Topology& out, Work& w) {
  if (!w.partner.resize(size_t(nt) * 3) || !w.uf.init(nt)) return detail::oom(kArrays);
  UnionFind& uf = w.uf;
  const uint32_t* offsets = w.offsets.data();
  uint32_t* P = w.partner.data();
  uint64_t* keys = w.keys.data();
  // Local counters: stores through P could alias the fields of `out`.
  PairCounts c;
  // Threaded: vertex ranges (a side is in the bucket of its edge's smaller vertex, so each
  // part writes its own sides' words), the union-find shared; the counts are sums.
  const unsigned n = detail::partsFor(threads, nv, detail::parallelGrain(65536));
  if (n > 1) {
    PairCounts counts[detail::kMaxThreads];
    bool ok[detail::kMaxThreads] = {};
    // Ranges of about equal numbers of sides, not of vertices: a side is in the bucket of its
    // edge's smaller vertex, so in a file in random order the first vertices (numbered in order
    // of appearance) hold most sides (the 4M shuffled torus: 68.5% in the first half).
    const auto rangeBegin = [&](unsigned part) {
      const uint64_t want = uint64_t(offsets[nv]) * part / n;
      return part == n ? nv : uint32_t(std::lower_bound(offsets, offsets + nv, want) - offsets);
    };
    detail::runParts(n, [&](unsigned part) {
      // A non-manifold edge's unpaired sides of each direction, oldest first from head[d].
      Array<uint32_t> queue[2];
      SharedUnionFind shared(uf.parent.data());
      const uint32_t v0 = rangeBegin(part), v1 = rangeBegin(part + 1);
      ok[part] = markLater ? pairRange<true>(v0, v1, offsets, keys, P, shared, counts[part], queue)
                           : pairRange<false>(v0, v1, offsets, keys, P, shared, counts[part], queue);
      shared.flush();
    });
    for (unsigned part = 0; part < n; ++part) {
      if (!ok[part]) return detail::oom(kArrays);
      c.nCouples += counts[part].nCouples;
      c.nEdges += counts[part].nEdges;
      c.nBoundaryEdges += counts[part].nBoundaryEdges;
      c.nInconsistentEdges += counts[part].nInconsistentEdges;
      c.nNonManifoldEdges += counts[part].nNonManifoldEdges;
    }
  } else {
    // A non-manifold edge's unpaired sides of each direction, oldest first from head[d].
    Array<uint32_t> queue[2];
    bool ok = true;
    // (in chunks: vertex ranges of about kChunkItems sides each, in order)
    detail::forChunksIf<kChunked>(0, nv, [&](size_t v0, size_t v1) {
      ok = ok && (markLater ? pairRange<true>(uint32_t(v0), uint32_t(v1), offsets, keys, P, uf, c, queue)
                            : pairRange<false>(uint32_t(v0), uint32_t(v1), offsets, keys, P, uf, c, queue));
    }, detail::kChunkItems / 6);
    if (!ok) return detail::oom(kArrays);
  }
  uf.flush();
  w.nCouples = c.nCouples;
  out.nEdges = c.nEdges;
  out.nBoundaryEdges = c.nBoundaryEdges;
  out.nInconsistentEdges = c.nInconsistentEdges;
  out.nNonManifoldEdges = c.nNonManifoldEdges;
  w.keys.release();
  w.offsets.release();
  return Status{};
}

// Pass numberShells. Needs the flushed w.uf. Leaves out.nShells, the number of
// edge-connected components of the non-degenerate triangles, and when `keep`,
// out.triangleShell: per triangle its shell, the shells numbered in the order of their
// lowest triangle id, kInvalid for a degenerate triangle. The numbers are written over the
// union-find's parent array, which becomes triangleShell; without `keep` it is freed (so
// that it is gone before the half-edge arrays are allocated).
template <bool kChunked>
void numberShells(uint32_t nt, bool keep, Topology& out, Work& w) {
  const uint8_t* degen = out.triangleDegenerate.data();
  if (!keep) {
    for (uint32_t t = 0; t < nt; ++t)
      if (!degen[t] && w.uf.find(t) == t) ++out.nShells;
    w.uf.parent.release();
    return;
  }
  // unite() hangs the larger root under the smaller and find() only shortens paths, so
  // parent[t] <= t, with equality exactly for the roots (the lowest triangle of each
  // shell, and the degenerate triangles, never united). In increasing t the entries below
  // t already hold shell numbers: a non-root takes its parent's.
  uint32_t* p = w.uf.parent.data();
  uint32_t n = 0;
  detail::forChunksIf<kChunked>(0, nt, [&](size_t t0, size_t t1) {
    uint32_t m = n;
    for (uint32_t t = uint32_t(t0); t < t1; ++t) {
      if (degen[t])
        p[t] = kInvalid;
      else
        p[t] = p[t] == t ? m++ : p[p[t]];
    }
    n = m;
  });
  out.nShells = n;
  out.triangleShell = std::move(w.uf.parent);
}

// numberHalfedges on n threads, by ranges of triangles, with the same result. (A) Each range
// counts its opening sides (those whose word is not later(kind)) and its unpaired ones: a
// prefix sum gives each range its first pair id and its first place in w.boundary. (B) Each
// range numbers its opening sides in file order, as one thread does, and pushes each pair id
// into the later side's word (whose range reads words with relaxed atomics meanwhile: a word
// pushed or later is a closing side, skipped here). (C) With every word pushed, each range
// numbers its triangles' half-edges again, writes them, and gathers per vertex, in an array
// of its own, its outgoing half-edges' least (an unpaired side's twin, a boundary-loop
// half-edge, before any other: the one-thread choice, as the ids grow in file order) and its
// out-degree; (D) the arrays are merged by vertex ranges.
Status numberHalfedgesInParts(unsigned n, uint32_t nt, uint32_t nv, bool full, Topology& out, Work& w) {
  const uint32_t* C = w.C;
  const uint8_t* degen = out.triangleDegenerate.data();
  uint32_t* next = out.next.data();
  uint32_t* prev = out.prev.data();
  uint32_t* vert = out.vert.data();
  uint32_t* face = out.face.data();
  uint64_t* ubits = w.unlabelled.data();
  uint8_t* pairKind = out.pairKind.data();
  uint32_t* P = w.partner.data();
  uint32_t* bnd = w.boundary.data();
  // The vertices' choices while the ranges run: key = the boundary-loop half-edge's id, or
  // kOther | another half-edge's id, so that the least key is the one-thread choice.
  constexpr uint32_t kOther = 0x80000000u;
  // When a part's array cannot be allocated, the numbering runs in as many parts as got one
  // (part 0 writes w.vinfo): the same result on fewer threads.
  Array<Work::VertexInfo> own[detail::kMaxThreads];
  for (unsigned part = 1; part < n; ++part)
    if (!own[part].assign(nv, Work::VertexInfo{kInvalid, 0})) n = part;
  uint32_t opens[detail::kMaxThreads + 1] = {}, unpaired[detail::kMaxThreads + 1] = {};
  auto range = [&](unsigned part, uint32_t& t0, uint32_t& t1) {
    t0 = uint32_t(detail::partBegin(nt, n, part));
    t1 = uint32_t(detail::partBegin(nt, n, part + 1));
  };
  detail::runParts(n, [&](unsigned part) {  // (A)
    uint32_t t0, t1, o = 0, u = 0;
    range(part, t0, t1);
    for (uint32_t t = t0; t < t1; ++t) {
      if (degen[t]) continue;
      for (uint32_t c = 0; c < 3; ++c) {
        const uint32_t x = P[3 * t + c];
        o += !partner::isLater(x);
        u += partner::payload(x) == kNone;
      }
    }
    opens[part + 1] = o;
    unpaired[part + 1] = u;
  });
  for (unsigned part = 0; part < n; ++part) {
    opens[part + 1] += opens[part];
    unpaired[part + 1] += unpaired[part];
  }
  detail::runParts(n, [&](unsigned part) {  // (B)
    uint32_t t0, t1, k = opens[part], nb = unpaired[part];
    range(part, t0, t1);
    for (uint32_t t = t0; t < t1; ++t) {
      if (degen[t]) continue;
      for (uint32_t c = 0; c < 3; ++c) {
        const uint32_t s = 3 * t + c, x = __atomic_load_n(P + s, __ATOMIC_RELAXED), p = partner::payload(x);
        if (partner::isLater(x) || partner::isPushed(x)) continue;
        const uint32_t he = 2 * k;
        pairKind[k] = uint8_t(partner::tag(x));
        vert[he + 1] = C[dstSide(s)];
        if (p == kNone) {
          __atomic_fetch_or(ubits + ((he + 1) >> 6), uint64_t(1) << ((he + 1) & 63), __ATOMIC_RELAXED);
          bnd[nb++] = he + 1;
        } else {
#if defined(__EMSCRIPTEN__)
          // wasm's atomics are all sequentially consistent, and V8 compiles this store to
          // xchg, a full barrier per pair (7-10 ms of a 1M shuffled numbering on 2 threads,
          // bench/PROFILE.md, *Stop 43*). The ranges reading this word meanwhile skip it
          // whether they see later(kind) or pushed(k), so an aligned word's plain store does.
          *static_cast<volatile uint32_t*>(P + p) = partner::pushed(k);
#else
          __atomic_store_n(P + p, partner::pushed(k), __ATOMIC_RELAXED);
#endif
          if (full) face[he + 1] = p / 3;
        }
        ++k;
      }
    }
  });
  Work::VertexInfo* vi = w.vinfo.data();
  detail::runParts(n, [&](unsigned part) {  // (C)
    uint32_t t0, t1, k = opens[part], sink = 0;
    range(part, t0, t1);
    Work::VertexInfo* mine = part == 0 ? vi : own[part].data();
    auto choose = [mine](uint32_t v, uint32_t key) {
      if (key < mine[v].he) mine[v].he = key;
      ++mine[v].deg;
    };
    for (uint32_t t = t0; t < t1; ++t) {
      for (auto [u, ue] = detail::aheadOf(t, t0, t1, detail::kAhead); u < ue; ++u)
        for (uint32_t c = 0; c < 3; ++c) detail::touch(&mine[C[3 * size_t(u) + c]], sink);
      if (degen[t]) {
        out.triangleHalfedge[t] = kInvalid;
        continue;
      }
      uint32_t h[3];
      for (uint32_t c = 0; c < 3; ++c) {
        const uint32_t s = 3 * t + c, x = P[s];
        if (partner::isPushed(x)) {
          h[c] = 2 * partner::payload(x) + 1;
          continue;
        }
        h[c] = 2 * k++;
        if (partner::payload(x) == kNone) choose(C[dstSide(s)], h[c] + 1);
      }
      out.triangleHalfedge[t] = h[0];
      for (uint32_t c = 0; c < 3; ++c) {
        const uint32_t e = h[c], v = C[3 * t + c];
        next[e] = h[c == 2 ? 0 : c + 1];
        if (full) prev[e] = h[c == 0 ? 2 : c - 1];
        if (!(e & 1u)) {
          vert[e] = v;
          if (full) face[e] = t;
        }
        choose(v, kOther | e);
      }
    }
    detail::keepAlive(sink);
  });
  const unsigned nr = detail::partsFor(n, nv, detail::parallelGrain(65536));
  detail::runParts(nr, [&](unsigned part) {  // (D)
    const uint32_t v1 = uint32_t(detail::partBegin(nv, nr, part + 1));
    for (uint32_t v = uint32_t(detail::partBegin(nv, nr, part)); v < v1; ++v) {
      uint32_t key = vi[v].he, deg = vi[v].deg;
      for (unsigned q = 1; q < n; ++q) {
        key = std::min(key, own[q][v].he);
        deg += own[q][v].deg;
      }
      vi[v].he = key == kInvalid ? kInvalid : (key & kOther) ? key & ~kOther : key | kBoundaryBit;
      vi[v].deg = deg;
    }
  });
  w.partner.release();
  w.remapped.release();
  w.C = nullptr;
  return Status{};
}

// The most parts numberHalfedgesInParts runs in (see buildTopologyIn).
constexpr unsigned kMaxNumberParts = 4;

// Pass numberHalfedges. Needs the partner words. One pass over the live sides in file
// order: a side either opens a new pair k (half-edge 2k, pairKind[k] from its word) or, when
// its word is pushed(k), closes pair k (half-edge 2k + 1). The opening side pushes k into
// its partner's word and writes the closing half-edge's vert (its own destination) and
// face (the partner's triangle); an unpaired opening side's twin 2k + 1 is a boundary-loop
// half-edge: listed in w.boundary (increasing) and marked in w.unlabelled. Leaves next
// (triangle half-edges only), prev and face (when prevAndFace; boundary face entries
// later), vert, pairKind, triangleHalfedge (kInvalid for degenerate triangles) and
// w.vinfo: per vertex its lowest-id outgoing boundary half-edge (with kBoundaryBit), else
// its lowest-id outgoing half-edge, and its out-degree. Frees the partner words and w.C's
// storage.
// parts: the number of triangle ranges it runs in (numberHalfedgesInParts when 2 or more, after
// pairSides with markLater).
// full: in, whether to write prev and face; out, false when they could not be allocated and
// ifRoom allowed going on without them (TopologyOptions::prevAndFaceIfRoom).
template <bool kChunked>
Status numberHalfedges(uint32_t nt, uint32_t nv, bool& full, bool ifRoom, unsigned parts, Topology& out, Work& w) {
  const uint32_t nLive = w.nLive, nCouples = w.nCouples;
  const uint32_t nPairs = nLive - nCouples;
  const uint32_t nh = 2 * nPairs;
  const uint32_t nBoundarySides = nLive - 2 * nCouples;
  if (!out.next.resize(nh) || !out.vert.resize(nh) || !out.pairKind.resize(nPairs) ||
      !out.triangleHalfedge.resize(nt) || !out.vertexHalfedge.resize(nv) || !w.boundary.resize(nBoundarySides) ||
      !w.vinfo.assign(nv, Work::VertexInfo{kInvalid, 0}))
    return detail::oom(kArrays);
  if (!w.unlabelled.assign((size_t(nh) + 63) / 64, 0)) return detail::oom(kArrays);
  if (full && (!out.prev.resize(nh) || !out.face.resize(nh))) {
    if (!ifRoom) return detail::oom(kArrays);
    out.prev.release();
    out.face.release();
    full = false;
  }
  const uint32_t* C = w.C;
  const uint8_t* degen = out.triangleDegenerate.data();
  uint32_t* next = out.next.data();
  uint32_t* prev = out.prev.data();
  uint32_t* vert = out.vert.data();
  uint32_t* face = out.face.data();
  uint64_t* ubits = w.unlabelled.data();
  uint8_t* pairKind = out.pairKind.data();
  Work::VertexInfo* vi = w.vinfo.data();
  uint32_t* P = w.partner.data();
  uint32_t* bnd = w.boundary.data();
  if (parts > 1) return numberHalfedgesInParts(parts, nt, nv, full, out, w);
  uint32_t nextPair = 0, nextBoundary = 0;
  detail::forChunksIf<kChunked>(0, nt, [&](size_t t0, size_t t1) {
    uint32_t k = nextPair, nb = nextBoundary, sink = 0;
    for (uint32_t t = uint32_t(t0); t < t1; ++t) {
      // The corners' entries of a triangle a few ahead: random reads in a file whose triangles
      // are not in spatial order. (Not its partner entries: a later side's holds nothing until
      // its partner's triangle is numbered.) Not in wasm, where a touch is a load that the
      // loop waits on: without them the 1M tori took 1-7% less (bench/PROFILE.md, *Stop 42*).
#if !defined(__EMSCRIPTEN__)
      for (auto [u, ue] = detail::aheadOf(t, 0, nt, detail::kAhead); u < ue; ++u)
        for (uint32_t c = 0; c < 3; ++c) detail::touch(&vi[C[3 * size_t(u) + c]], sink);
#endif
      if (degen[t]) {
        out.triangleHalfedge[t] = kInvalid;
        continue;
      }
      uint32_t h[3];
      for (uint32_t c = 0; c < 3; ++c) {
        uint32_t s = 3 * t + c, x = P[s], p = partner::payload(x);
        if (partner::isPushed(x)) {
          h[c] = 2 * p + 1;  // closes the pair whose id its partner pushed into p
          continue;
        }
        uint32_t he = 2 * k;
        pairKind[k] = uint8_t(partner::tag(x));
        uint32_t v = C[dstSide(s)];
        vert[he + 1] = v;
        if (p == kNone) {
          ubits[(he + 1) >> 6] |= uint64_t(1) << ((he + 1) & 63);
          bnd[nb++] = he + 1;
          if (!(vi[v].he & kBoundaryBit) || vi[v].he == kInvalid) vi[v].he = (he + 1) | kBoundaryBit;
          ++vi[v].deg;
        } else {
          P[p] = partner::pushed(k);  // p > s: a partner earlier in file order would have pushed
          if (full) face[he + 1] = p / 3;
        }
        ++k;
        h[c] = he;
      }
      out.triangleHalfedge[t] = h[0];
      for (uint32_t c = 0; c < 3; ++c) {
        uint32_t e = h[c], v = C[3 * t + c];
        next[e] = h[c == 2 ? 0 : c + 1];
        if (full) prev[e] = h[c == 0 ? 2 : c - 1];
        if (!(e & 1u)) {  // opening: the closing side's entries were written by its partner
          vert[e] = v;
          if (full) face[e] = t;
        }
        uint32_t cur = vi[v].he;
        if (cur == kInvalid || (!(cur & kBoundaryBit) && e < cur)) vi[v].he = e;
        ++vi[v].deg;
      }
    }
    nextPair = k;
    nextBoundary = nb;
    detail::keepAlive(sink);
  });
  w.partner.release();
  w.remapped.release();
  w.C = nullptr;
  return Status{};
}

// Whether boundary-loop half-edge e is still unlabelled (false for triangle half-edges).
inline bool isUnlabelled(const uint64_t* ubits, uint32_t e) { return ((ubits[e >> 6] >> (e & 63)) & 1u) != 0; }

// Pass linkBoundaryLoops (the fan rule). Needs next of the triangle half-edges and
// w.unlabelled. For the twin b of each unpaired side u->v: turn around u through the
// triangles (lPrev, taken as next[next[h]] of a triangle half-edge h, then across the
// paired edge) to the next unpaired side p, and set next[b] = twin(p) (and prev), which
// leaves u in the same fan. Afterwards next is a permutation of all half-edges. Returns
// invalid only if a walk does not end (a defect of the passes before).
Status linkBoundaryLoops(bool full, Topology& out, Work& w) {
  const uint32_t nh = out.nHalfedges();
  const uint32_t nBoundarySides = uint32_t(w.boundary.size());
  const uint32_t* bnd = w.boundary.data();
  const uint64_t* ubits = w.unlabelled.data();
  uint32_t* next = out.next.data();
  uint32_t* prev = out.prev.data();
  for (uint32_t i = 0; i < nBoundarySides; ++i) {
    uint32_t b = bnd[i];
    uint32_t h = b ^ 1u;
    uint32_t steps = 0;
    for (;;) {
      uint32_t p = next[next[h]];  // lPrev: h is a triangle half-edge
      if (isUnlabelled(ubits, p ^ 1u)) {
        next[b] = p ^ 1u;
        if (full) prev[p ^ 1u] = b;
        break;
      }
      h = p ^ 1u;
      if (++steps > nh) return fail(Code::Invalid, "internal error: fan walk did not end");
    }
  }
  return Status{};
}

// Pass labelLoops. Needs the whole next. Numbers the next cycles of boundary half-edges
// in order of their lowest half-edge id: loop l is face nt + l. Leaves face of the
// boundary half-edges (when prevAndFace), loopHalfedge, loopOffsets, loopHalfedges (in
// next order from loopHalfedge), loopIsSeam (a side of the loop is inconsistent or
// non-manifold), loopPerimeter (float64 sum of edge lengths), nHoles and nSeams. Frees
// w.boundary and w.unlabelled.
Status labelLoops(const Mesh& mesh, bool full, Topology& out, Work& w) {
  const uint32_t nt = out.nTriangles, nh = out.nHalfedges();
  const uint32_t nBoundarySides = uint32_t(w.boundary.size());
  const uint32_t* bnd = w.boundary.data();
  uint64_t* ubits = w.unlabelled.data();
  const uint32_t* next = out.next.data();
  const uint32_t* vert = out.vert.data();
  const uint8_t* pairKind = out.pairKind.data();
  uint32_t* face = out.face.data();
  uint32_t nLoops = 0;
  if (!out.loopOffsets.push_back(0)) return detail::oom(kArrays);
  for (uint32_t i = 0; i < nBoundarySides; ++i) {
    uint32_t e = bnd[i];
    if (!isUnlabelled(ubits, e)) continue;
    uint32_t f = nt + nLoops;
    bool seam = false;
    double perim = 0;
    uint32_t x = e, steps = 0;
    do {
      ubits[x >> 6] &= ~(uint64_t(1) << (x & 63));
      if (full) face[x] = f;
      if (!out.loopHalfedges.push_back(x)) return detail::oom(kArrays);
      if (pairKind[x >> 1] != uint8_t(EdgeKind::Boundary)) seam = true;
      const float* a = mesh.positions.data() + size_t(vert[x]) * 3;
      const float* c = mesh.positions.data() + size_t(vert[x ^ 1u]) * 3;
      double dx = double(a[0]) - c[0], dy = double(a[1]) - c[1], dz = double(a[2]) - c[2];
      perim += std::sqrt(dx * dx + dy * dy + dz * dz);
      x = next[x];
      if (++steps > nh) return fail(Code::Invalid, "internal error: boundary loop did not close");
    } while (x != e);
    if (!out.loopHalfedge.push_back(e) || !out.loopOffsets.push_back(uint32_t(out.loopHalfedges.size())) ||
        !out.loopIsSeam.push_back(seam ? 1 : 0) || !out.loopPerimeter.push_back(perim))
      return detail::oom(kArrays);
    if (seam)
      ++out.nSeams;
    else
      ++out.nHoles;
    ++nLoops;
  }
  w.boundary.release();
  w.unlabelled.release();
  return Status{};
}

// Pass classifyVertices. Needs next and w.vinfo. A used vertex (one with an outgoing
// half-edge) is non-manifold when the vnext cycle through its chosen half-edge does not
// hold all of its outgoing half-edges (more than one cycle). Leaves vertexHalfedge (the
// chosen one, kInvalid if unused), vertexNonManifold, nUsedVertices and
// nNonManifoldVertices. Returns invalid only if a cycle does not close.
template <bool kChunked>
Status classifyVertices(uint32_t nv, unsigned threads, Topology& out, Work& w) {
  if (!out.vertexNonManifold.resize(nv)) return detail::oom(kArrays);
  const uint32_t* next = out.next.data();
  const Work::VertexInfo* vi = w.vinfo.data();
  uint32_t* vh = out.vertexHalfedge.data();
  uint8_t* nm = out.vertexNonManifold.data();
  // Vertices [v0, v1): their entries, and their counts added to usedOut and nonManifoldOut;
  // false when a cycle does not close. The counts are kept in locals: a store through nm
  // (bytes) could alias the outputs, so counting in them stored one per vertex, and on threads
  // the parts' outputs share a cache line (the 4M torus's pass took 12.5 ms on 2 threads
  // against 7 ms on one).
  auto classify = [&](uint32_t v0, uint32_t v1, uint32_t& usedOut, uint32_t& nonManifoldOut) {
    uint32_t nUsed = 0, nNonManifold = 0;
    for (uint32_t v = v0; v < v1; ++v) {
      uint32_t e0 = vi[v].he, deg = vi[v].deg;
      nm[v] = 0;
      if (e0 == kInvalid) {
        vh[v] = kInvalid;
        continue;
      }
      e0 &= ~kBoundaryBit;
      vh[v] = e0;
      ++nUsed;
      uint32_t x = e0, steps = 0;
      do {
        x = next[x ^ 1u];
        if (++steps > deg) return false;
      } while (x != e0);
      if (steps != deg) {
        nm[v] = 1;
        ++nNonManifold;
      }
    }
    usedOut += nUsed;
    nonManifoldOut += nNonManifold;
    return true;
  };
  uint32_t nUsed = 0, nNonManifold = 0;
  bool closed = true;
  // Threaded: vertex ranges, each on its own entries; the counts are sums.
  const unsigned n = detail::partsFor(threads, nv, detail::parallelGrain(65536));
  if (n <= 1) {
    detail::forChunksIf<kChunked>(0, nv, [&](size_t v0, size_t v1) {
      closed = closed && classify(uint32_t(v0), uint32_t(v1), nUsed, nNonManifold);
    });
  } else {
    uint32_t used[detail::kMaxThreads] = {}, nonManifold[detail::kMaxThreads] = {};
    bool ok[detail::kMaxThreads] = {};
    detail::runParts(n, [&](unsigned part) {
      ok[part] = classify(uint32_t(detail::partBegin(nv, n, part)), uint32_t(detail::partBegin(nv, n, part + 1)),
                          used[part], nonManifold[part]);
    });
    for (unsigned part = 0; part < n; ++part) {
      closed &= ok[part];
      nUsed += used[part];
      nNonManifold += nonManifold[part];
    }
  }
  if (!closed) return fail(Code::Invalid, "internal error: vertex loop did not close");
  out.nUsedVertices = nUsed;
  out.nNonManifoldVertices = nNonManifold;
  w.vinfo.release();
  return Status{};
}

// buildTopology; with kChunked, the loops of its passes that run once over the whole mesh
// in chunks (detail::forChunksIf: for the full wasm module, whose first load would otherwise
// run them in V8's baseline code). Only the full module calls that instantiation
// (detail::buildTopologyInChunks), so the core holds only the one-call code.
template <bool kChunked>
Status buildTopologyIn(const Mesh& mesh, Topology& out, const TopologyOptions& options) {
  out = Topology{};
  const uint32_t nt = mesh.nTriangles();
  const uint32_t nv = mesh.nVertices();
  out.nTriangles = nt;
  out.nVertices = nv;
  out.tolerance = options.tolerance > 0 ? options.tolerance : 0;
  if (uint64_t(nt) * 3 >= uint64_t(kInvalid) / 2)
    return fail(Code::TooLarge, "too many triangles for 32-bit half-edge ids");
  if (3 * nt >= kNone) return fail(Code::TooLarge, "too many triangles for the topology");
  // prev and face are only written, never read, by the passes, so they can be skipped.
  bool full = options.prevAndFace;
  const unsigned threads = detail::threadCount(options.threads);
  Work w;
  Status s;
  if (!(s = weldCorners(mesh, options, out, w)).ok()) return s;
  if (!(s = groupSidesByEdge<kChunked>(nt, nv, threads, out, w)).ok()) return s;
  // The numbering in parts (numberHalfedgesInParts): natively always; in wasm in the threaded
  // modules and in the full module's instantiation (kChunked), not in the single-threaded
  // core, which runs on one thread (about 2 kB gzipped: tests/js/modules.test.mjs).
#if defined(__EMSCRIPTEN__)
  constexpr bool kNumberInParts = kChunked || STLTOPO_THREADS;
#else
  constexpr bool kNumberInParts = true;
#endif
  // Each part after the first holds a vertex array of its own (8 B a vertex, about 4 B a
  // triangle), so the numbering runs in at most kMaxNumberParts parts whatever the threads:
  // with a part a thread, `info` of the 4M shuffled torus peaked at 71.7, 78.5, 86.9, 105.1 and
  // 134.7 B a triangle on 1, 2, 4, 8 and 16 threads (bench/PROFILE.md, *Stop 58*).
  const unsigned numberParts =
      kNumberInParts ? std::min(detail::partsFor(threads, nt, detail::parallelGrain(65536)), kMaxNumberParts) : 1;
  if (!(s = pairSides<kChunked>(nt, nv, threads, numberParts > 1, out, w)).ok()) return s;
  numberShells<kChunked>(nt, options.triangleShell, out, w);
  if (!(s = numberHalfedges<kChunked>(nt, nv, full, options.prevAndFaceIfRoom, numberParts, out, w)).ok()) return s;
  if (!(s = linkBoundaryLoops(full, out, w)).ok()) return s;
  if (!(s = labelLoops(mesh, full, out, w)).ok()) return s;
  return classifyVertices<kChunked>(nv, threads, out, w);
}

}  // namespace

Status buildTopology(const Mesh& mesh, Topology& out, const TopologyOptions& options) {
#if !defined(__EMSCRIPTEN__)
  // (the tests' chunk size runs the chunked passes natively: setChunkItemsForTesting)
  if (detail::chunkItemsForTesting() > 0) return buildTopologyIn<true>(mesh, out, options);
#endif
  return buildTopologyIn<false>(mesh, out, options);
}

namespace detail {
Status buildTopologyInChunks(const Mesh& mesh, Topology& out, const TopologyOptions& options) {
  return buildTopologyIn<true>(mesh, out, options);
}
}  // namespace detail

}  // namespace stltopo
