// The per-shell report and the defect lists, from a mesh, its topology and the shell of
// each triangle. Uses next, vert, pairKind and the per-element arrays, never prev or face.
#include "stltopo/shells.h"

#include <algorithm>
#include <cmath>

#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"
#include "geometry_detail.h"
#include "parallel.h"
#include "predicates.h"
#include "prefetch.h"
#include "triangle_figures.h"
#include "try_alloc.h"

namespace stltopo {
namespace {

Status bad(const char* msg) { return Status::error(Code::InvalidArgument, msg); }
// What out-of-memory says could not be allocated.
constexpr const char* kLists = "the shell and defect lists";

// A triangle side on a cut (inconsistent or non-manifold) edge.
struct CutSide {
  uint32_t a, b;  // the edge's vertices, a < b
  uint32_t triangle;
  uint8_t kind;  // EdgeKind
  bool operator<(const CutSide& o) const { return a != o.a ? a < o.a : b != o.b ? b < o.b : triangle < o.triangle; }
};

// One vnext cycle of a non-manifold vertex and the shell it lies in.
struct Cycle {
  uint32_t vertex, shell;
  bool operator<(const Cycle& o) const { return vertex != o.vertex ? vertex < o.vertex : shell < o.shell; }
};

// A half-edge of the triangle of wanted[i]: when it is that triangle's triangleHalfedge,
// the triangle pass finds it.
struct Probe {
  uint32_t halfedge, wanted;
  bool operator<(const Probe& o) const { return halfedge < o.halfedge; }
};

bool testBit(const Array<uint64_t>& bits, uint32_t i) { return (bits[i >> 6] >> (i & 63)) & 1u; }
void setBit(Array<uint64_t>& bits, uint32_t i) { bits[i >> 6] |= uint64_t(1) << (i & 63); }

// Which corners of a triangle with welded corners a, b, c coincide (Defects::degenerateCorners).
uint8_t cornerMask(uint32_t a, uint32_t b, uint32_t c) {
  return uint8_t((a == b ? 1 : 0) | (b == c ? 2 : 0) | (c == a ? 4 : 0));
}

}  // namespace

const char* orientationName(Orientation o) {
  switch (o) {
    case Orientation::Inconsistent: return "inconsistent";
    case Orientation::Open: return "open";
    case Orientation::Outward: return "outward";
    case Orientation::Inward: return "inward";
    case Orientation::Flat: return "flat";
  }
  return "unknown";
}

Orientation Shell::orientation() const {
  if (inconsistentEdges > 0) return Orientation::Inconsistent;
  if (boundaryEdges > 0) return Orientation::Open;
  if (volumeSign > 0) return Orientation::Outward;
  if (volumeSign < 0) return Orientation::Inward;
  return Orientation::Flat;
}

namespace {

// The sum of the absolute values of the six products in det(a, b, c): the scale of the
// rounding error of triangleVolume(a, b, c).
inline double volumePermanent(const float* a, const float* b, const float* c) {
  const double ax = std::fabs(a[0]), ay = std::fabs(a[1]), az = std::fabs(a[2]);
  const double bx = std::fabs(b[0]), by = std::fabs(b[1]), bz = std::fabs(b[2]);
  const double cx = std::fabs(c[0]), cy = std::fabs(c[1]), cz = std::fabs(c[2]);
  return ax * (by * cz + bz * cy) + ay * (bx * cz + bz * cx) + az * (bx * cy + by * cx);
}

// Shell::volumeSign of every shell. Each triangle's triangleVolume is within 5u perm / 6 of
// det / 6 (u = 2^-53; the two products of floats in each 2x2 term are exact, then four
// roundings and the division), and the volume, summed in triangle order, within
// (n + 4) u (1 + 1e-6) P / 6 of the exact sum for n < 2^32 triangles (P: the sum of their
// volumePermanent). Beyond (n + 8) 1.2e-16 P / 6 the rounded volume's sign is the exact one;
// P = 0 means every product is 0, so the sum is exactly 0. The shells left (flat or nearly
// flat) get the exact sum (VolumeSum) in one more pass over their triangles.
Status signVolumes(const Mesh& mesh, const Topology& topo, const Array<double>& perm, Array<Shell>& shells) {
  Array<uint32_t> slot;  // per shell: its VolumeSum, or kInvalid when decided
  uint32_t undecided = 0;
  for (uint32_t s = 0; s < shells.size(); ++s) {
    Shell& S = shells[s];
    const double bound = (double(S.triangles) + 8) * 1.2e-16 * (perm[s] / 6);
    if (perm[s] == 0 || std::fabs(S.volume) > bound) {
      S.volumeSign = S.volume > 0 ? 1 : S.volume < 0 ? -1 : 0;
      continue;
    }
    if (slot.empty() && !slot.assign(shells.size(), kInvalid)) return detail::oom(kLists);
    slot[s] = undecided++;
  }
  if (undecided == 0) return Status{};
  Array<pred::VolumeSum> sums;
  if (!sums.assign(undecided, pred::VolumeSum{})) return detail::oom(kLists);
  const float* P = mesh.positions.data();
  for (uint32_t t = 0; t < mesh.nTriangles(); ++t) {
    const uint32_t s = topo.triangleShell[t];
    if (s == kInvalid || slot[s] == kInvalid) continue;
    const uint32_t* corner = mesh.triangles.data() + size_t(t) * 3;
    sums[slot[s]].add(P + size_t(corner[0]) * 3, P + size_t(corner[1]) * 3, P + size_t(corner[2]) * 3);
  }
  for (uint32_t s = 0; s < shells.size(); ++s)
    if (slot[s] != kInvalid) shells[s].volumeSign = sums[slot[s]].sign();
  return Status{};
}

}  // namespace

Status findShellsAndDefects(const Mesh& mesh, const Topology& topo, Array<Shell>* shellsOut, Defects* defectsOut) {
  if (shellsOut) *shellsOut = Array<Shell>{};
  if (defectsOut) *defectsOut = Defects{};
  const uint32_t nt = mesh.nTriangles(), nv = mesh.nVertices(), nh = topo.nHalfedges(), nl = topo.nLoops();
  const uint32_t nShells = topo.nShells;
  if (topo.nTriangles != nt || topo.nVertices != nv || topo.triangleHalfedge.size() != nt ||
      topo.triangleDegenerate.size() != nt || topo.vertexNonManifold.size() != nv || topo.vertexWeld.size() != nv ||
      topo.vert.size() != nh || topo.pairKind.size() != nh / 2 || topo.loopOffsets.size() != size_t(nl) + 1 ||
      topo.loopIsSeam.size() != nl || topo.loopHalfedges.size() != topo.loopOffsets[nl])
    return bad("the topology was not built from this mesh");
  if (topo.triangleShell.size() != nt)
    return bad("the topology has no triangleShell (TopologyOptions::triangleShell = false)");
  const uint32_t* triangleShell = topo.triangleShell.data();
  const uint32_t* next = topo.next.data();
  const uint32_t* vert = topo.vert.data();
  const uint8_t* pairKind = topo.pairKind.data();
  auto kindOf = [&](uint32_t e) { return EdgeKind(pairKind[e >> 1]); };
  const auto notMesh = [] { return bad("the topology was not built from this mesh"); };

  Array<Shell> shells;
  Defects d;
  Array<uint64_t> isLoop;                    // per half-edge: a boundary-loop half-edge
  Array<uint32_t> wanted;                    // half-edges (triangle sides) whose triangle the triangle pass finds
  Array<uint32_t> cutSides;                  // indices into wanted: the triangle sides on cut edges
  Array<uint32_t> outgoing;                  // the half-edges leaving non-manifold vertices, increasing
  Array<uint8_t> visited;                    // per entry of outgoing
  Array<uint32_t> cycleVertex, cycleWanted;  // per vnext cycle of those: its vertex, a triangle side of it
  if (!shells.assign(nShells, Shell{}) || !isLoop.assign((size_t(nh) + 63) / 64, 0) || !wanted.resize(nl) ||
      !d.loopShell.assign(nl, kInvalid))
    return detail::oom(kLists);
  for (uint32_t x : topo.loopHalfedges) {
    if (x >= nh) return notMesh();
    setBit(isLoop, x);
  }
  // The triangles to find: loop h's (wanted[h], the twin of its first half-edge: a triangle
  // side), then those of the cut sides (the opening side 2k of a cut pair k, and 2k + 1 when
  // it is a triangle side too), then one per vnext cycle of a non-manifold vertex.
  for (uint32_t h = 0; h < nl; ++h) wanted[h] = twin(topo.loopHalfedge[h]);
  for (uint32_t k = 0; k < nh / 2; ++k) {
    if (EdgeKind(pairKind[k]) != EdgeKind::Inconsistent && EdgeKind(pairKind[k]) != EdgeKind::NonManifold) continue;
    for (uint32_t e = 2 * k; e <= 2 * k + 1; ++e) {
      if (testBit(isLoop, e)) continue;
      if (!cutSides.push_back(uint32_t(wanted.size())) || !wanted.push_back(e)) return detail::oom(kLists);
    }
  }
  if (topo.nNonManifoldVertices > 0) {
    for (uint32_t e = 0; e < nh; ++e)
      if (topo.vertexNonManifold[vert[e]] && !outgoing.push_back(e)) return detail::oom(kLists);
    if (!visited.assign(outgoing.size(), 0)) return detail::oom(kLists);
    for (size_t i = 0; i < outgoing.size(); ++i) {
      if (visited[i]) continue;
      uint32_t x = outgoing[i], side = kInvalid, steps = 0;
      do {
        const uint32_t* it = std::lower_bound(outgoing.begin(), outgoing.end(), x);
        if (it == outgoing.end() || *it != x) return notMesh();
        visited[size_t(it - outgoing.begin())] = 1;
        if (side == kInvalid && !testBit(isLoop, x)) side = x;
        x = next[twin(x)];
        if (++steps > nh) return notMesh();
      } while (x != outgoing[i]);
      // Every cycle has a triangle side: the next of a loop half-edge's twin is one.
      if (side == kInvalid) return notMesh();
      if (!cycleVertex.push_back(vert[side]) || !cycleWanted.push_back(uint32_t(wanted.size())) ||
          !wanted.push_back(side))
        return detail::oom(kLists);
    }
    outgoing.release();
    visited.release();
  }
  // A wanted side's triangle holds it, next of it and next of that; one of the three is the
  // triangle's triangleHalfedge, which the triangle pass reads in order.
  Array<Probe> probes;
  Array<uint64_t> probeBit;
  Array<uint32_t> triangleOf;  // per wanted entry
  if (!probes.resize(wanted.size() * 3) || !probeBit.assign((size_t(nh) + 63) / 64, 0) ||
      !triangleOf.assign(wanted.size(), kInvalid))
    return detail::oom(kLists);
  for (size_t i = 0; i < wanted.size(); ++i) {
    uint32_t e = wanted[i];
    if (e >= nh) return notMesh();
    for (int c = 0; c < 3; ++c, e = next[e]) {
      probes[3 * i + c] = {e, uint32_t(i)};
      setBit(probeBit, e);
    }
  }
  std::sort(probes.begin(), probes.end());

  // One pass over the triangles in file order: the shells' triangles, figures and solids, the
  // vertices that are manifold (a manifold vertex is in one shell), the degenerate triangles,
  // and the triangles of the wanted sides.
  Array<uint64_t> seen;  // per vertex: counted in its (only) shell; manifold vertices only
  Array<double> perm;    // per shell: the scale of its volume's rounding error (signVolumes)
  if (!seen.assign((size_t(nv) + 63) / 64, 0) || !perm.assign(nShells, 0)) return detail::oom(kLists);
  const float* P = mesh.positions.data();
  const std::vector<Solid>& solids = mesh.solids;
  size_t solid = 0;
  uint32_t nextShell = 0;
  const bool exactWeld = !(topo.tolerance > 0);
  // (in chunks: detail::forChunks; an error stops them, in `failed`)
  Status failed;
  detail::forChunks(0, nt, [&](size_t t0, size_t t1) {
    if (!failed.ok()) return;
    uint32_t sink = 0, nextShellHere = nextShell;
    size_t solidHere = solid;
    for (uint32_t t = uint32_t(t0); t < t1; ++t) {
      const uint32_t* corner = mesh.triangles.data() + size_t(t) * 3;
      // The corners of a triangle a few ahead: in a file whose triangles are not in spatial
      // order, these reads miss the cache.
      for (auto [u, ue] = detail::aheadOf(t, 0, nt, detail::kAhead); u < ue; ++u)
        for (int c = 0; c < 3; ++c) detail::touch(P + size_t(mesh.triangles[3 * size_t(u) + c]) * 3, sink);
      uint32_t s = triangleShell[t];
      if (topo.triangleDegenerate[t]) {
        if (s != kInvalid) {
          failed = bad("triangleShell: a degenerate triangle has a shell");
          return;
        }
        if (defectsOut) {
          const uint32_t* w = topo.vertexWeld.data();
          if (!d.degenerateTriangles.push_back(t) ||
              !d.degenerateCorners.push_back(cornerMask(w[corner[0]], w[corner[1]], w[corner[2]]))) {
            failed = detail::oom(kLists);
            return;
          }
        }
        continue;
      }
      if (s >= nShells) {
        failed = bad("triangleShell: a shell id out of range");
        return;
      }
      Shell& S = shells[s];
      while (solidHere < solids.size() &&
             t >= uint64_t(solids[solidHere].firstTriangle) + solids[solidHere].triangleCount)
        ++solidHere;
      uint32_t solidOfT =
          solidHere < solids.size() && t >= solids[solidHere].firstTriangle ? uint32_t(solidHere) : kInvalid;
      if (S.triangles == 0) {
        if (s != nextShellHere++) {
          failed = bad("triangleShell: shells are not numbered by their lowest triangle id");
          return;
        }
        S.firstTriangle = t;
        S.solid = solidOfT;
        for (int k = 0; k < 3; ++k) S.bboxMin[k] = S.bboxMax[k] = P[size_t(corner[0]) * 3 + k];
      } else if (S.solid != solidOfT) {
        S.solid = kMixedSolid;
      }
      ++S.triangles;
      const float* A = P + size_t(corner[0]) * 3;
      const float* B = P + size_t(corner[1]) * 3;
      const float* C = P + size_t(corner[2]) * 3;
      detail::TriangleFigures fig = detail::triangleFigures(A, B, C);
      S.area += fig.area;
      S.volume += fig.volume;
      perm[s] += volumePermanent(A, B, C);
      for (const float* Q : {A, B, C})
        for (int k = 0; k < 3; ++k) {
          S.bboxMin[k] = std::min(S.bboxMin[k], Q[k]);
          S.bboxMax[k] = std::max(S.bboxMax[k], Q[k]);
        }
      for (int c = 0; c < 3; ++c) {
        uint32_t v = exactWeld ? corner[c] : topo.vertexWeld[corner[c]];
        if (!topo.vertexNonManifold[v] && !testBit(seen, v)) {
          setBit(seen, v);
          ++S.vertices;
        }
      }
      uint32_t h0 = topo.triangleHalfedge[t];
      if (h0 < nh && testBit(probeBit, h0)) {
        const Probe* it = std::lower_bound(probes.begin(), probes.end(), Probe{h0, 0});
        for (; it != probes.end() && it->halfedge == h0; ++it) triangleOf[it->wanted] = t;
      }
    }
    nextShell = nextShellHere;
    solid = solidHere;
    detail::keepAlive(sink);
  });
  if (!failed.ok()) return failed;
  if (nextShell != nShells) return bad("triangleShell: fewer shells than Topology::nShells");
  seen.release();
  if (Status st = signVolumes(mesh, topo, perm, shells); !st.ok()) return st;
  perm.release();
  probes.release();
  probeBit.release();
  for (uint32_t t : triangleOf)
    if (t == kInvalid) return notMesh();

  // Loops: each lies in one shell, with its boundary edges (a boundary pair's twin is a loop
  // half-edge). A shell's interior edges follow from its sides: 3 triangles = 2 interior
  // + boundary + cut sides.
  Array<uint32_t> sides;  // per shell: boundary and cut sides
  if (!sides.assign(nShells, 0)) return detail::oom(kLists);
  for (uint32_t h = 0; h < nl; ++h) {
    uint32_t s = triangleShell[triangleOf[h]];
    d.loopShell[h] = s;
    Shell& S = shells[s];
    if (topo.loopIsSeam[h])
      ++S.seams;
    else
      ++S.holes;
    for (uint32_t i = topo.loopOffsets[h]; i < topo.loopOffsets[h + 1]; ++i)
      if (kindOf(topo.loopHalfedges[i]) == EdgeKind::Boundary) ++S.boundaryEdges;
  }
  // Cut edges: the sides of one undirected edge are adjacent once sorted.
  Array<CutSide> cuts;
  if (!cuts.resize(cutSides.size())) return detail::oom(kLists);
  for (size_t i = 0; i < cutSides.size(); ++i) {
    uint32_t e = wanted[cutSides[i]], a = vert[e], b = vert[twin(e)];  // twin's origin = e's destination
    uint32_t t = triangleOf[cutSides[i]];
    cuts[i] = {std::min(a, b), std::max(a, b), t, uint8_t(kindOf(e))};
    ++sides[triangleShell[t]];
  }
  std::sort(cuts.begin(), cuts.end());
  if (defectsOut && !d.nonManifoldEdgeOffsets.push_back(0)) return detail::oom(kLists);
  for (size_t i = 0; i < cuts.size();) {
    size_t j = i + 1;
    while (j < cuts.size() && cuts[j].a == cuts[i].a && cuts[j].b == cuts[i].b) ++j;
    Shell& S = shells[triangleShell[cuts[i].triangle]];
    ++S.edges;
    bool nonManifold = cuts[i].kind == uint8_t(EdgeKind::NonManifold);
    if (nonManifold)
      ++S.nonManifoldEdges;
    else
      ++S.inconsistentEdges;
    if (defectsOut) {
      Array<uint32_t>& vertices = nonManifold ? d.nonManifoldEdgeVertices : d.inconsistentEdgeVertices;
      Array<uint32_t>& triangles = nonManifold ? d.nonManifoldEdgeTriangles : d.inconsistentEdgeTriangles;
      if (!vertices.push_back(cuts[i].a) || !vertices.push_back(cuts[i].b)) return detail::oom(kLists);
      for (size_t k = i; k < j; ++k)
        if (!triangles.push_back(cuts[k].triangle)) return detail::oom(kLists);
      if (nonManifold && !d.nonManifoldEdgeOffsets.push_back(uint32_t(triangles.size()))) return detail::oom(kLists);
    }
    i = j;
  }
  cuts.release();
  for (uint32_t s = 0; s < nShells; ++s) {
    Shell& S = shells[s];
    uint64_t paired = 3 * uint64_t(S.triangles) - S.boundaryEdges - sides[s];
    if (paired % 2 != 0) return notMesh();
    S.edges += uint32_t(paired / 2) + S.boundaryEdges;
  }

  // Non-manifold vertices: a shell counts a vertex once per vnext cycle it has there (a cycle
  // never leaves its fan, so it lies in the shell of any of its triangles).
  Array<Cycle> cycles;
  if (!cycles.resize(cycleVertex.size())) return detail::oom(kLists);
  for (size_t i = 0; i < cycleVertex.size(); ++i)
    cycles[i] = {cycleVertex[i], triangleShell[triangleOf[cycleWanted[i]]]};
  std::sort(cycles.begin(), cycles.end());
  for (size_t i = 0; i < cycles.size();) {
    size_t j = i;
    while (j < cycles.size() && cycles[j].vertex == cycles[i].vertex) {
      size_t k = j;
      while (k < cycles.size() && cycles[k].vertex == cycles[j].vertex && cycles[k].shell == cycles[j].shell) ++k;
      Shell& S = shells[cycles[j].shell];
      ++S.vertices;
      if (k - j > 1) ++S.nonManifoldVertices;
      j = k;
    }
    if (defectsOut &&
        (!d.nonManifoldVertices.push_back(cycles[i].vertex) || !d.nonManifoldVertexCycles.push_back(uint32_t(j - i))))
      return detail::oom(kLists);
    i = j;
  }

  if (shellsOut) *shellsOut = std::move(shells);
  if (defectsOut) *defectsOut = std::move(d);
  return Status{};
}

Status geometry_detail::watertightShells(const Mesh& mesh, const Topology& topo, Array<Shell>& out) {
  out = Array<Shell>{};
  const uint32_t nt = mesh.nTriangles(), nShells = topo.nShells;
  if (topo.nTriangles != nt || topo.nVertices != mesh.nVertices() || topo.triangleDegenerate.size() != nt)
    return bad("the topology was not built from this mesh");
  if (topo.triangleShell.size() != nt)
    return bad("the topology has no triangleShell (TopologyOptions::triangleShell = false)");
  if (!topo.watertight() || !topo.manifold()) return bad("watertightShells: the mesh is not watertight and manifold");
  Array<Shell> shells;
  Array<double> perm;
  if (!shells.assign(nShells, Shell{}) || !perm.assign(nShells, 0)) return detail::oom(kLists);
  const uint32_t* triangleShell = topo.triangleShell.data();
  const float* P = mesh.positions.data();
  uint32_t nextShell = 0;
  // The same triangles, in the same order and with the same formula, as findShellsAndDefects:
  // the volumes are the same to the bit.
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t s = triangleShell[t];
    if (topo.triangleDegenerate[t]) {
      if (s != kInvalid) return bad("triangleShell: a degenerate triangle has a shell");
      continue;
    }
    if (s >= nShells) return bad("triangleShell: a shell id out of range");
    Shell& S = shells[s];
    if (S.triangles == 0) {
      if (s != nextShell++) return bad("triangleShell: shells are not numbered by their lowest triangle id");
      S.firstTriangle = t;
    }
    ++S.triangles;
    const uint32_t* corner = mesh.triangles.data() + size_t(t) * 3;
    const float *A = P + size_t(corner[0]) * 3, *B = P + size_t(corner[1]) * 3, *C = P + size_t(corner[2]) * 3;
    S.volume += detail::triangleVolume(A, B, C);
    perm[s] += volumePermanent(A, B, C);
  }
  if (nextShell != nShells) return bad("triangleShell: fewer shells than Topology::nShells");
  if (Status st = signVolumes(mesh, topo, perm, shells); !st.ok()) return st;
  out = std::move(shells);
  return Status{};
}

}  // namespace stltopo
