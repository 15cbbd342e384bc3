// Half-edge topology: pairing of triangle sides, boundary loops ("hole faces")
// built with the fan rule, vertex loops and the per-element problem flags.
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "detail.h"
#include "stltopo.h"

namespace stltopo {
namespace {

Status fail(Code c, const char* msg) { return detail::makeStatus(c, msg); }
Status oom() { return fail(Code::OutOfMemory, "could not allocate the topology arrays"); }

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
    if (a < b) parent[b] = a; else parent[a] = b;
  }

  // Unions are queued and done in batches: the batch's parent entries are loaded first
  // (a prefetch natively; in wasm, which has no prefetch instruction, plain loads in a
  // loop of their own, kept alive through touchSink), so that their cache misses overlap
  // instead of each find waiting for its own. On a shuffled file the two triangles of an
  // edge are at random places in parent[].
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

// Deterministic tolerance weld (topology only): vertices in id order; a vertex joins the
// lowest-id representative within `tol` (Euclidean, in double) found in its own or the 26
// neighbouring grid cells of size `tol`; otherwise it becomes a representative itself.
bool toleranceWeld(const Mesh& mesh, double tol, Array<uint32_t>& rep) {
  uint32_t nv = mesh.nVertices();
  if (!rep.resize(nv)) return false;
  auto cellOf = [&](double x) -> int64_t {
    double c = std::floor(x / tol);
    if (std::fabs(c) <= 0x1p40) return int64_t(c);
    // Far from the origin in units of tol (or tol tiny): the float spacing at x exceeds
    // tol, so only vertices with exactly this coordinate can be within tol. Key by the
    // value, outside the range of the regular cells, instead of clamping: a clamped cell
    // would collect every such vertex and make the search quadratic.
    int64_t k = (int64_t(1) << 42) + int64_t(detail::bitCast<uint32_t>(std::fabs(float(x))));
    return x < 0 ? -k : k;
  };
  struct Key {
    int64_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      uint64_t h = uint64_t(k.x) * 0x9E3779B97F4A7C15ull;
      h ^= uint64_t(k.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
      h ^= uint64_t(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
      return size_t(h ^ (h >> 29));
    }
  };
  Array<uint32_t> chain;  // next representative in the same cell
  if (!chain.assign(nv, kInvalid)) return false;
  std::unordered_map<Key, uint32_t, KeyHash> cells;
  const float* p = mesh.positions.data();
  double tol2 = tol * tol;
  for (uint32_t v = 0; v < nv; ++v) {
    double x = p[3 * v], y = p[3 * v + 1], z = p[3 * v + 2];
    Key k{cellOf(x), cellOf(y), cellOf(z)};
    uint32_t best = kInvalid;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = cells.find(Key{k.x + dx, k.y + dy, k.z + dz});
          if (it == cells.end()) continue;
          for (uint32_t r = it->second; r != kInvalid; r = chain[r]) {
            double ex = p[3 * r] - x, ey = p[3 * r + 1] - y, ez = p[3 * r + 2] - z;
            if (ex * ex + ey * ey + ez * ez <= tol2 && r < best) best = r;
          }
        }
    if (best != kInvalid) {
      rep[v] = best;
    } else {
      rep[v] = v;
      auto [it, inserted] = cells.try_emplace(k, v);
      if (!inserted) {
        chain[v] = it->second;
        it->second = v;
      }
    }
  }
  return true;
}

}  // namespace

Status buildTopology(const Mesh& mesh, Topology& out, const TopologyOptions& options) {
  out = Topology{};
  const uint32_t nt = mesh.nTriangles();
  const uint32_t nv = mesh.nVertices();
  out.nTriangles = nt;
  out.nVertices = nv;
  if (uint64_t(nt) * 3 >= uint64_t(kInvalid) / 2)
    return fail(Code::TooLarge, "too many triangles for 32-bit half-edge ids");
  const uint32_t* tri = mesh.triangles.data();

  // Vertex map for the topology (identity for the exact weld).
  if (options.tolerance > 0) {
    if (!toleranceWeld(mesh, options.tolerance, out.vertexWeld)) return oom();
  } else {
    if (!out.vertexWeld.resize(nv)) return oom();
    for (uint32_t v = 0; v < nv; ++v) out.vertexWeld[v] = v;
  }
  // The corner vertices as the topology sees them (remapped by the tolerance weld).
  Array<uint32_t> remapped;
  const uint32_t* C = tri;
  if (options.tolerance > 0) {
    if (!remapped.resize(size_t(nt) * 3)) return oom();
    for (size_t i = 0; i < size_t(nt) * 3; ++i) remapped[i] = out.vertexWeld[tri[i]];
    C = remapped.data();
  }

  // Side s = 3t + c runs from corner c to corner (c+1)%3.
  const uint32_t ns = 3 * nt;
  constexpr uint32_t kNone = 0x3FFFFFFFu;  // "no partner" in the 30-bit side field
  if (ns >= kNone) return fail(Code::TooLarge, "too many triangles for the topology");
  auto dstSide = [](uint32_t s) { return s % 3 == 2 ? s - 2 : s + 1; };

  // Group sides by undirected edge: a CSR over the smaller vertex whose entries are
  // (larger vertex << 31 | side << 1 | runs-low-to-high), so sorting a bucket groups its
  // edges with their sides in file order. The counting pass also flags degenerate
  // triangles (two corners on the same vertex).
  Array<uint32_t> offsets;
  Array<uint64_t> keys;
  if (!out.triangleDegenerate.resize(nt) || !offsets.assign(size_t(nv) + 1, 0)) return oom();
  uint8_t* degen = out.triangleDegenerate.data();
  uint32_t nLive = 0;
  for (uint32_t t = 0; t < nt; ++t) {
    uint32_t a = C[3 * t], b = C[3 * t + 1], c = C[3 * t + 2];
    bool d = a == b || b == c || a == c;
    degen[t] = d;
    if (d) {
      ++out.nDegenerate;
      continue;
    }
    ++offsets[std::min(a, b) + 1];
    ++offsets[std::min(b, c) + 1];
    ++offsets[std::min(c, a) + 1];
    nLive += 3;
  }
  for (uint32_t v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
  if (!keys.resize(nLive)) return oom();
  {
    Array<uint32_t> cursor;
    if (!cursor.resize(nv)) return oom();
    if (nv > 0) std::memcpy(cursor.data(), offsets.data(), size_t(nv) * sizeof(uint32_t));
    uint64_t* K = keys.data();
    auto put = [&](uint32_t s, uint32_t a, uint32_t b) {
      if (a < b) K[cursor[a]++] = (uint64_t(b) << 31) | (uint64_t(s) << 1) | 1u;
      else K[cursor[b]++] = (uint64_t(a) << 31) | (uint64_t(s) << 1);
    };
    for (uint32_t t = 0; t < nt; ++t) {
      if (degen[t]) continue;
      uint32_t a = C[3 * t], b = C[3 * t + 1], c = C[3 * t + 2];
      put(3 * t, a, b);
      put(3 * t + 1, b, c);
      put(3 * t + 2, c, a);
    }
  }

  // Pair the sides of each undirected edge, classify the edge, and unite its triangles
  // into shells. partner[s] = kind << 30 | paired side (kNone: boundary or cut). The
  // later side of a pair (in file order) needs no word here: the numbering pass writes it
  // before reading it.
  Array<uint32_t> partner;
  UnionFind uf;
  if (!partner.resize(ns) || !uf.init(nt)) return oom();
  uint32_t nCouples = 0;
  // Local counters: stores through P could alias the fields of `out`.
  uint32_t nEdges = 0, nBoundaryEdges = 0, nInconsistentEdges = 0, nNonManifoldEdges = 0;
  {
    std::vector<uint32_t> queue[2];
    uint32_t* P = partner.data();
    for (uint32_t v = 0; v < nv; ++v) {
      uint64_t* k0 = keys.data() + offsets[v];
      uint32_t k = offsets[v + 1] - offsets[v];
      if (k == 0) continue;
      if (k <= 32) {
        for (uint32_t i = 1; i < k; ++i) {
          uint64_t x = k0[i];
          uint32_t j = i;
          while (j > 0 && k0[j - 1] > x) { k0[j] = k0[j - 1]; --j; }
          k0[j] = x;
        }
      } else {
        std::sort(k0, k0 + k);
      }
      for (uint32_t g0 = 0; g0 < k;) {
        uint32_t g1 = g0 + 1;
        while (g1 < k && (k0[g1] >> 31) == (k0[g0] >> 31)) ++g1;
        uint32_t m = g1 - g0;
        ++nEdges;
        auto side = [&](uint32_t i) { return uint32_t(k0[i] >> 1) & kNone; };
        auto dir = [&](uint32_t i) { return int(k0[i] & 1u); };
        uint32_t s0 = side(g0);
        for (uint32_t i = g0 + 1; i < g1; ++i) uf.uniteLater(s0 / 3, side(i) / 3);
        if (m == 1) {
          ++nBoundaryEdges;
          P[s0] = (uint32_t(EdgeKind::Boundary) << 30) | kNone;
        } else if (m == 2) {
          uint32_t s1 = side(g0 + 1);
          if (dir(g0) != dir(g0 + 1)) {
            P[s0] = s1;  // kind Interior = 0; s0 < s1 (a group is sorted by side)
            ++nCouples;
          } else {
            ++nInconsistentEdges;
            P[s0] = P[s1] = (uint32_t(EdgeKind::Inconsistent) << 30) | kNone;
          }
        } else {
          // First unpaired with first unpaired, opposite directions, in file order.
          ++nNonManifoldEdges;
          constexpr uint32_t nm = uint32_t(EdgeKind::NonManifold) << 30;
          queue[0].clear();
          queue[1].clear();
          size_t head[2] = {0, 0};
          for (uint32_t i = g0; i < g1; ++i) {
            uint32_t s = side(i);
            int d = dir(i);
            P[s] = nm | kNone;  // until paired: then the push from o replaces it
            if (head[1 - d] < queue[1 - d].size()) {
              uint32_t o = queue[1 - d][head[1 - d]++];
              P[o] = nm | s;  // o < s (a group is sorted by side)
              ++nCouples;
            } else {
              queue[d].push_back(s);
            }
          }
        }
        g0 = g1;
      }
    }
    uf.flush();
  }
  out.nEdges = nEdges;
  out.nBoundaryEdges = nBoundaryEdges;
  out.nInconsistentEdges = nInconsistentEdges;
  out.nNonManifoldEdges = nNonManifoldEdges;
  keys.release();
  offsets.release();

  // Shells: edge-connected components of the non-degenerate triangles. Counted now, so
  // that the union-find is freed before the half-edge arrays are allocated.
  for (uint32_t t = 0; t < nt; ++t)
    if (!degen[t] && uf.find(t) == t) ++out.nShells;
  uf.parent.release();

  // One pass in file order numbers the pairs and writes the triangle half-edges. A side
  // either opens a new pair (even id 2k) or closes the pair its earlier partner opened
  // (odd id 2k+1). The opening side pushes k into its partner's partner[] word (marked with
  // the Boundary kind, which is otherwise only stored with kNone), so the closing side
  // finds its id in its own word, read in order, instead of reading its partner's word at a
  // random place. The opening side also writes what it knows of the closing half-edge:
  // vert (its own destination) and face (its partner's triangle), next to its own entries,
  // so the closing side writes only next and prev at the random place of its id. The twin
  // of an unpaired side is a boundary-loop half-edge (listed in `boundary`, in increasing
  // id order). The same pass picks each vertex's outgoing half-edge (bit 31 marks a
  // boundary one, which wins over any triangle half-edge) and counts its outgoing
  // half-edges.
  const uint32_t nPairs = nLive - nCouples;
  const uint32_t nh = 2 * nPairs;
  const uint32_t nBoundarySides = nLive - 2 * nCouples;
  // Per vertex while building: the chosen outgoing half-edge and the out-degree, side by
  // side so that one cache line serves both.
  struct VertexInfo {
    uint32_t he, deg;
  };
  // A bit per half-edge marks the boundary-loop half-edges not labelled with their loop
  // yet; the fan walk takes lPrev of a triangle half-edge as next[next[e]]. So prev and
  // face are only written, never read, and options.prevAndFace = false can skip them.
  const bool full = options.prevAndFace;
  Array<uint32_t> boundary;
  Array<VertexInfo> vinfo;
  Array<uint64_t> unlabelled;
  if (!out.next.resize(nh) || !out.vert.resize(nh) || !out.pairKind.resize(nPairs) ||
      !out.triangleHalfedge.resize(nt) || !out.vertexHalfedge.resize(nv) || !boundary.resize(nBoundarySides) ||
      !vinfo.assign(nv, VertexInfo{kInvalid, 0}))
    return oom();
  if (!unlabelled.assign((size_t(nh) + 63) / 64, 0) || (full && (!out.prev.resize(nh) || !out.face.resize(nh))))
    return oom();
  uint32_t* next = out.next.data();
  uint32_t* prev = out.prev.data();
  uint32_t* vert = out.vert.data();
  uint32_t* face = out.face.data();
  uint64_t* ubits = unlabelled.data();
  // Whether boundary-loop half-edge e is still unlabelled (false for triangle half-edges).
  auto isUnlabelled = [&](uint32_t e) { return ((ubits[e >> 6] >> (e & 63)) & 1u) != 0; };
  uint8_t* pairKind = out.pairKind.data();
  uint32_t* vh = out.vertexHalfedge.data();
  VertexInfo* vi = vinfo.data();
  constexpr uint32_t kBoundaryBit = 0x80000000u;  // half-edge ids are < 2^31 (ns < 2^30)
  constexpr uint32_t kPushed = uint32_t(EdgeKind::Boundary);  // partner word holding a pair id
  {
    uint32_t* P = partner.data();
    uint32_t* bnd = boundary.data();
    uint32_t k = 0, nb = 0;
    for (uint32_t t = 0; t < nt; ++t) {
      if (degen[t]) {
        out.triangleHalfedge[t] = kInvalid;
        continue;
      }
      uint32_t h[3];
      for (uint32_t c = 0; c < 3; ++c) {
        uint32_t s = 3 * t + c, x = P[s], p = x & kNone;
        if (x >> 30 == kPushed && p != kNone) {
          h[c] = 2 * p + 1;  // closes the pair whose id its partner pushed into p
          continue;
        }
        uint32_t he = 2 * k;
        pairKind[k] = uint8_t(x >> 30);
        uint32_t v = C[dstSide(s)];
        vert[he + 1] = v;
        if (p == kNone) {
          ubits[(he + 1) >> 6] |= uint64_t(1) << ((he + 1) & 63);
          bnd[nb++] = he + 1;
          if (!(vi[v].he & kBoundaryBit) || vi[v].he == kInvalid) vi[v].he = (he + 1) | kBoundaryBit;
          ++vi[v].deg;
        } else {
          P[p] = (kPushed << 30) | k;  // p > s: a partner earlier in file order would have pushed
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
  }
  partner.release();
  remapped.release();
  const uint32_t* bnd = boundary.data();

  // Boundary next by the fan rule: for the twin b of side s = u->v, turn around u through
  // the triangles (lPrev, then across the paired edge) until the next unpaired side p;
  // next[b] = twin(p), which leaves u in the same fan.
  for (uint32_t i = 0; i < nBoundarySides; ++i) {
    uint32_t b = bnd[i];
    uint32_t h = b ^ 1u;
    uint32_t steps = 0;
    for (;;) {
      uint32_t p = next[next[h]];  // lPrev: h is a triangle half-edge
      if (isUnlabelled(p ^ 1u)) {
        next[b] = p ^ 1u;
        if (full) prev[p ^ 1u] = b;
        break;
      }
      h = p ^ 1u;
      if (++steps > nh) return fail(Code::Invalid, "internal error: fan walk did not end");
    }
  }

  // Label the boundary loops in order of their lowest half-edge id.
  uint32_t nLoops = 0;
  if (!out.loopOffsets.push_back(0)) return oom();
  for (uint32_t i = 0; i < nBoundarySides; ++i) {
    uint32_t e = bnd[i];
    if (!isUnlabelled(e)) continue;
    uint32_t f = nt + nLoops;
    bool seam = false;
    double perim = 0;
    uint32_t x = e, steps = 0;
    do {
      ubits[x >> 6] &= ~(uint64_t(1) << (x & 63));
      if (full) face[x] = f;
      if (!out.loopHalfedges.push_back(x)) return oom();
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
      return oom();
    if (seam) ++out.nSeams; else ++out.nHoles;
    ++nLoops;
  }
  boundary.release();

  // Vertex loops: a used vertex is non-manifold when the vnext cycle through its chosen
  // outgoing half-edge does not hold all of its outgoing half-edges (more than one cycle).
  if (!out.vertexNonManifold.resize(nv)) return oom();
  {
    uint8_t* nm = out.vertexNonManifold.data();
    uint32_t nUsed = 0, nNonManifold = 0;
    for (uint32_t v = 0; v < nv; ++v) {
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
        if (++steps > deg) return fail(Code::Invalid, "internal error: vertex loop did not close");
      } while (x != e0);
      if (steps != deg) {
        nm[v] = 1;
        ++nNonManifold;
      }
    }
    out.nUsedVertices = nUsed;
    out.nNonManifoldVertices = nNonManifold;
  }

  return Status{};
}

}  // namespace stltopo
