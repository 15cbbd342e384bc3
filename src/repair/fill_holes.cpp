// The fill-holes repair step (steps.h): each boundary loop of the mesh, in loop order, is one
// item. A loop is filled only when everything about its fill is decided and checked before
// the first edit:
//   1. skipped outright: seams (a cut side: filling would make non-manifold edges), loops
//      over a size limit (edges, perimeter), loops an earlier fill of this step changed;
//   2. the loop is cut at vertices it passes more than once into simple parts (as
//      EditableMesh::fillHole does); a part of two edges cannot be filled (skipped);
//   3. each part is triangulated by minimum weight (Liepa 2003, after Barequet and Sharir:
//      O(n^3) dynamic programming; weight = the largest dihedral angle, with the mesh across
//      the loop's edges and inside the patch, then the area, compared lexicographically;
//      inner edges that exist already are not used) up to kMinWeightCap edges, by ear
//      clipping in the part's Newell plane above (and by minimum weight after all, up to
//      kMinWeightFallbackCap edges, when the ear-clipped patch fails the checks);
//   4. optionally refined (Liepa: centroid splits where the scale allows, the target being
//      the mean length of the loop's edges, then Delaunay flips of the patch's inner edges)
//      and faired (umbrella smoothing of the new vertices only, the loop fixed);
//   5. checked exactly: no zero-area new triangle (collinear corners), no fold-over (a new
//      triangle's normal against the mesh triangle across its loop edge by more than 90
//      degrees: the exact sign of the dot product of the normals; not asked of a patch of
//      one triangle, the only fill of its hole), no inner edge on an
//      existing edge or used twice (non-manifold), the area limit, and no new triangle
//      meeting an existing triangle, an earlier fill's or another of its own other than in
//      the corners and sides they share (the exact pair test of the intersection pass,
//      against the triangles whose boxes overlap, found through a bounding-volume hierarchy
//      built once per step over the triangles near the loops). A refined patch that fails
//      is replaced by the plain triangulation (the item says so); a plain one that fails
//      skips the item;
//   6. applied with addVertex and addTriangle. A refused edit means a check missed
//      something: the item's triangles are removed again and it is skipped with the refusal.
// The geometric decisions (zero area, fold-over, crossing) go through the exact predicates;
// the weights of the triangulation and the refinement's choices are floating point: they
// choose among fills, the exact checks accept or refuse the chosen one. Zero-area triangles
// of the mesh (collinear corners) are left out of the crossing test (the zero-area step
// runs before this one).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "geometry_detail.h"
#include "predicates.h"
#include "repair/steps.h"
#include "text_format.h"
#include "try_alloc.h"

namespace stltopo {
namespace repair_detail {
namespace {

using geometry_detail::Tri;

// Parts with up to this many edges are triangulated by minimum weight (O(n^3) time, O(n^2)
// memory: 200 edges take a few milliseconds), longer ones by ear clipping.
constexpr uint32_t kMinWeightCap = 200;
// Ear-clipped parts up to this many edges get a second chance by minimum weight when the
// ear-clipped patch fails the checks (O(n^3): about a second at 600 edges; 16 MB).
constexpr uint32_t kMinWeightFallbackCap = 600;
// Refinement: at most this many rounds of splits, and at most this many triangles in one
// patch (the refinement stops there; the patch stays valid).
constexpr int kRefineRounds = 30;
constexpr uint32_t kMaxPatchTriangles = 1u << 20;
constexpr int kRelaxPasses = 20;
// Fairing: umbrella iterations over the new vertices.
constexpr int kFairIterations = 200;
constexpr double kAlpha = 1.4142135623730951;  // Liepa's density control, sqrt(2)

constexpr const char* kWhat = "the fill-holes step's arrays";
Status oom() { return detail::oom(kWhat); }

inline uint64_t edgeKey(uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a; }

// ------------------------------------------------------------------------- vectors
struct V3 {
  double x = 0, y = 0, z = 0;
};
inline V3 vsub(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 vcross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double vdot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double vlen(const V3& a) { return std::sqrt(vdot(a, a)); }
inline V3 vof(const float* p) { return {p[0], p[1], p[2]}; }
// The unit normal of (a, b, c); zero when it has none.
inline V3 unitNormal(const V3& a, const V3& b, const V3& c) {
  V3 n = vcross(vsub(b, a), vsub(c, a));
  double l = vlen(n);
  if (!(l > 0) || !std::isfinite(l)) return {};
  return {n.x / l, n.y / l, n.z / l};
}
inline double triArea(const V3& a, const V3& b, const V3& c) { return 0.5 * vlen(vcross(vsub(b, a), vsub(c, a))); }

// ------------------------------------------------------------------------- the mesh's triangles
// Live triangles with three distinct, non-collinear corners, in a bounding-volume hierarchy
// (sorted by the Morton code of their box centres, leaves of up to kLeaf, the left child
// following its parent).
struct Box {
  float lo[3], hi[3];
};
inline bool overlaps(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}
inline void extend(Box& b, const float* p) {
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = std::min(b.lo[k], p[k]);
    b.hi[k] = std::max(b.hi[k], p[k]);
  }
}
inline Box emptyBox() {
  Box b;
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = std::numeric_limits<float>::infinity();
    b.hi[k] = -std::numeric_limits<float>::infinity();
  }
  return b;
}
inline void merge(Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k) {
    a.lo[k] = std::min(a.lo[k], b.lo[k]);
    a.hi[k] = std::max(a.hi[k], b.hi[k]);
  }
}

constexpr uint32_t kLeaf = 8;

struct Bvh {
  struct Node {
    Box box;
    uint32_t first, end, right;  // right == 0: a leaf
  };
  Array<uint32_t> tri;
  Array<Box> box;
  Array<Node> nodes;

  uint32_t build(uint32_t first, uint32_t end) {
    const uint32_t self = uint32_t(nodes.size());
    Node n;
    n.box = emptyBox();
    for (uint32_t i = first; i < end; ++i) merge(n.box, box[i]);
    n.first = first;
    n.end = end;
    n.right = 0;
    (void)nodes.push_back(n);  // capacity reserved
    if (end - first > kLeaf) {
      const uint32_t mid = first + (end - first) / 2;
      build(first, mid);
      const uint32_t r = build(mid, end);
      nodes[self].right = r;
    }
    return self;
  }

  // Every stored triangle whose box overlaps q.
  template <class F>
  bool query(const Box& q, F&& f) const {
    if (nodes.size() == 0) return true;
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes[stack[--top]];
      if (!overlaps(n.box, q)) continue;
      if (n.right == 0) {
        for (uint32_t i = n.first; i < n.end; ++i)
          if (overlaps(box[i], q) && !f(tri[i])) return false;
      } else {
        const uint32_t self = uint32_t(&n - nodes.data());
        stack[top++] = n.right;
        stack[top++] = self + 1;
      }
    }
    return true;
  }
};

// The cells of a grid over a set of boxes that some box touches (the candidate loops' boxes,
// for Filler::init): a box that touches none of them overlaps none of the boxes, which one
// look at a bit tells, where the hierarchy's query walks its nodes. At 4M triangles that query
// per triangle was a third of `stltopo repair --plan` (bench/PROFILE.md, *Stop 50*). A box
// that touches a marked cell still goes to the query, so the grid changes no result: a cell
// index is a monotone function of the coordinate (rounding is monotone), so two overlapping
// boxes share a cell; a NaN coordinate overlaps nothing in the query, and lands in cell 0.
// The hierarchy itself is in Morton order (buildSorted); the grid still spares most queries:
// at 4M triangles and 10,311 holes, Filler::init took about 0.8-0.9 s without it, 0.2 s with.
bool gFillCellGrid = true;  // setFillCellGridForTesting

struct CellGrid {
  uint32_t g[3] = {0, 0, 0};  // cells per axis; g[0] == 0: no grid (every box may overlap)
  double lo[3] = {0, 0, 0}, scale[3] = {0, 0, 0};
  Array<uint64_t> bits;

  uint32_t cell(int k, float x) const {
    const double d = (double(x) - lo[k]) * scale[k];
    return d > 0 ? (d < double(g[k]) ? uint32_t(d) : g[k] - 1) : 0;
  }
  // The cells of b, and how many.
  uint64_t range(const Box& b, uint32_t c0[3], uint32_t c1[3]) const {
    uint64_t n = 1;
    for (int k = 0; k < 3; ++k) {
      c0[k] = cell(k, b.lo[k]);
      c1[k] = cell(k, b.hi[k]);
      n *= uint64_t(c1[k] >= c0[k] ? c1[k] - c0[k] + 1 : 1);
    }
    return n;
  }
  uint64_t index(uint32_t x, uint32_t y, uint32_t z) const { return (uint64_t(x) * g[1] + y) * g[2] + z; }
  // Cells about the size of the boxes' median extent (a box then touches up to 8), doubled
  // while the grid would have more than maxCells cells or its marking would visit more than
  // 2^24. None for up to 2 kLeaf boxes (the query looks at a leaf or two, and a fresh bit
  // array costs more) or boxes of no extent. False when memory runs out.
  bool build(const Box* boxes, uint32_t n, uint64_t maxCells) {
    g[0] = 0;
    if (n <= 2 * kLeaf) return true;
    Box all = emptyBox();
    for (uint32_t i = 0; i < n; ++i) merge(all, boxes[i]);
    double size = 0;  // the largest of the three medians of the boxes' extents
    {
      Array<float> ext;
      if (!ext.resize(n)) return false;
      for (int k = 0; k < 3; ++k) {
        for (uint32_t i = 0; i < n; ++i) ext[i] = boxes[i].hi[k] - boxes[i].lo[k];
        std::nth_element(ext.begin(), ext.begin() + n / 2, ext.end());
        size = std::max(size, double(ext[n / 2]));
      }
    }
    if (!(size > 0) || !std::isfinite(size)) return true;
    for (;; size *= 2) {
      uint64_t cells = 1;
      for (int k = 0; k < 3; ++k) {
        lo[k] = all.lo[k];
        const double ext = double(all.hi[k]) - all.lo[k];
        g[k] = uint32_t(std::min(4096.0, std::max(1.0, std::ceil(ext / size))));
        scale[k] = ext > 0 ? double(g[k]) / ext : 0;
        cells *= g[k];
      }
      if (cells == 1) {  // one cell: every box is in it
        g[0] = 0;
        return true;
      }
      if (cells > maxCells) continue;
      uint64_t visits = 0;
      uint32_t c0[3], c1[3];
      for (uint32_t i = 0; i < n && visits <= (uint64_t(1) << 24); ++i) visits += range(boxes[i], c0, c1);
      if (visits <= (uint64_t(1) << 24)) break;
    }
    if (!bits.assign((uint64_t(g[0]) * g[1] * g[2] + 63) / 64, 0)) return false;
    uint32_t c0[3], c1[3];
    for (uint32_t i = 0; i < n; ++i) {
      range(boxes[i], c0, c1);
      for (uint32_t x = c0[0]; x <= c1[0]; ++x)
        for (uint32_t y = c0[1]; y <= c1[1]; ++y)
          for (uint32_t z = c0[2]; z <= c1[2]; ++z) {
            const uint64_t c = index(x, y, z);
            bits[c / 64] |= uint64_t(1) << (c % 64);
          }
    }
    return true;
  }
  // False only when b overlaps none of the boxes.
  bool mayOverlap(const Box& b) const {
    if (g[0] == 0) return true;
    uint32_t c0[3], c1[3];
    if (range(b, c0, c1) > 64) return true;  // a box of many cells: the query decides
    for (uint32_t x = c0[0]; x <= c1[0]; ++x)
      for (uint32_t y = c0[1]; y <= c1[1]; ++y)
        for (uint32_t z = c0[2]; z <= c1[2]; ++z) {
          const uint64_t c = index(x, y, z);
          if (bits[c / 64] >> (c % 64) & 1) return true;
        }
    return false;
  }
};

inline uint32_t spread10(uint32_t x) {
  x &= 0x3FF;
  x = (x | (x << 16)) & 0x30000FF;
  x = (x | (x << 8)) & 0x300F00F;
  x = (x | (x << 4)) & 0x30C30C3;
  x = (x | (x << 2)) & 0x9249249;
  return x;
}

// Orders a hierarchy's items (tri, box) by the Morton code of their box centres on a 1024^3
// grid over their common box, so that each node's items lie together; builds it. False when
// memory runs out.
bool buildSorted(Bvh& h) {
  const uint32_t n = uint32_t(h.tri.size());
  if (n == 0) return true;
  Array<uint64_t> keyed;
  Array<Box> boxes;
  if (!keyed.resize(n) || !boxes.resize(n) || !h.nodes.reserve(size_t(n) / 2 + 16)) return false;
  Box all = emptyBox();
  for (uint32_t i = 0; i < n; ++i) merge(all, h.box[i]);
  double scale[3];
  for (int k = 0; k < 3; ++k) {
    const double ext = double(all.hi[k]) - all.lo[k];
    scale[k] = ext > 0 ? 1023.0 / ext : 0;
  }
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t code = 0;
    for (int k = 0; k < 3; ++k) {
      const double mid = 0.5 * (double(h.box[i].lo[k]) + h.box[i].hi[k]);
      code |= spread10(uint32_t((mid - all.lo[k]) * scale[k])) << k;
    }
    keyed[i] = (uint64_t(code) << 32) | i;
  }
  std::sort(keyed.begin(), keyed.end());
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = uint32_t(keyed[i]);
    boxes[i] = h.box[j];
    keyed[i] = h.tri[j];  // its code is no longer needed
  }
  for (uint32_t i = 0; i < n; ++i) {
    h.box[i] = boxes[i];
    h.tri[i] = uint32_t(keyed[i]);
  }
  h.build(0, n);
  return true;
}

// ------------------------------------------------------------------------- the step's state
struct Filler {
  StepContext& ctx;
  EditableMesh& em;
  // The loops as the step found them.
  Array<uint32_t> loopOffsets, loopHalfedges, loopVerts;
  Array<uint8_t> loopIsSeam;
  Array<double> loopPerimeter;
  // The candidate loops' vertices: a slot each (kInvalid for the other vertices), and per
  // slot the live triangles with three distinct corners at it (CSR), as the step found them.
  Array<uint32_t> vertexSlot, slotOffsets, slotList;
  // Edges that earlier fills of this step added (sorted), their triangles and boxes.
  Array<uint64_t> addedEdges;
  Array<uint32_t> addedTriangles;  // triangle ids
  Array<uint32_t> addedItemOffsets;
  Array<Box> addedItemBoxes;
  Bvh bvh;
  uint32_t nVerticesAtStart = 0, nTrianglesAtStart = 0;
  Array<uint32_t> stamp;     // per vertex (step-start count), for cutting loops
  Array<uint32_t> meshVtri;  // per vertex (step-start count): kInvalid outside refine()
  uint32_t epoch = 0;

  explicit Filler(StepContext& c) : ctx(c), em(c.em) {}

  const float* pos(uint32_t v) const { return em.positions().data() + 3 * size_t(v); }

  bool triangleUsable(uint32_t t) const {
    if (!em.triangleAlive(t)) return false;
    const uint32_t* C = em.triangles().data() + 3 * size_t(t);
    return C[0] != C[1] && C[1] != C[2] && C[0] != C[2];
  }

  // Whether the step would try loop h at all (seams and loops over the edge and perimeter
  // limits are skipped before anything is looked up).
  bool candidate(uint32_t h) const {
    const uint32_t n = loopOffsets[h + 1] - loopOffsets[h];
    return !loopIsSeam[h] && n <= ctx.options.maxHoleEdges &&
           !(ctx.options.maxHolePerimeter > 0 && loopPerimeter[h] > ctx.options.maxHolePerimeter);
  }

  // What the items need of the mesh as the step finds it, in one pass over the triangles
  // (O(n), plus O(k log k) for the k triangles near the loops):
  //   - the triangles at the candidate loops' vertices (slot per such vertex, CSR), for the
  //     edges that exist there: every inner edge a fill can add between mesh vertices joins
  //     two vertices of its loop;
  //   - the triangles whose boxes overlap a candidate loop's box, in a hierarchy, for the
  //     crossing test: a fill lies in its loop's box (its corners are the loop's vertices,
  //     centroids and averages of them).
  Status init() {
    nVerticesAtStart = em.nVertices();
    nTrianglesAtStart = em.nTriangles();
    const EditLoops& L = em.loops();
    auto copy = [](auto& dst, const auto& src) {
      if (!dst.resize(src.size())) return false;
      if (src.size() > 0) std::memcpy(dst.data(), src.data(), src.size() * sizeof(src[0]));
      return true;
    };
    if (L.nLoops() > 0 && L.loopOffsets.size() != L.nLoops() + 1) return oom();  // loops() ran out of memory
    if (!copy(loopOffsets, L.loopOffsets) || !copy(loopHalfedges, L.loopHalfedges) || !copy(loopIsSeam, L.loopIsSeam) ||
        !copy(loopPerimeter, L.loopPerimeter) || !loopVerts.resize(L.loopHalfedges.size()))
      return oom();
    for (size_t i = 0; i < loopHalfedges.size(); ++i) loopVerts[i] = em.vert()[loopHalfedges[i]];
    if (!addedItemOffsets.push_back(0)) return oom();
    const uint32_t nLoops = L.nLoops();
    if (nLoops == 0) return Status{};
    const uint32_t nv = nVerticesAtStart, nt = nTrianglesAtStart;
    if (!stamp.assign(nv, 0) || !meshVtri.assign(nv, kInvalid) || !vertexSlot.assign(nv, kInvalid)) return oom();
    // The candidate loops' vertices and boxes.
    Bvh loopBoxes;
    uint32_t nSlots = 0, nCand = 0;
    for (uint32_t h = 0; h < nLoops; ++h) {
      if (!candidate(h)) continue;
      ++nCand;
      for (uint32_t i = loopOffsets[h]; i < loopOffsets[h + 1]; ++i)
        if (vertexSlot[loopVerts[i]] == kInvalid) vertexSlot[loopVerts[i]] = nSlots++;
    }
    if (!loopBoxes.tri.resize(nCand) || !loopBoxes.box.resize(nCand)) return oom();
    nCand = 0;
    for (uint32_t h = 0; h < nLoops; ++h) {
      if (!candidate(h)) continue;
      Box b = emptyBox();
      for (uint32_t i = loopOffsets[h]; i < loopOffsets[h + 1]; ++i) extend(b, pos(loopVerts[i]));
      loopBoxes.tri[nCand] = h;
      loopBoxes.box[nCand++] = b;
    }
    if (!buildSorted(loopBoxes)) return oom();
    CellGrid loopCells;
    // At most 16 cells a triangle (a bit array of 2 B a triangle, fresh memory that costs less
    // than the queries it spares), and 2^26 (8 MB).
    const uint64_t maxCells = std::min<uint64_t>(uint64_t(1) << 26, std::max<uint64_t>(uint64_t(1) << 16, 16 * uint64_t(nt)));
    if (gFillCellGrid && !loopCells.build(loopBoxes.box.data(), nCand, maxCells)) return oom();
    // One pass over the triangles.
    const uint32_t* T = em.triangles().data();
    Array<uint64_t> slotTri;  // slot << 32 | triangle
    Array<uint32_t> near;
    for (uint32_t t = 0; t < nt; ++t) {
      if (!triangleUsable(t)) continue;
      const uint32_t* C = T + 3 * size_t(t);
      for (int c = 0; c < 3; ++c)
        if (vertexSlot[C[c]] != kInvalid && !slotTri.push_back((uint64_t(vertexSlot[C[c]]) << 32) | t)) return oom();
      Box b = emptyBox();
      for (int c = 0; c < 3; ++c) extend(b, pos(C[c]));
      bool hit = false;
      if (loopCells.mayOverlap(b))
        loopBoxes.query(b, [&](uint32_t) {
          hit = true;
          return false;
        });
      if (hit && !pred::collinear(pos(C[0]), pos(C[1]), pos(C[2])) && !near.push_back(t)) return oom();
    }
    std::sort(slotTri.begin(), slotTri.end());
    if (!slotOffsets.assign(size_t(nSlots) + 1, 0) || !slotList.resize(slotTri.size())) return oom();
    for (size_t i = 0; i < slotTri.size(); ++i) {
      ++slotOffsets[uint32_t(slotTri[i] >> 32) + 1];
      slotList[i] = uint32_t(slotTri[i]);
    }
    for (uint32_t k = 0; k < nSlots; ++k) slotOffsets[k + 1] += slotOffsets[k];
    // The hierarchy over the triangles near the loops.
    const uint32_t n = uint32_t(near.size());
    if (!bvh.tri.resize(n) || !bvh.box.resize(n)) return oom();
    for (uint32_t i = 0; i < n; ++i) {
      Box b = emptyBox();
      for (int c = 0; c < 3; ++c) extend(b, pos(T[3 * size_t(near[i]) + c]));
      bvh.tri[i] = near[i];
      bvh.box[i] = b;
    }
    if (!buildSorted(bvh)) return oom();
    return Status{};
  }

  // Whether edge u-v exists between two vertices of candidate loops: in the mesh as the step
  // found it (a live triangle with three distinct corners has it) or among the edges earlier
  // fills added.
  bool edgeExists(uint32_t u, uint32_t v) const {
    if (u < nVerticesAtStart && v < nVerticesAtStart && vertexSlot[u] != kInvalid) {
      const uint32_t* T = em.triangles().data();
      const uint32_t k = vertexSlot[u];
      for (uint32_t i = slotOffsets[k]; i < slotOffsets[k + 1]; ++i) {
        const uint32_t* C = T + 3 * size_t(slotList[i]);
        if (C[0] == v || C[1] == v || C[2] == v) return true;
      }
    }
    return std::binary_search(addedEdges.begin(), addedEdges.end(), edgeKey(u, v));
  }

  Status run();
  Status fillItem(uint32_t h);
};

// ------------------------------------------------------------------------- the patch
// A candidate fill: vertices are the mesh's (ids < base) or new ones (base + k, positions in
// newPos); triangles in loop orientation; per side 3t + c (corner c -> c + 1) the patch
// triangle across it, or -1 - i for the loop's edge i.
struct Patch {
  uint32_t base = 0;
  Array<uint32_t> tris;
  Array<int64_t> nbr;
  Array<float> newPos;     // 3 per new vertex
  Array<double> newScale;  // per new vertex
  Array<uint32_t> vtri;    // per new vertex: a triangle using it (for circulation)
  uint32_t nTris() const { return uint32_t(tris.size() / 3); }
  uint32_t nNew() const { return uint32_t(newScale.size()); }
};

inline uint32_t nextC(uint32_t c) { return c == 2 ? 0 : c + 1; }
inline uint32_t prevC(uint32_t c) { return c == 0 ? 2 : c - 1; }

// The parts of a loop: runs of the loop's edge positions, each a simple polygon.
struct Parts {
  Array<uint32_t> pos;      // loop positions (edge i runs from vertex i to vertex i + 1)
  Array<uint32_t> offsets;  // part p is pos[offsets[p], offsets[p + 1])
};

// Minimum-weight triangulation of one simple polygon (Liepa's weight). Polygon vertex i has
// position P[i]; edge i (i -> i + 1 mod m) has the mesh triangle's unit normal NB[i] across
// it. forbidden(i, j): the inner edge i-j may not be used. Appends triangles as polygon
// indices (i, k, j), i < k < j. False when every triangulation needs a forbidden edge.
template <class Forbidden>
Status minWeight(uint32_t m, const V3* P, const V3* NB, Forbidden&& forbidden, Array<uint32_t>& out, bool& found) {
  found = false;
  const size_t mm = size_t(m) * m;
  Array<double> angle, area;
  Array<uint32_t> arg;
  Array<V3> normal;
  Array<uint8_t> bad;
  if (!angle.assign(mm, std::numeric_limits<double>::infinity()) || !area.assign(mm, 0) || !arg.assign(mm, kInvalid) ||
      !normal.resize(mm) || !bad.assign(mm, 0))
    return oom();
  for (uint32_t i = 0; i < m; ++i)
    for (uint32_t j = i + 2; j < m; ++j)
      if (!(i == 0 && j == m - 1) && forbidden(i, j)) bad[size_t(i) * m + j] = 1;
  // Cost of the dihedral between a new triangle (unit normal a) and a neighbour (b): 1 - cos
  // of the angle between the normals (0 flat, 2 folded back). A new triangle without a
  // normal costs more than any angle (and is charged once for itself below); a neighbour
  // without one says nothing.
  auto cost = [](const V3& a, const V3& b) {
    if (vdot(a, a) == 0) return 4.0;
    if (vdot(b, b) == 0) return 0.0;
    return 1 - vdot(a, b);
  };
  for (uint32_t i = 0; i + 1 < m; ++i) angle[size_t(i) * m + i + 1] = 0;
  for (uint32_t len = 2; len < m; ++len)
    for (uint32_t i = 0; i + len < m; ++i) {
      const uint32_t j = i + len;
      const size_t ij = size_t(i) * m + j;
      if (bad[ij]) continue;
      double bestA = std::numeric_limits<double>::infinity(), bestS = 0;
      uint32_t best = kInvalid;
      V3 bestN;
      for (uint32_t k = i + 1; k < j; ++k) {
        const size_t ik = size_t(i) * m + k, kj = size_t(k) * m + j;
        if (!std::isfinite(angle[ik]) || !std::isfinite(angle[kj])) continue;
        const V3 n = unitNormal(P[i], P[k], P[j]);
        double a = std::max(angle[ik], angle[kj]);
        if (vdot(n, n) == 0) a = std::max(a, 4.0);
        a = std::max(a, cost(n, k == i + 1 ? NB[i] : normal[ik]));
        a = std::max(a, cost(n, j == k + 1 ? NB[k] : normal[kj]));
        if (i == 0 && j == m - 1) a = std::max(a, cost(n, NB[m - 1]));
        const double s = area[ik] + area[kj] + triArea(P[i], P[k], P[j]);
        if (a < bestA || (a == bestA && s < bestS)) {
          bestA = a;
          bestS = s;
          best = k;
          bestN = n;
        }
      }
      angle[ij] = bestA;
      area[ij] = bestS;
      arg[ij] = best;
      normal[ij] = bestN;
    }
  if (arg[m - 1] == kInvalid) return Status{};
  // Unwind (i, j) ranges.
  Array<uint64_t> stack;
  if (!stack.push_back(uint64_t(m - 1))) return oom();
  while (stack.size() > 0) {
    const uint64_t r = stack[stack.size() - 1];
    stack.shrink(stack.size() - 1);
    const uint32_t i = uint32_t(r >> 32), j = uint32_t(r);
    if (j - i < 2) continue;
    const uint32_t k = arg[size_t(i) * m + j];
    if (!out.push_back(i) || !out.push_back(k) || !out.push_back(j)) return oom();
    if (!stack.push_back((uint64_t(i) << 32) | k) || !stack.push_back((uint64_t(k) << 32) | j)) return oom();
  }
  found = true;
  return Status{};
}

// Ear clipping of one simple polygon in its Newell plane. found = false when it has no
// plane or every ear needs a forbidden edge.
template <class Forbidden>
Status earClip(uint32_t m, const V3* P, Forbidden&& forbidden, Array<uint32_t>& out, bool& found) {
  found = false;
  V3 nrm;
  for (uint32_t i = 0; i < m; ++i) {
    const V3& A = P[i];
    const V3& B = P[(i + 1) % m];
    nrm.x += (A.y - B.y) * (A.z + B.z);
    nrm.y += (A.z - B.z) * (A.x + B.x);
    nrm.z += (A.x - B.x) * (A.y + B.y);
  }
  const double len = vlen(nrm);
  if (!(len > 0) || !std::isfinite(len)) return Status{};
  nrm = {nrm.x / len, nrm.y / len, nrm.z / len};
  V3 ax;
  if (std::fabs(nrm.x) <= std::fabs(nrm.y) && std::fabs(nrm.x) <= std::fabs(nrm.z))
    ax.x = 1;
  else if (std::fabs(nrm.y) <= std::fabs(nrm.z))
    ax.y = 1;
  else
    ax.z = 1;
  V3 u = vcross(nrm, ax);
  const double ul = vlen(u);
  u = {u.x / ul, u.y / ul, u.z / ul};
  const V3 w = vcross(nrm, u);
  Array<double> xy;
  Array<uint32_t> ring;
  if (!xy.resize(2 * size_t(m)) || !ring.resize(m)) return oom();
  for (uint32_t i = 0; i < m; ++i) {
    xy[2 * i] = vdot(P[i], u);
    xy[2 * i + 1] = vdot(P[i], w);
    ring[i] = i;
  }
  auto cross = [&](uint32_t i, uint32_t j, uint32_t k) {
    return (xy[2 * j] - xy[2 * i]) * (xy[2 * k + 1] - xy[2 * i + 1]) -
           (xy[2 * j + 1] - xy[2 * i + 1]) * (xy[2 * k] - xy[2 * i]);
  };
  auto usable = [&](uint32_t i, uint32_t k) {
    const uint32_t lo = std::min(i, k), hi = std::max(i, k);
    return (lo == 0 && hi == m - 1) || hi == lo + 1 || !forbidden(lo, hi);
  };
  uint32_t n = m;
  while (n > 3) {
    uint32_t pick = kInvalid, fallback = kInvalid;
    for (uint32_t r = 0; r < n && pick == kInvalid; ++r) {
      const uint32_t i = ring[(r + n - 1) % n], j = ring[r], k = ring[(r + 1) % n];
      if (!usable(i, k)) continue;
      if (fallback == kInvalid) fallback = r;
      if (!(cross(i, j, k) > 0)) continue;
      bool inside = false;
      for (uint32_t q = 0; q < n && !inside; ++q) {
        const uint32_t o = ring[q];
        if (o == i || o == j || o == k) continue;
        if (cross(i, j, o) >= 0 && cross(j, k, o) >= 0 && cross(k, i, o) >= 0) inside = true;
      }
      if (!inside) pick = r;
    }
    if (pick == kInvalid) pick = fallback;
    if (pick == kInvalid) return Status{};
    const uint32_t i = ring[(pick + n - 1) % n], j = ring[pick], k = ring[(pick + 1) % n];
    if (!out.push_back(i) || !out.push_back(j) || !out.push_back(k)) return oom();
    for (uint32_t r = pick; r + 1 < n; ++r) ring[r] = ring[r + 1];
    --n;
  }
  if (!out.push_back(ring[0]) || !out.push_back(ring[1]) || !out.push_back(ring[2])) return oom();
  found = true;
  return Status{};
}

// ------------------------------------------------------------------------- one item
struct ItemState {
  uint32_t first = 0, n = 0;  // the loop's positions in loopHalfedges
  Array<uint32_t> nbTri;      // per loop edge: the mesh triangle across it
  double target = 0;          // mean length of the loop's edges
  Box box;                    // of the loop's vertices
};

// The position of patch vertex v.
inline const float* patchPos(const Filler& F, const Patch& p, uint32_t v) {
  return v < p.base ? F.pos(v) : p.newPos.data() + 3 * size_t(v - p.base);
}
inline V3 patchV(const Filler& F, const Patch& p, uint32_t v) { return vof(patchPos(F, p, v)); }

// Neighbours across the sides of the patch's triangles. Inner sides pair by their
// undirected edge; the loop's edges are recognised by their (from, to) loop positions.
Status linkPatch(Patch& p, const Array<uint32_t>& sideLoopEdge) {
  const uint32_t nt = p.nTris();
  if (!p.nbr.assign(size_t(nt) * 3, std::numeric_limits<int64_t>::min())) return oom();
  Array<uint64_t> keys;
  Array<uint64_t> sides;
  for (uint32_t s = 0; s < 3 * nt; ++s) {
    if (sideLoopEdge[s] != kInvalid) {
      p.nbr[s] = -1 - int64_t(sideLoopEdge[s]);
      continue;
    }
    if (!keys.push_back(edgeKey(p.tris[s], p.tris[3 * (s / 3) + nextC(s % 3)])) || !sides.push_back(s)) return oom();
  }
  Array<uint32_t> order;
  if (!order.resize(keys.size())) return oom();
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return keys[a] != keys[b] ? keys[a] < keys[b] : sides[a] < sides[b]; });
  for (size_t i = 0; i + 1 < order.size(); ++i)
    if (keys[order[i]] == keys[order[i + 1]] && (i + 2 >= order.size() || keys[order[i + 2]] != keys[order[i]]) &&
        (i == 0 || keys[order[i - 1]] != keys[order[i]])) {
      const uint32_t a = uint32_t(sides[order[i]]), b = uint32_t(sides[order[i + 1]]);
      if (p.tris[a] == p.tris[b]) continue;  // both the same way: inconsistent
      p.nbr[a] = b / 3;
      p.nbr[b] = a / 3;
    }
  // A side left unpaired (an inner edge used once, twice the same way, or more than twice)
  // keeps INT64_MIN: the check reports it.
  return Status{};
}

// Circulates around patch vertex x (from triangle t0) and says whether the patch has edge x-y.
bool patchHasEdge(const Patch& p, uint32_t t0, uint32_t x, uint32_t y) {
  auto has = [&](uint32_t t) {
    const uint32_t* C = p.tris.data() + 3 * size_t(t);
    return C[0] == y || C[1] == y || C[2] == y;
  };
  auto cornerOf = [&](uint32_t t) {
    for (uint32_t c = 0; c < 3; ++c)
      if (p.tris[3 * size_t(t) + c] == x) return c;
    return 3u;
  };
  for (int dir = 0; dir < 2; ++dir) {
    uint32_t t = t0;
    for (uint32_t steps = 0; steps < p.nTris() + 1; ++steps) {
      if (has(t)) return true;
      const uint32_t c = cornerOf(t);
      if (c == 3) break;
      const int64_t nb = p.nbr[3 * size_t(t) + (dir == 0 ? c : prevC(c))];
      if (nb < 0) break;
      t = uint32_t(nb);
      if (t == t0) return false;
    }
  }
  return false;
}

// Liepa's refinement of the patch: centroid splits where the scale allows, then Delaunay
// flips of the inner edges.
// nbNormal[i]: the unit normal of the mesh triangle across the loop's edge i.
// meshVtri: per mesh vertex, kInvalid (and so again on return); a patch triangle using
// each loop vertex while refining.
Status refine(const Filler& F, Patch& p, double target, const Array<V3>& nbNormal, Array<uint32_t>& meshVtri) {
  auto scaleOf = [&](uint32_t v) { return v < p.base ? target : p.newScale[v - p.base]; };
  auto vtriOf = [&](uint32_t v, uint32_t t) { (v >= p.base ? p.vtri[v - p.base] : meshVtri[v]) = t; };
  auto anyTri = [&](uint32_t v) { return v >= p.base ? p.vtri[v - p.base] : meshVtri[v]; };
  for (uint32_t t = 0; t < p.nTris(); ++t)
    for (uint32_t c = 0; c < 3; ++c) vtriOf(p.tris[3 * size_t(t) + c], t);
  struct Reset {
    Patch& p;
    Array<uint32_t>& meshVtri;
    ~Reset() {
      for (uint32_t v : p.tris)
        if (v < p.base) meshVtri[v] = kInvalid;
    }
  } reset{p, meshVtri};
  // The angle at corner c of triangle t.
  auto angleAt = [&](uint32_t t, uint32_t c) {
    const V3 a = patchV(F, p, p.tris[3 * size_t(t) + c]);
    const V3 b = patchV(F, p, p.tris[3 * size_t(t) + nextC(c)]);
    const V3 d = patchV(F, p, p.tris[3 * size_t(t) + prevC(c)]);
    const V3 u = vsub(b, a), w = vsub(d, a);
    return std::atan2(vlen(vcross(u, w)), vdot(u, w));
  };
  auto flipIfNotDelaunay = [&](uint32_t t1, uint32_t c1) -> bool {
    const int64_t nb = p.nbr[3 * size_t(t1) + c1];
    if (nb < 0) return false;
    const uint32_t t2 = uint32_t(nb);
    const uint32_t a = p.tris[3 * size_t(t1) + c1], b = p.tris[3 * size_t(t1) + nextC(c1)];
    uint32_t c2 = 3;
    for (uint32_t c = 0; c < 3; ++c)
      if (p.tris[3 * size_t(t2) + c] == b && p.tris[3 * size_t(t2) + nextC(c)] == a) c2 = c;
    if (c2 == 3) return false;
    const uint32_t oc1 = prevC(c1), oc2 = prevC(c2);
    const uint32_t c = p.tris[3 * size_t(t1) + oc1], d = p.tris[3 * size_t(t2) + oc2];
    if (c == d) return false;
    if (!(angleAt(t1, oc1) + angleAt(t2, oc2) > 3.141592653589793 + 1e-12)) return false;
    // The flipped pair must keep the orientation (both new normals agree with the old
    // ones) and the edge c-d must not exist.
    const V3 A = patchV(F, p, a), B = patchV(F, p, b), C = patchV(F, p, c), D = patchV(F, p, d);
    const V3 n0 = vcross(vsub(B, A), vsub(C, A)), n1 = vcross(vsub(A, B), vsub(D, B));
    const V3 m0 = vcross(vsub(A, C), vsub(D, C)), m1 = vcross(vsub(B, D), vsub(C, D));
    const V3 avg = {n0.x + n1.x, n0.y + n1.y, n0.z + n1.z};
    if (!(vdot(m0, avg) > 0) || !(vdot(m1, avg) > 0)) return false;
    // Nor may it fold a triangle over the mesh across a loop edge (the relaxation is for
    // nearly flat patches; on a curved one a flip can turn a rim triangle too far).
    auto foldsAt = [&](const V3& n, int64_t across) {
      return across < 0 && !(vdot(n, nbNormal[size_t(-1 - across)]) > 0);
    };
    {
      const int64_t nCA0 = p.nbr[3 * size_t(t1) + oc1], nAD0 = p.nbr[3 * size_t(t2) + nextC(c2)];
      const int64_t nDB0 = p.nbr[3 * size_t(t2) + oc2], nBC0 = p.nbr[3 * size_t(t1) + nextC(c1)];
      if (foldsAt(m0, nCA0) || foldsAt(m0, nAD0) || foldsAt(m1, nDB0) || foldsAt(m1, nBC0)) return false;
    }
    if (c < p.base && d < p.base && F.edgeExists(c, d)) return false;
    const uint32_t tc = anyTri(c);
    if (tc != kInvalid && patchHasEdge(p, tc, c, d)) return false;
    // (a, b, c) + (b, a, d) -> (c, a, d) + (d, b, c).
    const int64_t nBC = p.nbr[3 * size_t(t1) + nextC(c1)], nCA = p.nbr[3 * size_t(t1) + oc1];
    const int64_t nAD = p.nbr[3 * size_t(t2) + nextC(c2)], nDB = p.nbr[3 * size_t(t2) + oc2];
    uint32_t* T1 = p.tris.data() + 3 * size_t(t1);
    uint32_t* T2 = p.tris.data() + 3 * size_t(t2);
    T1[0] = c, T1[1] = a, T1[2] = d;
    T2[0] = d, T2[1] = b, T2[2] = c;
    int64_t* N1 = p.nbr.data() + 3 * size_t(t1);
    int64_t* N2 = p.nbr.data() + 3 * size_t(t2);
    N1[0] = nCA, N1[1] = nAD, N1[2] = int64_t(t2);
    N2[0] = nDB, N2[1] = nBC, N2[2] = int64_t(t1);
    auto repoint = [&](int64_t nbT, uint32_t from, uint32_t to) {
      if (nbT < 0) return;
      for (uint32_t k = 0; k < 3; ++k)
        if (p.nbr[3 * size_t(nbT) + k] == int64_t(from)) p.nbr[3 * size_t(nbT) + k] = to;
    };
    repoint(nAD, t2, t1);
    repoint(nBC, t1, t2);
    vtriOf(a, t1), vtriOf(c, t1), vtriOf(d, t1), vtriOf(b, t2);
    return true;
  };
  for (int round = 0; round < kRefineRounds; ++round) {
    bool split = false;
    const uint32_t nt = p.nTris();
    for (uint32_t t = 0; t < nt; ++t) {
      if (p.nTris() + 2 > kMaxPatchTriangles) break;
      const uint32_t a = p.tris[3 * size_t(t)], b = p.tris[3 * size_t(t) + 1], c = p.tris[3 * size_t(t) + 2];
      const V3 A = patchV(F, p, a), B = patchV(F, p, b), C = patchV(F, p, c);
      const V3 m = {(A.x + B.x + C.x) / 3, (A.y + B.y + C.y) / 3, (A.z + B.z + C.z) / 3};
      const double sm = (scaleOf(a) + scaleOf(b) + scaleOf(c)) / 3;
      bool ok = true;
      const V3* corners[3] = {&A, &B, &C};
      const uint32_t ids[3] = {a, b, c};
      for (int k = 0; k < 3 && ok; ++k) {
        const double d = kAlpha * vlen(vsub(m, *corners[k]));
        if (!(d > sm && d > scaleOf(ids[k]))) ok = false;
      }
      if (!ok) continue;
      const float pm[3] = {float(m.x), float(m.y), float(m.z)};
      if (!std::isfinite(pm[0]) || !std::isfinite(pm[1]) || !std::isfinite(pm[2])) continue;
      const uint32_t v = p.base + p.nNew();
      if (!p.newPos.push_back(pm[0]) || !p.newPos.push_back(pm[1]) || !p.newPos.push_back(pm[2]) ||
          !p.newScale.push_back(sm) || !p.vtri.push_back(t))
        return oom();
      const uint32_t t1 = p.nTris(), t2 = t1 + 1;
      const int64_t nAB = p.nbr[3 * size_t(t)], nBC = p.nbr[3 * size_t(t) + 1], nCA = p.nbr[3 * size_t(t) + 2];
      // t = (a, b, v), t1 = (b, c, v), t2 = (c, a, v).
      p.tris[3 * size_t(t) + 2] = v;
      if (!p.tris.push_back(b) || !p.tris.push_back(c) || !p.tris.push_back(v) || !p.tris.push_back(c) ||
          !p.tris.push_back(a) || !p.tris.push_back(v))
        return oom();
      p.nbr[3 * size_t(t) + 1] = t1;
      p.nbr[3 * size_t(t) + 2] = t2;
      if (!p.nbr.push_back(nBC) || !p.nbr.push_back(t2) || !p.nbr.push_back(t) || !p.nbr.push_back(nCA) ||
          !p.nbr.push_back(t) || !p.nbr.push_back(t1))
        return oom();
      auto repoint = [&](int64_t nbT, uint32_t to) {
        if (nbT < 0) return;
        for (uint32_t k = 0; k < 3; ++k)
          if (p.nbr[3 * size_t(nbT) + k] == int64_t(t)) {
            // The side of nbT that faces the old triangle's side now faced by `to`.
            const uint32_t x = p.tris[3 * size_t(nbT) + k], y = p.tris[3 * size_t(nbT) + nextC(k)];
            const uint32_t* T = p.tris.data() + 3 * size_t(to);
            bool facesTo = false;
            for (uint32_t j = 0; j < 3; ++j)
              if (T[j] == y && T[nextC(j)] == x) facesTo = true;
            if (facesTo) p.nbr[3 * size_t(nbT) + k] = to;
          }
      };
      repoint(nBC, t1);
      repoint(nCA, t2);
      (void)nAB;
      vtriOf(c, t1);
      split = true;
    }
    if (!split) break;
    for (int pass = 0; pass < kRelaxPasses; ++pass) {
      bool flipped = false;
      for (uint32_t t = 0; t < p.nTris(); ++t)
        for (uint32_t c = 0; c < 3; ++c)
          if (p.nbr[3 * size_t(t) + c] > int64_t(t) && flipIfNotDelaunay(t, c)) flipped = true;
      if (!flipped) break;
    }
  }
  return Status{};
}

// Umbrella smoothing of the new vertices (the loop's vertices stay): each moves to the mean
// of its neighbours, all at once, kFairIterations times.
Status fair(const Filler& F, Patch& p) {
  const uint32_t nn = p.nNew();
  if (nn == 0) return Status{};
  Array<double> cur, sum;
  Array<uint32_t> count;
  if (!cur.resize(3 * size_t(nn)) || !sum.resize(3 * size_t(nn)) || !count.resize(nn)) return oom();
  for (size_t i = 0; i < 3 * size_t(nn); ++i) cur[i] = p.newPos[i];
  auto at = [&](uint32_t v, int k) { return v < p.base ? double(F.pos(v)[k]) : cur[3 * size_t(v - p.base) + k]; };
  for (int it = 0; it < kFairIterations; ++it) {
    for (size_t i = 0; i < 3 * size_t(nn); ++i) sum[i] = 0;
    for (uint32_t i = 0; i < nn; ++i) count[i] = 0;
    for (uint32_t t = 0; t < p.nTris(); ++t)
      for (uint32_t c = 0; c < 3; ++c) {
        const uint32_t v = p.tris[3 * size_t(t) + c];
        if (v < p.base) continue;
        const uint32_t a = p.tris[3 * size_t(t) + nextC(c)], b = p.tris[3 * size_t(t) + prevC(c)];
        for (int k = 0; k < 3; ++k) sum[3 * size_t(v - p.base) + k] += at(a, k) + at(b, k);
        count[v - p.base] += 2;
      }
    for (uint32_t i = 0; i < nn; ++i)
      if (count[i] > 0)
        for (int k = 0; k < 3; ++k) cur[3 * size_t(i) + k] = sum[3 * size_t(i) + k] / count[i];
  }
  for (size_t i = 0; i < 3 * size_t(nn); ++i) {
    const float f = float(cur[i]);
    if (std::isfinite(f)) p.newPos[i] = f;
  }
  return Status{};
}

// The exact checks of a candidate patch: "" when it may be applied, else why not.
Status check(const Filler& F, const ItemState& it, const Patch& p, std::string& why) {
  why.clear();
  const uint32_t nt = p.nTris();
  const uint32_t* T = F.em.triangles().data();
  auto P = [&](uint32_t v) { return patchPos(F, p, v); };
  // Zero area.
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t* C = p.tris.data() + 3 * size_t(t);
    if (pred::collinear(P(C[0]), P(C[1]), P(C[2]))) {
      why = text("a new triangle (%u, %u, %u) would have zero area (collinear corners)", C[0], C[1], C[2]);
      return Status{};
    }
  }
  // Inner edges: paired, unique, new.
  Array<uint64_t> inner;
  for (uint32_t s = 0; s < 3 * nt; ++s) {
    const int64_t nb = p.nbr[s];
    const uint32_t a = p.tris[s], b = p.tris[3 * (s / 3) + nextC(s % 3)];
    if (nb == std::numeric_limits<int64_t>::min()) {
      why = text("the fill would make edge %u-%u non-manifold or inconsistent (new triangles do not pair on it)", a, b);
      return Status{};
    }
    if (nb < 0 || uint32_t(nb) < s / 3) continue;
    if (!inner.push_back(edgeKey(a, b))) return oom();
  }
  std::sort(inner.begin(), inner.end());
  for (size_t i = 0; i < inner.size(); ++i) {
    const uint32_t a = uint32_t(inner[i] >> 32), b = uint32_t(inner[i]);
    if ((i > 0 && inner[i] == inner[i - 1]) || (a < p.base && b < p.base && F.edgeExists(a, b))) {
      why = text("a new inner edge %u-%u would land on an existing edge (non-manifold)", a, b);
      return Status{};
    }
  }
  // Fold-over across the loop's edges. A patch of one triangle (a hole of three edges) is
  // the only fill there is, so the angle has nothing to choose against: it is the file's
  // missing facet, at a sharp edge as often as not (a tetrahedron's faces turn by 109
  // degrees). It folds over only onto a neighbour: coplanar on one side, a crossing (refused
  // below), or the loop of a lone triangle, whose fill would be that triangle reversed (the
  // angle test below refuses it, at its first edge).
  bool angles = nt > 1;
  if (nt == 1 && p.nbr[0] < 0 && p.nbr[1] < 0 && p.nbr[2] < 0) {
    const uint32_t m = it.nbTri[uint32_t(-1 - p.nbr[0])];
    angles = it.nbTri[uint32_t(-1 - p.nbr[1])] == m && it.nbTri[uint32_t(-1 - p.nbr[2])] == m;
  }
  for (uint32_t s = 0; angles && s < 3 * nt; ++s) {
    const int64_t nb = p.nbr[s];
    if (nb >= 0) continue;
    const uint32_t i = uint32_t(-1 - nb), m = it.nbTri[i];
    const uint32_t* C = p.tris.data() + 3 * size_t(s / 3);
    const uint32_t* M = T + 3 * size_t(m);
    if (pred::normalsDot(F.pos(M[0]), F.pos(M[1]), F.pos(M[2]), P(C[0]), P(C[1]), P(C[2])) < 0) {
      why = text("the fill would fold over at edge %u-%u (more than 90 degrees against triangle %u)", p.tris[s],
                 p.tris[3 * (s / 3) + nextC(s % 3)], m);
      return Status{};
    }
  }
  // Area.
  if (F.ctx.options.maxHoleArea > 0) {
    double area = 0;
    for (uint32_t t = 0; t < nt; ++t) {
      const uint32_t* C = p.tris.data() + 3 * size_t(t);
      area += triArea(vof(P(C[0])), vof(P(C[1])), vof(P(C[2])));
    }
    if (area > F.ctx.options.maxHoleArea) {
      why = text("the fill's area %.6g is over the limit of %.6g (maxHoleArea)", area, F.ctx.options.maxHoleArea);
      return Status{};
    }
  }
  // Crossings.
  Array<Box> boxes;
  if (!boxes.resize(nt)) return oom();
  Box all = emptyBox();
  for (uint32_t t = 0; t < nt; ++t) {
    Box b = emptyBox();
    for (uint32_t c = 0; c < 3; ++c) extend(b, P(p.tris[3 * size_t(t) + c]));
    boxes[t] = b;
    merge(all, b);
  }
  auto triOfPatch = [&](uint32_t t) {
    Tri x;
    for (int c = 0; c < 3; ++c) {
      x.v[c] = p.tris[3 * size_t(t) + c];
      x.p[c] = P(x.v[c]);
    }
    return x;
  };
  auto triOfMesh = [&](uint32_t t) {
    Tri x;
    for (int c = 0; c < 3; ++c) {
      x.v[c] = T[3 * size_t(t) + c];
      x.p[c] = F.pos(x.v[c]);
    }
    return x;
  };
  double point[3];
  auto meets = [&](const Tri& a, uint32_t m) {
    if (geometry_detail::trianglePairTest(a, triOfMesh(m), point) < 0) return false;
    why =
        text("the fill would cross the mesh (new triangle (%u, %u, %u) meets triangle %u)", a.v[0], a.v[1], a.v[2], m);
    return true;
  };
  bool inLoopBox = true;
  for (int k = 0; k < 3; ++k) inLoopBox = inLoopBox && it.box.lo[k] <= all.lo[k] && all.hi[k] <= it.box.hi[k];
  if (inLoopBox) {
    for (uint32_t t = 0; t < nt && why.empty(); ++t) {
      const Tri a = triOfPatch(t);
      F.bvh.query(boxes[t], [&](uint32_t m) { return !meets(a, m); });
    }
  } else {
    // The hierarchy holds the triangles near the loops' boxes, and a fill lies in its
    // loop's box; should one not, every triangle is tested (O(n) for this item).
    for (uint32_t m = 0; m < F.nTrianglesAtStart && why.empty(); ++m) {
      if (!F.triangleUsable(m)) continue;
      const uint32_t* M = T + 3 * size_t(m);
      if (pred::collinear(F.pos(M[0]), F.pos(M[1]), F.pos(M[2]))) continue;
      Box bm = emptyBox();
      for (int c = 0; c < 3; ++c) extend(bm, F.pos(M[c]));
      if (!overlaps(bm, all)) continue;
      for (uint32_t t = 0; t < nt && why.empty(); ++t)
        if (overlaps(bm, boxes[t])) meets(triOfPatch(t), m);
    }
  }
  if (!why.empty()) return Status{};
  // Earlier fills of this step.
  for (uint32_t item = 0; item + 1 < F.addedItemOffsets.size() && why.empty(); ++item) {
    if (!overlaps(F.addedItemBoxes[item], all)) continue;
    for (uint32_t i = F.addedItemOffsets[item]; i < F.addedItemOffsets[item + 1] && why.empty(); ++i) {
      const uint32_t m = F.addedTriangles[i];
      const Tri b = triOfMesh(m);
      Box bb = emptyBox();
      for (int c = 0; c < 3; ++c) extend(bb, b.p[c]);
      for (uint32_t t = 0; t < nt && why.empty(); ++t)
        if (overlaps(boxes[t], bb) && geometry_detail::trianglePairTest(triOfPatch(t), b, point) >= 0)
          why = text("the fill would cross an earlier fill (triangle %u)", m);
    }
  }
  if (!why.empty()) return Status{};
  // Its own triangles, pairwise (sorted by the boxes' low x, swept).
  Array<uint32_t> order;
  if (!order.resize(nt)) return oom();
  for (uint32_t t = 0; t < nt; ++t) order[t] = t;
  std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) {
    return boxes[x].lo[0] != boxes[y].lo[0] ? boxes[x].lo[0] < boxes[y].lo[0] : x < y;
  });
  for (uint32_t i = 0; i < nt && why.empty(); ++i) {
    const uint32_t x = order[i];
    for (uint32_t j = i + 1; j < nt; ++j) {
      const uint32_t y = order[j];
      if (boxes[y].lo[0] > boxes[x].hi[0]) break;
      if (!overlaps(boxes[x], boxes[y])) continue;
      if (geometry_detail::trianglePairTest(triOfPatch(x), triOfPatch(y), point) >= 0) {
        why = text("the fill would cross itself (new triangles (%u, %u, %u) and (%u, %u, %u))", p.tris[3 * x],
                   p.tris[3 * x + 1], p.tris[3 * x + 2], p.tris[3 * y], p.tris[3 * y + 1], p.tris[3 * y + 2]);
        break;
      }
    }
  }
  return Status{};
}

Status Filler::run() {
  Status s = init();
  if (!s.ok()) return s;
  for (uint32_t h = 0; h + 1 < loopOffsets.size(); ++h) {
    s = fillItem(h);
    if (!s.ok()) return s;
  }
  return Status{};
}

Status Filler::fillItem(uint32_t h) {
  ItemState it;
  it.first = loopOffsets[h];
  it.n = loopOffsets[h + 1] - loopOffsets[h];
  const uint32_t* he = loopHalfedges.data() + it.first;
  const uint32_t* lv = loopVerts.data() + it.first;
  // The item's box comes from the vertices: begin() would read a loop's from em.loops(),
  // which an earlier fill renumbered (and reading it would renumber the loops, O(n), per item).
  std::vector<uint32_t> verts(lv, lv + it.n);
  RepairItem& item = ctx.begin(text("fill hole %u (%u edges)", h, it.n), {}, std::move(verts));
  item.loops.push_back(h);
  if (ctx.excluded()) return Status{};
  if (loopIsSeam[h]) {
    ctx.skip(
        "a seam: the loop has cut sides (non-manifold or inconsistent edges); filling it would make non-manifold "
        "edges");
    return Status{};
  }
  if (it.n > ctx.options.maxHoleEdges) {
    ctx.skip(text("%u edges, over the limit of %u (maxHoleEdges)", it.n, ctx.options.maxHoleEdges));
    return Status{};
  }
  if (ctx.options.maxHolePerimeter > 0 && loopPerimeter[h] > ctx.options.maxHolePerimeter) {
    ctx.skip(text("perimeter %.6g, over the limit of %.6g (maxHolePerimeter)", loopPerimeter[h],
                  ctx.options.maxHolePerimeter));
    return Status{};
  }
  // The loop must be as the step found it (an earlier fill may have closed or re-linked it).
  const Array<uint32_t>& vert = em.vert();
  const Array<uint32_t>& next = em.next();
  for (uint32_t i = 0; i < it.n; ++i) {
    const uint32_t e = he[i];
    if (!em.halfedgeAlive(e) || !em.isBoundary(e) || vert[e] != lv[i] || next[e] != he[(i + 1) % it.n]) {
      ctx.skip("an earlier fill of this step changed the loop");
      return Status{};
    }
  }
  // The mesh triangle across each loop edge, and the target length.
  if (!it.nbTri.resize(it.n)) return oom();
  double perim = 0;
  for (uint32_t i = 0; i < it.n; ++i) {
    const uint32_t t = em.faceWords()[he[i] ^ 1u];
    if ((t & kLoopFaceBit) != 0 || !em.triangleAlive(t)) {
      ctx.skip("a seam: a loop edge has no triangle across it");
      return Status{};
    }
    it.nbTri[i] = t;
    perim += vlen(vsub(vof(pos(lv[i])), vof(pos(lv[(i + 1) % it.n]))));
  }
  it.target = perim / it.n;
  it.box = emptyBox();
  for (uint32_t i = 0; i < it.n; ++i) extend(it.box, pos(lv[i]));
  // Cut at repeated vertices into simple parts (a stack of loop positions).
  Parts parts;
  if (!parts.offsets.push_back(0)) return oom();
  {
    Array<uint32_t> stack;
    if (++epoch == 0) {
      for (uint32_t v = 0; v < stamp.size(); ++v) stamp[v] = 0;
      epoch = 1;
    }
    // stamp == epoch: on the stack (positions found by a search back when a vertex repeats).
    auto emit = [&](size_t from) {
      for (size_t i = from; i < stack.size(); ++i) {
        if (!parts.pos.push_back(stack[i])) return false;
        stamp[lv[stack[i]]] = epoch - 1;
      }
      stack.shrink(from);
      return parts.offsets.push_back(uint32_t(parts.pos.size()));
    };
    for (uint32_t i = 0; i < it.n; ++i) {
      const uint32_t v = lv[i];
      if (stamp[v] == epoch) {
        size_t from = stack.size();
        while (from > 0 && lv[stack[from - 1]] != v) --from;
        if (!emit(from - 1)) return oom();
      }
      stamp[v] = epoch;
      if (!stack.push_back(i)) return oom();
    }
    if (!emit(0)) return oom();
    ++epoch;  // leaves no vertex marked
    // A part of two edges (u -> w -> u) needs two opposite boundary sides on one edge, which
    // only an edge with cut sides has (a seam, skipped above): a guard.
    for (uint32_t p = 0; p + 1 < parts.offsets.size(); ++p) {
      const uint32_t m = parts.offsets[p + 1] - parts.offsets[p];
      if (m < 3) {
        ctx.skip(
            text("the loop passes vertex %u more than once, with a part of %u edges between: no "
                 "triangle can fill it",
                 lv[parts.pos[parts.offsets[p]]], m));
        return Status{};
      }
    }
  }
  // Triangulate each part: by minimum weight up to the cap, by ear clipping above. When a
  // patch with ear-clipped parts fails the checks and those parts are at most
  // kMinWeightFallbackCap long, they are triangulated by minimum weight after all (slower,
  // and much better on curved holes).
  Patch plain;
  plain.base = em.nVertices();
  bool byMinWeight = false, byEars = false, fellBack = false;
  std::string why;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const uint32_t cap = attempt == 0 ? kMinWeightCap : kMinWeightFallbackCap;
    fellBack = attempt == 1;
    plain.tris.clear();
    byMinWeight = byEars = false;
    Array<uint32_t> sideLoopEdge;
    for (uint32_t p = 0; p + 1 < parts.offsets.size(); ++p) {
      const uint32_t* P = parts.pos.data() + parts.offsets[p];
      const uint32_t m = parts.offsets[p + 1] - parts.offsets[p];
      Array<V3> pts, nb;
      if (!pts.resize(m) || !nb.resize(m)) return oom();
      for (uint32_t i = 0; i < m; ++i) {
        pts[i] = vof(pos(lv[P[i]]));
        const uint32_t* M = em.triangles().data() + 3 * size_t(it.nbTri[P[i]]);
        nb[i] = unitNormal(vof(pos(M[0])), vof(pos(M[1])), vof(pos(M[2])));
      }
      auto forbidden = [&](uint32_t i, uint32_t j) { return edgeExists(lv[P[i]], lv[P[j]]); };
      Array<uint32_t> local;
      bool found = false;
      Status s = m <= cap ? minWeight(m, pts.data(), nb.data(), forbidden, local, found)
                          : earClip(m, pts.data(), forbidden, local, found);
      if (!s.ok()) return s;
      (m <= cap ? byMinWeight : byEars) = true;
      if (!found) {
        ctx.skip(m <= cap ? "every triangulation would put a new inner edge on an existing edge (non-manifold)"
                          : "ear clipping found no triangulation (the loop has no best-fitting plane, or every ear "
                            "would put a new inner edge on an existing edge)");
        return Status{};
      }
      for (size_t k = 0; k < local.size(); k += 3)
        for (uint32_t c = 0; c < 3; ++c) {
          const uint32_t i = local[k + c], j = local[k + nextC(c)];
          if (!plain.tris.push_back(lv[P[i]])) return oom();
          if (!sideLoopEdge.push_back(j == (i + 1) % m ? P[i] : kInvalid)) return oom();
        }
    }
    Status s = linkPatch(plain, sideLoopEdge);
    if (!s.ok()) return s;
    s = check(*this, it, plain, why);
    if (!s.ok()) return s;
    if (why.empty() || !byEars) break;
    bool fallbackFits = true;
    for (uint32_t p = 0; p + 1 < parts.offsets.size(); ++p)
      fallbackFits = fallbackFits && parts.offsets[p + 1] - parts.offsets[p] <= kMinWeightFallbackCap;
    if (!fallbackFits) break;
  }
  if (!why.empty()) {
    ctx.skip(why);
    return Status{};
  }
  Status s;
  // Refine and fair a copy; keep it when it passes the checks too.
  Patch refined;
  Patch* chosen = &plain;
  std::string notRefined;
  if (ctx.options.fillRefine) {
    refined.base = plain.base;
    if (!refined.tris.resize(plain.tris.size()) || !refined.nbr.resize(plain.nbr.size())) return oom();
    std::memcpy(refined.tris.data(), plain.tris.data(), plain.tris.size() * sizeof(uint32_t));
    std::memcpy(refined.nbr.data(), plain.nbr.data(), plain.nbr.size() * sizeof(int64_t));
    Array<V3> nbNormal;
    if (!nbNormal.resize(it.n)) return oom();
    for (uint32_t i = 0; i < it.n; ++i) {
      const uint32_t* M = em.triangles().data() + 3 * size_t(it.nbTri[i]);
      nbNormal[i] = unitNormal(vof(pos(M[0])), vof(pos(M[1])), vof(pos(M[2])));
    }
    s = refine(*this, refined, it.target, nbNormal, meshVtri);
    if (!s.ok()) return s;
    if (ctx.options.fillFair) {
      s = fair(*this, refined);
      if (!s.ok()) return s;
    }
    if (refined.nNew() > 0) {
      s = check(*this, it, refined, why);
      if (!s.ok()) return s;
      if (why.empty())
        chosen = &refined;
      else
        notRefined = why;
    }
  }
  const Patch& patch = *chosen;
  // Apply: the new vertices, then the triangles.
  s = em.reserve(patch.nNew(), patch.nTris());
  if (!s.ok()) return s;
  Array<uint32_t> ids, added;
  if (!ids.resize(patch.nNew()) || !added.reserve(patch.nTris())) return oom();
  for (uint32_t k = 0; k < patch.nNew(); ++k) {
    const float* q = patch.newPos.data() + 3 * size_t(k);
    s = em.addVertex(q[0], q[1], q[2], &ids[k]);
    if (!s.ok()) return s;  // finite positions, reserved: only running out of memory is left
  }
  auto idOf = [&](uint32_t v) { return v < patch.base ? v : ids[v - patch.base]; };
  for (uint32_t t = 0; t < patch.nTris(); ++t) {
    uint32_t out = kInvalid;
    s = em.addTriangle(idOf(patch.tris[3 * size_t(t)]), idOf(patch.tris[3 * size_t(t) + 1]),
                       idOf(patch.tris[3 * size_t(t) + 2]), &out);
    if (!s.ok()) {
      for (size_t k = added.size(); k-- > 0;) {
        Status r = em.removeTriangle(added[k]);
        if (!r.ok()) return r;
      }
      if (s.code != Code::EditRefused && s.code != Code::InvalidArgument) return s;
      ctx.skip("the editor refused a new triangle: " + s.message);
      return Status{};
    }
    (void)added.push_back(out);  // reserved
  }
  // Record the new edges, triangles and box for the later items.
  const size_t before = addedEdges.size();
  for (uint32_t t = 0; t < patch.nTris(); ++t)
    for (uint32_t c = 0; c < 3; ++c)
      if (!addedEdges.push_back(
              edgeKey(idOf(patch.tris[3 * size_t(t) + c]), idOf(patch.tris[3 * size_t(t) + nextC(c)]))))
        return oom();
  std::sort(addedEdges.begin() + before, addedEdges.end());
  std::inplace_merge(addedEdges.begin(), addedEdges.begin() + before, addedEdges.end());
  Box box = emptyBox();
  for (uint32_t t : added) {
    if (!addedTriangles.push_back(t)) return oom();
    for (uint32_t c = 0; c < 3; ++c) extend(box, pos(em.triangles()[3 * size_t(t) + c]));
  }
  if (!addedItemOffsets.push_back(uint32_t(addedTriangles.size())) || !addedItemBoxes.push_back(box)) return oom();
  std::string action = text("fill hole %u (%u edges) with %u triangles", h, it.n, patch.nTris());
  if (patch.nNew() > 0) action += text(" and %u new vertices", patch.nNew());
  action += byMinWeight && byEars ? " (minimum weight and ear clipping"
            : byEars              ? " (ear clipping"
            : fellBack            ? " (minimum weight, as ear clipping failed the checks"
                                  : " (minimum weight";
  if (chosen == &refined)
    action += ctx.options.fillFair ? ", refined and faired)" : ", refined)";
  else if (!notRefined.empty())
    action += "; not refined: " + notRefined + ")";
  else
    action += ")";
  item.action = std::move(action);
  return Status{};
}

}  // namespace

Status runFillHoles(StepContext& ctx) {
  Filler f(ctx);
  return f.run();
}

void setFillCellGridForTesting(bool on) { gFillCellGrid = on; }

}  // namespace repair_detail
}  // namespace stltopo
