// The cheap geometric checks every report has (stltopo/geometry.h, checkTriangles):
// zero-area triangles and duplicate groups. Its own file, so that the wasm core module links
// it (the report) without the intersection pass.
#include <cstring>

#include "geometry_detail.h"
#include "parallel.h"
#include "predicates.h"
#include "prefetch.h"
#include "stltopo/geometry.h"

namespace stltopo {
using geometry_detail::checkWeld;
using geometry_detail::oom;
using geometry_detail::Welded;
using geometry_detail::weldOf;

namespace {

uint64_t mix(uint64_t x) {
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdull;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ull;
  x ^= x >> 33;
  return x;
}

void sort3(uint32_t& a, uint32_t& b, uint32_t& c) {
  if (a > b) std::swap(a, b);
  if (b > c) std::swap(b, c);
  if (a > b) std::swap(a, b);
}

// Whether (a, b, c) is a rotation of (x, y, z) (same set assumed).
bool sameWinding(uint32_t a, uint32_t b, uint32_t c, uint32_t x, uint32_t y, uint32_t z) {
  return (a == x && b == y && c == z) || (a == y && b == z && c == x) || (a == z && b == x && c == y);
}

}  // namespace

const char* duplicateOrientationName(DuplicateOrientation o) {
  switch (o) {
    case DuplicateOrientation::Same: return "same";
    case DuplicateOrientation::Opposite: return "opposite";
    case DuplicateOrientation::Mixed: return "mixed";
  }
  return "unknown";
}

// ---------------------------------------------------------------------------
// Zero-area and duplicate triangles.

// What the topology says of t's duplicates, from e, t's side corner0 -> corner1 (kInvalid for
// a degenerate t): a duplicate of t has that side too. When its edge is a boundary edge, t has
// none; when it is interior (exactly two opposite sides), its only other triangle is the one
// across, a duplicate of t exactly when its third corner is t's (ThirdCorner: compare it, see
// sideAcross); only a cut edge (more sides) leaves the question open (Maybe).
namespace {
enum class DuplicateTest : uint8_t { None, Maybe, ThirdCorner };
// duplicateTestOf and sideAcrossOf: on the raw arrays, for the wasm pass below.
inline DuplicateTest duplicateTestOf(const uint8_t* pairKind, uint32_t e) {
  if (e == kInvalid) return DuplicateTest::None;
  switch (EdgeKind(pairKind[e >> 1])) {
    case EdgeKind::Boundary: return DuplicateTest::None;
    case EdgeKind::Interior: return DuplicateTest::ThirdCorner;
    default: return DuplicateTest::Maybe;
  }
}
inline DuplicateTest duplicateTest(const Topology& topo, uint32_t e) { return duplicateTestOf(topo.pairKind.data(), e); }
// The other triangle's side leaving e's origin: it runs to that triangle's third corner.
inline uint32_t sideAcrossOf(const uint32_t* next, uint32_t e) { return next[e ^ 1u] ^ 1u; }
inline uint32_t sideAcross(const Topology& topo, uint32_t e) { return sideAcrossOf(topo.next.data(), e); }
}  // namespace

bool canHaveDuplicate(const Topology& topo, uint32_t t, uint32_t thirdCorner) {
  const uint32_t e = topo.triangleHalfedge[t];
  switch (duplicateTest(topo, e)) {
    case DuplicateTest::None: return false;
    case DuplicateTest::ThirdCorner: return topo.vert[sideAcross(topo, e)] == thirdCorner;
    default: return true;
  }
}

Status checkTriangles(const Mesh& mesh, const Topology* topo, TriangleChecks& out) {
  return checkTriangles(mesh, topo, out, 1);
}

namespace {

// The candidates for a duplicate group without a topology, in triangle order: the
// non-degenerate triangles whose corner set another one may share. Every such triangle
// would do, but a table of them all costs 16-24 B a triangle and a random probe each (79 ms
// of the 1M-triangle torus natively, more than its read; bench/PROFILE.md, *Stop 50*). So a
// sieve first: a corner set's hash picks an entry of 2 bits (seen, seen again) among at
// least 8 a triangle; one pass marks each triangle's entry, a second lists the triangles
// whose entry was marked twice. Triangles with the same corner set share their entry, so
// none of a duplicate group is left out; a triangle that merely shares its entry (about 1 in
// 8 to 16) goes on to the exact table, which tells them apart.
Status sieveCandidates(const Welded& w, uint32_t nt, Array<uint32_t>& cand) {
  unsigned bits = 6;
  while ((size_t(1) << bits) < 8 * size_t(nt) && bits < 32) ++bits;
  Array<uint32_t> state;  // entry i: bits 2 (i % 16) (seen) and 2 (i % 16) + 1 (seen again) of word i / 16
  if (!state.assign((size_t(1) << bits) / 16, 0)) return oom("the duplicate sieve");
  uint32_t marked = 0, n = 0;  // marked: the marks on an entry already seen
  for (int pass = 0; pass < 2; ++pass) {
    // Each mark on a seen entry adds one triangle to the list, and each entry marked again the
    // one that first marked it: at most 2 * marked.
    if (pass == 1 && !cand.resize(2 * size_t(marked))) return oom("the duplicate candidates");
    for (uint32_t t = 0; t < nt && (pass == 0 || marked); ++t) {
      const uint32_t* corner = w.mesh.triangles.data() + 3 * size_t(t);
      uint32_t a = corner[0], b = corner[1], c = corner[2];
      if (w.weld) {
        a = w.weld[a];
        b = w.weld[b];
        c = w.weld[c];
      }
      if (a == b || b == c || a == c) continue;  // degenerate
      // The corner set's hash, without branches (the corners are in no order a branch could
      // predict) or calls (wasm's -Oz keeps even std::min out of line): a multiplicative
      // hash of the sorted corners, read in its high bits.
      const uint32_t lo0 = a < b ? a : b, hi0 = a < b ? b : a;
      const uint32_t lo = lo0 < c ? lo0 : c, hi = hi0 > c ? hi0 : c, mid = a ^ b ^ c ^ lo ^ hi;
      const uint64_t k = 0x9e3779b97f4a7c15ull;
      const uint64_t h = (((uint64_t(lo) << 32 | mid) * k) ^ hi) * k;
      const uint32_t i = uint32_t(h >> (64 - bits)), shift = 2 * (i % 16);
      uint32_t& word = state[i / 16];
      if (pass == 0) {
        const uint32_t seen = (word >> shift) & 1;
        marked += seen;
        word |= (seen + 1) << shift;  // seen, or seen again
      } else if (word >> shift & 2) {
        cand[n++] = t;
      }
    }
  }
  (void)cand.resize(n);  // smaller
  return {};
}

// checkTriangles; with kChunked, its pass over the triangles in chunks (detail::forChunks: for
// the full wasm module's intersection pass, detail::checkTrianglesInChunks; a separate
// instantiation, so that the core module holds only the one-call code).
template <bool kChunked>
Status checkTrianglesIn(const Mesh& mesh, const Topology* topo, TriangleChecks& out, unsigned threads) {
  out = TriangleChecks{};
  if (Status s = checkWeld(mesh, topo); !s.ok()) return s;
  const Welded w{mesh, weldOf(topo)};
  const uint32_t nt = mesh.nTriangles();
  const bool useTopology = topo && topo->triangleHalfedge.size() == nt && !topo->next.empty() && !topo->vert.empty();
  // Pass 1: zero-area triangles, and with a topology the candidates for a duplicate group:
  // the triangles it cannot rule out, none in a clean mesh (without one, the sieve after this
  // pass lists them). Threaded: each part lists a range of triangles, and the lists are joined
  // in range order.
  Array<uint32_t> cand;
  auto pass1 = [&](uint32_t t0, uint32_t t1, Array<uint32_t>& zeroArea, Array<uint32_t>& candidates) __attribute__((flatten)) -> Status {
#if defined(__EMSCRIPTEN__)
    // wasm has no prefetch, and its touches are loads that the loop waits on: in a file in
    // spatial order they made this pass take 1.7x its time (bench/PROFILE.md, *Stop 42*). In
    // blocks instead: first canHaveDuplicate's reads for the block, in two runs of independent
    // loads (the edge's kind and the side across, then for an interior edge the third corner
    // of the triangle across), whose misses overlap in a scattered file; then the tests.
    // On raw pointers: at -Oz (this file's level in wasm) the arrays' accessors (operator[],
    // data()) stayed calls in this loop, `flatten` notwithstanding (it inlines the lambda's own
    // calls, not theirs); -O3 for the file cost 0.8 kB gzipped of the core module. The report
    // of the 1M and 4M tori took 0.72-0.89x its time (bench/PROFILE.md, *Stop 60*).
    constexpr uint32_t kBlock = 64;
    uint32_t across[kBlock];
    DuplicateTest test[kBlock];  // canHaveDuplicate's, across[i] the third corner across
    const uint32_t* tri = mesh.triangles.data();
    const uint32_t* weld = w.weld;
    const float* xyz = mesh.positions.data();
    const uint32_t* firstSide = useTopology ? topo->triangleHalfedge.data() : nullptr;
    const uint8_t* kind = useTopology ? topo->pairKind.data() : nullptr;
    const uint32_t* next = useTopology ? topo->next.data() : nullptr;
    const uint32_t* vert = useTopology ? topo->vert.data() : nullptr;
    for (uint32_t b0 = t0; b0 < t1; b0 += kBlock) {
      const uint32_t m = t1 - b0 < kBlock ? t1 - b0 : kBlock;
      if (useTopology) {
        for (uint32_t i = 0; i < m; ++i) {
          const uint32_t e = firstSide[b0 + i];
          test[i] = duplicateTestOf(kind, e);
          across[i] = e == kInvalid ? 0 : sideAcrossOf(next, e);
        }
        for (uint32_t i = 0; i < m; ++i)
          if (test[i] == DuplicateTest::ThirdCorner) across[i] = vert[across[i]];
      }
      for (uint32_t i = 0; i < m; ++i) {
        const uint32_t t = b0 + i;
        uint32_t a = tri[3 * size_t(t)], b = tri[3 * size_t(t) + 1], c = tri[3 * size_t(t) + 2];
        if (weld) {
          a = weld[a];
          b = weld[b];
          c = weld[c];
        }
        if (a == b || b == c || a == c) continue;  // degenerate
        if (pred::collinear(xyz + 3 * size_t(a), xyz + 3 * size_t(b), xyz + 3 * size_t(c)) && !zeroArea.push_back(t))
          return oom("the zero-area list");
        const bool maybe = useTopology && (test[i] == DuplicateTest::Maybe ||
                                           (test[i] == DuplicateTest::ThirdCorner && across[i] == c));
        if (maybe && !candidates.push_back(t)) return oom("the duplicate candidates");
      }
    }
    return {};
#else
    uint32_t sink = 0;
    for (uint32_t t = t0; t < t1; ++t) {
      // The corners (and the edge canHaveDuplicate reads) of a triangle a few ahead: in a
      // file whose triangles are not in spatial order, these reads miss the cache.
      // canHaveDuplicate's reads are a chain of two: the first link 2 * kAhead ahead.
      for (auto [u, ue] = detail::aheadOf(t, t0, t1, detail::kAhead); u < ue; ++u) {
        for (int i = 0; i < 3; ++i) detail::touch(w.p(w.v(u, i)), sink);
        if (useTopology) {
          const uint32_t e = topo->triangleHalfedge[u];
          if (e != kInvalid) detail::touch(&topo->vert[sideAcross(*topo, e)], sink);
        }
      }
      if (useTopology)
        for (auto [u, ue] = detail::aheadOf(t, t0, t1, 2 * detail::kAhead); u < ue; ++u) {
          const uint32_t e = topo->triangleHalfedge[u];
          if (e != kInvalid) {
            detail::touch(&topo->pairKind[e >> 1], sink);
            detail::touch(&topo->next[e ^ 1u], sink);
          }
        }
      const uint32_t a = w.v(t, 0), b = w.v(t, 1), c = w.v(t, 2);
      if (a == b || b == c || a == c) continue;  // degenerate
      if (pred::collinear(w.p(a), w.p(b), w.p(c)) && !zeroArea.push_back(t)) return oom("the zero-area list");
      if (useTopology && canHaveDuplicate(*topo, t, c) && !candidates.push_back(t))
        return oom("the duplicate candidates");
    }
    detail::keepAlive(sink);
    return {};
#endif
  };
  const unsigned n = detail::partsFor(detail::threadCount(threads), nt, detail::parallelGrain(65536));
  if (n <= 1) {
    Status s;
    // (Not detail::forChunksIf: compiled at -Oz in wasm, as this file is, the one-call
    // version keeps its lambda out of line, 75 B gzipped more in the core module.)
    if constexpr (kChunked) {
      detail::forChunks(0, nt, [&](size_t t0, size_t t1) {
        if (s.ok()) s = pass1(uint32_t(t0), uint32_t(t1), out.zeroArea, cand);
      });
    } else {
      s = pass1(0, nt, out.zeroArea, cand);
    }
    if (!s.ok()) return s;
  } else {
    struct PartLists {
      Array<uint32_t> zeroArea, cand;
      Status status;
    };
    PartLists lists[detail::kMaxThreads];
    detail::runParts(n, [&](unsigned part) {
      PartLists& l = lists[part];
      l.status = pass1(uint32_t(detail::partBegin(nt, n, part)), uint32_t(detail::partBegin(nt, n, part + 1)),
                       l.zeroArea, l.cand);
    });
    size_t nz = 0, ncand = 0;
    for (unsigned part = 0; part < n; ++part) {
      if (!lists[part].status.ok()) return lists[part].status;
      nz += lists[part].zeroArea.size();
      ncand += lists[part].cand.size();
    }
    if (!out.zeroArea.resize(nz)) return oom("the zero-area list");
    if (!cand.resize(ncand)) return oom("the duplicate candidates");
    nz = ncand = 0;
    for (unsigned part = 0; part < n; ++part) {
      const PartLists& l = lists[part];
      if (l.zeroArea.size())
        std::memcpy(out.zeroArea.data() + nz, l.zeroArea.data(), l.zeroArea.size() * sizeof(uint32_t));
      if (l.cand.size()) std::memcpy(cand.data() + ncand, l.cand.data(), l.cand.size() * sizeof(uint32_t));
      nz += l.zeroArea.size();
      ncand += l.cand.size();
    }
  }
  if (!useTopology)
    if (Status s = sieveCandidates(w, nt, cand); !s.ok()) return s;
  // Pass 2: the candidates into an open-addressed table keyed by their sorted corners;
  // rep[i] = the index of the lowest candidate with candidate i's corner set.
  const uint32_t nc = uint32_t(cand.size());
  Array<uint32_t> rep;
  size_t cap = 16;
  while (cap < 2 * size_t(nc)) cap *= 2;
  Array<uint32_t> table;
  if (!rep.resize(nc) || !table.assign(cap, kInvalid)) return oom("the duplicate-triangle table");
  const size_t mask = cap - 1;
  uint32_t dupMembers = 0;
  for (uint32_t i = 0; i < nc; ++i) {
    uint32_t a = w.v(cand[i], 0), b = w.v(cand[i], 1), c = w.v(cand[i], 2);
    sort3(a, b, c);
    size_t h = mix((uint64_t(a) << 32 | b) ^ mix(c)) & mask;
    for (;; h = (h + 1) & mask) {
      const uint32_t u = table[h];
      if (u == kInvalid) {
        table[h] = i;
        rep[i] = i;
        break;
      }
      uint32_t x = w.v(cand[u], 0), y = w.v(cand[u], 1), z = w.v(cand[u], 2);
      sort3(x, y, z);
      if (x == a && y == b && z == c) {
        rep[i] = u;
        ++dupMembers;
        break;
      }
    }
  }
  table.release();
  if (dupMembers == 0) {
    if (!out.duplicateOffsets.push_back(0)) return oom("the duplicate groups");
    return {};
  }
  // Pass 3: the groups, ordered by their lowest triangle (= rep), members ascending.
  Array<uint32_t> slot;  // per representative that has other members: its group
  if (!slot.assign(nc, kInvalid)) return oom("the duplicate groups");
  constexpr uint32_t kHasMembers = kInvalid - 1;
  for (uint32_t i = 0; i < nc; ++i)
    if (rep[i] != i) slot[rep[i]] = kHasMembers;
  uint32_t groups = 0;
  for (uint32_t i = 0; i < nc; ++i)
    if (slot[i] == kHasMembers) slot[i] = groups++;
  Array<uint32_t>& offsets = out.duplicateOffsets;
  if (!offsets.assign(size_t(groups) + 1, 0) || !out.duplicateTriangles.resize(size_t(groups) + dupMembers) ||
      !out.duplicateOrientation.assign(groups, uint8_t(DuplicateOrientation::Same)))
    return oom("the duplicate groups");
  for (uint32_t i = 0; i < nc; ++i)
    if (slot[rep[i]] != kInvalid) ++offsets[slot[rep[i]] + 1];
  for (uint32_t g = 0; g < groups; ++g) offsets[g + 1] += offsets[g];
  Array<uint32_t> fill;
  if (!fill.resize(groups)) return oom("the duplicate groups");
  for (uint32_t g = 0; g < groups; ++g) fill[g] = offsets[g];
  for (uint32_t i = 0; i < nc; ++i) {
    if (slot[rep[i]] == kInvalid) continue;
    const uint32_t g = slot[rep[i]], t = cand[i], r = cand[rep[i]];
    out.duplicateTriangles[fill[g]++] = t;
    if (!sameWinding(w.v(t, 0), w.v(t, 1), w.v(t, 2), w.v(r, 0), w.v(r, 1), w.v(r, 2)))
      out.duplicateOrientation[g] = uint8_t(DuplicateOrientation::Opposite);
  }
  for (uint32_t g = 0; g < groups; ++g)
    if (out.duplicateOrientation[g] != uint8_t(DuplicateOrientation::Same) && offsets[g + 1] - offsets[g] > 2)
      out.duplicateOrientation[g] = uint8_t(DuplicateOrientation::Mixed);
  out.nDuplicateTriangles = dupMembers;
  return {};
}

}  // namespace

Status checkTriangles(const Mesh& mesh, const Topology* topo, TriangleChecks& out, unsigned threads) {
#if !defined(__EMSCRIPTEN__)
  // (the tests' chunk size runs the chunked pass natively: setChunkItemsForTesting)
  if (detail::chunkItemsForTesting() > 0) return checkTrianglesIn<true>(mesh, topo, out, threads);
#endif
  return checkTrianglesIn<false>(mesh, topo, out, threads);
}

namespace detail {
Status checkTrianglesInChunks(const Mesh& mesh, const Topology* topo, TriangleChecks& out, unsigned threads) {
  return checkTrianglesIn<true>(mesh, topo, out, threads);
}
}  // namespace detail

}  // namespace stltopo
