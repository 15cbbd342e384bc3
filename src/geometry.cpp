// The exact geometric checks (stltopo/geometry.h): zero-area and duplicate triangles,
// self-intersections through a bounding-volume hierarchy, and shell nesting by ray parity.
//
// Every decision goes through the exact predicates of predicates.h. Constructed points
// (an intersection's "point") are the only floating-point results, and decide nothing.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__wasm_simd128__)
#include <wasm_simd128.h>  // the wasm build compiles this file with -msimd128 (src/CMakeLists.txt)
#endif

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

namespace {}  // namespace

const char* intersectionKindName(IntersectionKind k) {
  switch (k) {
    case IntersectionKind::Crossing: return "crossing";
    case IntersectionKind::Touching: return "touching";
    case IntersectionKind::Coplanar: return "coplanar";
  }
  return "unknown";
}

// ---------------------------------------------------------------------------
// Exact triangle tests. A Tri holds its three welded corner ids and positions; every
// triangle passed here has three distinct, non-collinear corners.

namespace {

using geometry_detail::Tri;

// The axis k along which a triangle projects without collapsing (its normal's coordinate
// k is not zero), and the sign of that coordinate: orient2dIn(k, ...) * sign is then the
// orientation relative to the triangle's own winding.
struct Projection {
  int k;
  int sign;
};

Projection projectionOf(const float* a, const float* b, const float* c) {
  const double ux = double(b[0]) - a[0], uy = double(b[1]) - a[1], uz = double(b[2]) - a[2];
  const double vx = double(c[0]) - a[0], vy = double(c[1]) - a[1], vz = double(c[2]) - a[2];
  const double n[3] = {std::fabs(uy * vz - uz * vy), std::fabs(uz * vx - ux * vz), std::fabs(ux * vy - uy * vx)};
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int x, int y) { return n[x] > n[y]; });
  for (int k : order) {
    int s = pred::normalSign(a, b, c, k);
    if (s != 0) return {k, s};
  }
  return {0, 0};  // collinear: never called so
}

inline int orient2dIn(int k, const float* a, const float* b, const float* c) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  return pred::orient2d(a[i], a[j], b[i], b[j], c[i], c[j]);
}

// Closed 2D segment-segment intersection of coplanar segments (in projection k).
bool segSeg2d(int k, const float* p, const float* q, const float* r, const float* s) {
  const int o1 = orient2dIn(k, p, q, r), o2 = orient2dIn(k, p, q, s);
  const int o3 = orient2dIn(k, r, s, p), o4 = orient2dIn(k, r, s, q);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  auto onSeg = [&](const float* a, const float* b, const float* x) {  // x collinear with ab: within it?
    return std::min(a[i], b[i]) <= x[i] && x[i] <= std::max(a[i], b[i]) && std::min(a[j], b[j]) <= x[j] &&
           x[j] <= std::max(a[j], b[j]);
  };
  if (o1 == 0 && onSeg(p, q, r)) return true;
  if (o2 == 0 && onSeg(p, q, s)) return true;
  if (o3 == 0 && onSeg(r, s, p)) return true;
  if (o4 == 0 && onSeg(r, s, q)) return true;
  return false;
}

// Whether point x (in the triangle's plane) lies in the closed triangle.
bool pointInTri2d(const Projection& pr, const Tri& t, const float* x) {
  for (int e = 0; e < 3; ++e)
    if (orient2dIn(pr.k, t.p[e], t.p[(e + 1) % 3], x) * pr.sign < 0) return false;
  return true;
}

// Closed segment pq against closed triangle t, all in t's plane.
bool segTri2d(const Projection& pr, const Tri& t, const float* p, const float* q) {
  if (pointInTri2d(pr, t, p) || pointInTri2d(pr, t, q)) return true;
  for (int e = 0; e < 3; ++e)
    if (segSeg2d(pr.k, p, q, t.p[e], t.p[(e + 1) % 3])) return true;
  return false;
}

// Closed segment pq against closed triangle t in 3D, with sp and sq the sides of p and q
// of t's plane (orient3d).
bool segTri(const Tri& t, const float* p, const float* q, int sp, int sq) {
  if (sp * sq > 0) return false;
  if (sp == 0 && sq == 0) return segTri2d(projectionOf(t.p[0], t.p[1], t.p[2]), t, p, q);
  // pq meets the plane in one point: is it in the closed triangle? The three signed
  // volumes of the line pq with the sides may not have both strict signs.
  int pos = 0, neg = 0;
  for (int e = 0; e < 3; ++e) {
    int s = pred::orient3d(p, q, t.p[e], t.p[(e + 1) % 3]);
    pos += s > 0;
    neg += s < 0;
  }
  return !(pos && neg);
}

bool segTri(const Tri& t, const float* p, const float* q) {
  return segTri(t, p, q, pred::orient3d(t.p[0], t.p[1], t.p[2], p), pred::orient3d(t.p[0], t.p[1], t.p[2], q));
}

// Closed coplanar triangles (both in one plane): whether they meet. Two disjoint triangles
// in a plane lie strictly on either side of the line of one of their sides (separating
// axes), and meeting ones do not, so they meet exactly when no side line of either one has
// the whole other triangle strictly on its outer side.
bool triTri2d(const Projection& pr, const Tri& a, const Tri& b) {
  const Tri* t[2] = {&a, &b};
  for (int s = 0; s < 2; ++s) {
    const Tri& x = *t[s];
    const Tri& y = *t[1 - s];
    const int sg = s == 0 ? pr.sign : orient2dIn(pr.k, x.p[0], x.p[1], x.p[2]);
    for (int e = 0; e < 3; ++e) {
      bool separated = true;
      for (int i = 0; i < 3 && separated; ++i)
        if (orient2dIn(pr.k, x.p[e], x.p[(e + 1) % 3], y.p[i]) * sg >= 0) separated = false;
      if (separated) return false;
    }
  }
  return true;
}

// Whether the open interiors of two coplanar triangles meet: no side line of either one
// has the whole other triangle on its closed outer side (separating axes).
bool interiorsMeet2d(int k, const Tri& a, const Tri& b) {
  const Tri* t[2] = {&a, &b};
  for (int s = 0; s < 2; ++s) {
    const Tri& x = *t[s];
    const Tri& y = *t[1 - s];
    const int sg = orient2dIn(k, x.p[0], x.p[1], x.p[2]);
    for (int e = 0; e < 3; ++e) {
      bool separated = true;
      for (int i = 0; i < 3 && separated; ++i)
        if (orient2dIn(k, x.p[e], x.p[(e + 1) % 3], y.p[i]) * sg > 0) separated = false;
      if (separated) return false;
    }
  }
  return true;
}

// One point of the intersection of two intersecting triangles, in floating point: the
// mean of the exactly found corners of their intersection (corners of one inside the
// other, sides crossing the other's plane inside it, coplanar sides crossing), leaving
// out shared corners when anything else was found.
void intersectionPoint(const Tri& a, const Tri& b, bool coplanar, int k, double out[3]) {
  double sum[3] = {0, 0, 0}, shared[3] = {0, 0, 0};
  int n = 0, nShared = 0;
  auto addPoint = [&](double x, double y, double z, bool isShared) {
    if (isShared) {
      shared[0] += x, shared[1] += y, shared[2] += z, ++nShared;
    } else {
      sum[0] += x, sum[1] += y, sum[2] += z, ++n;
    }
  };
  auto isSharedVertex = [](const Tri& t, uint32_t v) { return t.v[0] == v || t.v[1] == v || t.v[2] == v; };
  const Tri* tris[2] = {&a, &b};
  for (int s = 0; s < 2; ++s) {
    const Tri& x = *tris[s];
    const Tri& y = *tris[1 - s];
    const Projection py =
        coplanar ? Projection{k, orient2dIn(k, y.p[0], y.p[1], y.p[2])} : projectionOf(y.p[0], y.p[1], y.p[2]);
    int o[3];
    for (int i = 0; i < 3; ++i) o[i] = pred::orient3d(y.p[0], y.p[1], y.p[2], x.p[i]);
    for (int i = 0; i < 3; ++i)  // corners of x in y
      if (o[i] == 0 && pointInTri2d(py, y, x.p[i]))
        addPoint(x.p[i][0], x.p[i][1], x.p[i][2], isSharedVertex(y, x.v[i]));
    if (!coplanar) {
      for (int i = 0; i < 3; ++i) {  // sides of x crossing y's plane inside y
        const int j = (i + 1) % 3;
        if (o[i] * o[j] >= 0) continue;
        if (!segTri(y, x.p[i], x.p[j])) continue;
        const double di = pred::orient3dApprox(y.p[0], y.p[1], y.p[2], x.p[i]);
        const double dj = pred::orient3dApprox(y.p[0], y.p[1], y.p[2], x.p[j]);
        double t = di / (di - dj);
        if (!(t >= 0 && t <= 1)) t = 0.5;
        addPoint(x.p[i][0] + t * (double(x.p[j][0]) - x.p[i][0]), x.p[i][1] + t * (double(x.p[j][1]) - x.p[i][1]),
                 x.p[i][2] + t * (double(x.p[j][2]) - x.p[i][2]), false);
      }
    }
  }
  if (coplanar) {  // sides crossing sides
    const int i0 = (k + 1) % 3, j0 = (k + 2) % 3;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const float *p = a.p[i], *q = a.p[(i + 1) % 3], *r = b.p[j], *s = b.p[(j + 1) % 3];
        if (orient2dIn(k, p, q, r) * orient2dIn(k, p, q, s) >= 0) continue;
        if (orient2dIn(k, r, s, p) * orient2dIn(k, r, s, q) >= 0) continue;
        const double d1x = double(q[i0]) - p[i0], d1y = double(q[j0]) - p[j0];
        const double d2x = double(s[i0]) - r[i0], d2y = double(s[j0]) - r[j0];
        const double den = d1x * d2y - d1y * d2x;
        double t = den != 0 ? ((double(r[i0]) - p[i0]) * d2y - (double(r[j0]) - p[j0]) * d2x) / den : 0.5;
        if (!(t >= 0 && t <= 1)) t = 0.5;
        addPoint(p[0] + t * (double(q[0]) - p[0]), p[1] + t * (double(q[1]) - p[1]), p[2] + t * (double(q[2]) - p[2]),
                 false);
      }
  }
  if (n == 0) {
    std::memcpy(sum, shared, sizeof sum);
    n = nShared;
  }
  for (int c = 0; c < 3; ++c) out[c] = n ? sum[c] / n : double(a.p[0][c]);
}

// Whether two closed triangles with no corner in the other's plane, each with corners on
// both sides of the other's plane, meet (after Guigue and Devillers, "Faster triangle-triangle
// intersection tests", 2003, with exact signs): each meets the other's plane in a segment on
// the line L where the planes meet, and the two segments overlap unless one of two
// orientations says that one lies wholly before the other along L. (The signs were checked
// against the side-by-side test on random integer triangles, exactly; the tests compare
// the pass with an integer brute force.) sa: a's corners against
// b's plane, sb: b's against a's (orient3d signs, none 0).
bool strictStraddlesMeet(const Tri& a, const Tri& b, const int sa[3], const int sb[3]) {
  // The corner alone on its side: the one whose sign differs from the next two's.
  const int i = sa[1] == sa[2] ? 0 : sa[0] == sa[2] ? 1 : 2;
  const int j = sb[1] == sb[2] ? 0 : sb[0] == sb[2] ? 1 : 2;
  // Each triangle from its lone corner, the other two swapped when the other triangle's lone
  // corner lies on the negative side of its plane (flipping the plane puts it on the positive).
  const float* p = a.p[i];
  const float* q = a.p[(i + (sb[j] > 0 ? 1 : 2)) % 3];
  const float* r = a.p[(i + (sb[j] > 0 ? 2 : 1)) % 3];
  const float* u = b.p[j];
  const float* v = b.p[(j + (sa[i] > 0 ? 1 : 2)) % 3];
  const float* w = b.p[(j + (sa[i] > 0 ? 2 : 1)) % 3];
  if (pred::orient3d(p, q, u, v) > 0) return false;
  return pred::orient3d(p, r, u, w) >= 0;
}

// Tests one pair. Returns -1 when they do not intersect (or share all three corners),
// else the IntersectionKind; `point` gets a point of the intersection.
int testPair(const Tri& a, const Tri& b, double point[3]) {
  int shared = 0, ia[3], ib[3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a.v[i] == b.v[j]) {
        ia[shared] = i;
        ib[shared] = j;
        ++shared;
      }
  if (shared >= 3) return -1;
  // Corners of b against a's plane, of a against b's plane; a shared corner lies in both
  // planes (0 without computing: the filter cannot decide an exact 0, the fallback would).
  bool sharedA[3] = {false, false, false}, sharedB[3] = {false, false, false};
  for (int i = 0; i < shared; ++i) sharedA[ia[i]] = sharedB[ib[i]] = true;
  int sb[3], sa[3];
  const pred::Plane planeA(a.p[0], a.p[1], a.p[2]);
  for (int i = 0; i < 3; ++i) sb[i] = sharedB[i] ? 0 : planeA.side(b.p[i]);
  if ((sb[0] > 0 && sb[1] > 0 && sb[2] > 0) || (sb[0] < 0 && sb[1] < 0 && sb[2] < 0)) return -1;
  if (shared == 2) {
    if (sb[3 - ib[0] - ib[1]] != 0) return -1;  // not coplanar: they meet only on the shared side
  } else if (shared == 1) {
    // With the other two corners of one strictly on one side of the other's plane, they
    // meet only at the shared corner.
    const int d = (ib[0] + 1) % 3, e = (ib[0] + 2) % 3;
    if (sb[d] * sb[e] > 0) return -1;
  }
  const pred::Plane planeB(b.p[0], b.p[1], b.p[2]);
  for (int i = 0; i < 3; ++i) sa[i] = sharedA[i] ? 0 : planeB.side(a.p[i]);
  if ((sa[0] > 0 && sa[1] > 0 && sa[2] > 0) || (sa[0] < 0 && sa[1] < 0 && sa[2] < 0)) return -1;
  if (shared == 1) {
    const int c = (ia[0] + 1) % 3, d = (ia[0] + 2) % 3;
    if (sa[c] * sa[d] > 0) return -1;
  }
  const bool coplanar = sb[0] == 0 && sb[1] == 0 && sb[2] == 0;
  bool hit;
  Projection pa{0, 0};
  if (coplanar) pa = projectionOf(a.p[0], a.p[1], a.p[2]);
  if (shared == 2) {
    const int c = 3 - ia[0] - ia[1], d = 3 - ib[0] - ib[1];
    const float *p = a.p[ia[0]], *q = a.p[ia[1]];
    hit = orient2dIn(pa.k, p, q, a.p[c]) == orient2dIn(pa.k, p, q, b.p[d]);
  } else if (shared == 1) {
    const int a1 = (ia[0] + 1) % 3, a2 = (ia[0] + 2) % 3, b1 = (ib[0] + 1) % 3, b2 = (ib[0] + 2) % 3;
    hit = segTri(b, a.p[a1], a.p[a2], sa[a1], sa[a2]) || segTri(a, b.p[b1], b.p[b2], sb[b1], sb[b2]);
  } else if (coplanar) {
    hit = triTri2d(pa, a, b);
  } else if (sa[0] && sa[1] && sa[2] && sb[0] && sb[1] && sb[2]) {
    hit = strictStraddlesMeet(a, b, sa, sb);
  } else {
    // Non-coplanar closed triangles meet iff a side of one meets the other.
    hit = false;
    for (int i = 0; i < 3 && !hit; ++i) hit = segTri(b, a.p[i], a.p[(i + 1) % 3], sa[i], sa[(i + 1) % 3]);
    for (int i = 0; i < 3 && !hit; ++i) hit = segTri(a, b.p[i], b.p[(i + 1) % 3], sb[i], sb[(i + 1) % 3]);
  }
  if (!hit) return -1;
  IntersectionKind kind;
  if (coplanar) {
    kind = interiorsMeet2d(pa.k, a, b) ? IntersectionKind::Coplanar : IntersectionKind::Touching;
  } else {
    const bool straddleA = std::max({sa[0], sa[1], sa[2]}) > 0 && std::min({sa[0], sa[1], sa[2]}) < 0;
    const bool straddleB = std::max({sb[0], sb[1], sb[2]}) > 0 && std::min({sb[0], sb[1], sb[2]}) < 0;
    kind = straddleA && straddleB ? IntersectionKind::Crossing : IntersectionKind::Touching;
  }
  intersectionPoint(a, b, coplanar, pa.k, point);
  return int(kind);
}

// The corners two triangles share, by welded id (three distinct ids each, from arrays with
// at least one more element after them): bit i of ma when a's corner i is one of b's, bit j
// of mb when b's corner j is one of a's.
inline void sharedCorners(const uint32_t* ca, const uint32_t* cb, unsigned& ma, unsigned& mb) {
#if defined(__SSE2__)
  const __m128i vb = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cb));  // the 4th lane is not b's
  const unsigned e0 = unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_set1_epi32(int(ca[0])), vb)))) & 7;
  const unsigned e1 = unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_set1_epi32(int(ca[1])), vb)))) & 7;
  const unsigned e2 = unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_set1_epi32(int(ca[2])), vb)))) & 7;
  mb = e0 | e1 | e2;
  ma = unsigned(e0 != 0) | unsigned(e1 != 0) << 1 | unsigned(e2 != 0) << 2;
#elif defined(__wasm_simd128__)
  const v128_t vb = wasm_v128_load(cb);  // the 4th lane is not b's
  const unsigned e0 = unsigned(wasm_i32x4_bitmask(wasm_i32x4_eq(wasm_i32x4_splat(int(ca[0])), vb))) & 7;
  const unsigned e1 = unsigned(wasm_i32x4_bitmask(wasm_i32x4_eq(wasm_i32x4_splat(int(ca[1])), vb))) & 7;
  const unsigned e2 = unsigned(wasm_i32x4_bitmask(wasm_i32x4_eq(wasm_i32x4_splat(int(ca[2])), vb))) & 7;
  mb = e0 | e1 | e2;
  ma = unsigned(e0 != 0) | unsigned(e1 != 0) << 1 | unsigned(e2 != 0) << 2;
#else
  ma = mb = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const unsigned eq = ca[i] == cb[j];
      ma |= eq << i;
      mb |= eq << j;
    }
#endif
}

#if defined(__GNUC__)
#define STLTOPO_NOINLINE __attribute__((noinline))
#else
#define STLTOPO_NOINLINE
#endif

// neighboursApart for two triangles in one plane (a flat stretch of a mesh) that share the
// side whose corners are a's bits in ma (d: b's third corner): a fold-over exactly when the
// third corners lie on one side of the shared side, as testPair decides it (a's projection,
// the shared corners in a's order). Out of line: the common path stays small.
STLTOPO_NOINLINE bool flatSideApart(const Tri& a, const Tri& b, unsigned ma, int d) {
  static constexpr int8_t kLow[8] = {-1, 0, 1, 0, 2, 0, 1, 0};
  const int s0 = kLow[ma], s1 = kLow[ma & (ma - 1)], c = kLow[~ma & 7];
  const Projection pa = projectionOf(a.p[0], a.p[1], a.p[2]);
  return orient2dIn(pa.k, a.p[s0], a.p[s1], a.p[c]) != orient2dIn(pa.k, a.p[s0], a.p[s1], b.p[d]);
}

// neighboursApart for two triangles in one plane that share the corner s (a's corner ia, b's
// ib). Each lies in its closed wedge at s and fills it near s, so they share more than s
// exactly when the wedges do, that is when a side ray of one lies in the other's closed wedge
// (both are narrower than a half-plane).
STLTOPO_NOINLINE bool flatCornerApart(const Tri& a, const Tri& b, int ia, int ib) {
  const Projection pa = projectionOf(a.p[0], a.p[1], a.p[2]);
  const float* s0 = a.p[ia];
  const float *a1 = a.p[(ia + 1) % 3], *a2 = a.p[(ia + 2) % 3], *b1 = b.p[(ib + 1) % 3], *b2 = b.p[(ib + 2) % 3];
  auto inWedge = [&](const float* u, const float* v, int sg, const float* x) {
    return orient2dIn(pa.k, s0, u, x) * sg >= 0 && orient2dIn(pa.k, s0, x, v) * sg >= 0;
  };
  const int sgA = orient2dIn(pa.k, s0, a1, a2), sgB = orient2dIn(pa.k, s0, b1, b2);
  return !(inWedge(a1, a2, sgA, b1) || inWedge(a1, a2, sgA, b2) || inWedge(b1, b2, sgB, a1) ||
           inWedge(b1, b2, sgB, a2));
}

// Whether testPair(a, b) returns -1 for a reason the corners they share (ma, mb:
// sharedCorners) decide with few exact signs, for the neighbours that make up nearly all the candidate pairs of a mesh:
// all three corners shared; a shared side with the fourth corners off each other's plane; one shared corner with the
// side opposite it of neither triangle meeting the other (the same sign tests, in the same order, as testPair's). False
// says nothing: testPair decides (it finds a pair that is not rejected here again, so the kind and the point are its
// own).
bool neighboursApart(const Tri& a, const Tri& b, unsigned ma, unsigned mb) {
  static constexpr int8_t kLow[8] = {-1, 0, 1, 0, 2, 0, 1, 0};         // the lowest set bit
  static constexpr int8_t kNext[3] = {1, 2, 0}, kPrev[3] = {2, 0, 1};  // (i + 1) % 3, (i + 2) % 3
  if (ma == 0) return false;
  if (ma == 7) return true;
  if (ma & (ma - 1)) {  // a shared side: apart unless b's third corner is in a's plane
    const int d = kLow[~mb & 7];
    return pred::orient3d(a.p[0], a.p[1], a.p[2], b.p[d]) != 0 || flatSideApart(a, b, ma, d);
  }
  const int ia = kLow[ma], ib = kLow[mb];
  const int b1 = kNext[ib], b2 = kPrev[ib];
  const pred::Plane planeA(a.p[0], a.p[1], a.p[2]);
  const int sb1 = planeA.side(b.p[b1]), sb2 = planeA.side(b.p[b2]);
  if (sb1 * sb2 > 0) return true;
  const int a1 = kNext[ia], a2 = kPrev[ia];
  int sa1 = 0, sa2 = 0;  // with b in a's plane (a flat stretch), a is in b's
  if (sb1 != 0 || sb2 != 0) {
    const pred::Plane planeB(b.p[0], b.p[1], b.p[2]);
    sa1 = planeB.side(a.p[a1]), sa2 = planeB.side(a.p[a2]);
    if (sa1 * sa2 > 0) return true;
  }
  if (sb1 * sb2 < 0 && sa1 * sa2 < 0) {
    // Each straddles the other's plane strictly: the planes meet in a line L through the
    // shared corner s, and a meets L in a segment [s, X] (X inside a's opposite side), b in
    // [s, Y] (Y inside b's). They share more than s exactly when X and Y lie on one side of s
    // on L, that is when Y lies on the side of line s a1 (in a's plane) that a2 lies on; or
    // on the side of the plane (s, a1, b1) that a2 lies on (it is not a's plane, as b1 is off
    // it). Y lies strictly between b1, which is in that plane, and b2: on b2's side. Neither
    // sign is 0 (a2 off the plane; b2 in it would put L = line s a1 in b's plane, but a1 is
    // off it). This is what testPair's segTri(b, a1, a2) || segTri(a, b1, b2) finds then.
    const float* s0 = a.p[ia];
    return pred::orient3d(s0, a.p[a1], b.p[b1], b.p[b2]) != pred::orient3d(s0, a.p[a1], b.p[b1], a.p[a2]);
  }
  if (sb1 == 0 && sb2 == 0) return flatCornerApart(a, b, ia, ib);
  return !(segTri(b, a.p[a1], a.p[a2], sa1, sa2) || segTri(a, b.p[b1], b.p[b2], sb1, sb2));
}

}  // namespace

int geometry_detail::trianglePairTest(const Tri& a, const Tri& b, double point[3]) { return testPair(a, b, point); }

namespace {

// ---------------------------------------------------------------------------
// The bounding-volume hierarchy: the valid triangles sorted by the Morton code of their
// box centres, leaves of up to kLeaf consecutive ones, and a balanced binary tree over
// the leaves in depth-first order (the left child follows its parent).

constexpr uint32_t kLeaf = 8;

struct Box {
  float lo[3], hi[3];
};

struct Node {
  Box box;
  uint32_t first, end;  // the sorted positions it covers
  uint32_t right;       // index of the right child; 0 for a leaf
};

// The boxes of the sorted positions as six float arrays (lo x, y, z, hi x, y, z), each of
// n + kLeaf entries: the ones past n are NaN, which overlaps nothing, so that kLeaf boxes can
// be read from any position below n.
struct BoxColumns {
  Array<float> v;
  size_t stride = 0;
  const float* col(int k) const { return v.data() + size_t(k) * stride; }
};

struct Bvh {
  Array<uint32_t> tri;  // sorted position -> triangle id
  Array<Box> box;       // sorted position -> its box (when not columnar)
  BoxColumns columns;   // the same boxes as columns (when columnar: the intersection pass)
  Array<Node> nodes;
  Box boxAt(uint32_t i) const {
    if (columns.stride == 0) return box[i];
    Box b;
    for (int k = 0; k < 3; ++k) b.lo[k] = columns.col(k)[i], b.hi[k] = columns.col(k + 3)[i];
    return b;
  }
};

inline bool overlaps(const Box& a, const Box& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] && a.lo[2] <= b.hi[2] &&
         b.lo[2] <= a.hi[2];
}

// Bit i set when the box of position first + i (i < kLeaf) overlaps `b` (closed boxes, as
// overlaps()); positions past the leaf's end must be masked off by the caller.
inline uint32_t overlapMask(const BoxColumns& c, uint32_t first, const Box& b) {
  static_assert(kLeaf == 8, "two groups of four");
#if defined(__SSE2__)
  uint32_t m = 0;
  for (int half = 0; half < 2; ++half) {
    const size_t q = first + 4 * size_t(half);
    __m128 ok = _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(c.col(0) + q), _mm_set1_ps(b.hi[0])),
                           _mm_cmpge_ps(_mm_loadu_ps(c.col(3) + q), _mm_set1_ps(b.lo[0])));
    ok = _mm_and_ps(ok, _mm_cmple_ps(_mm_loadu_ps(c.col(1) + q), _mm_set1_ps(b.hi[1])));
    ok = _mm_and_ps(ok, _mm_cmpge_ps(_mm_loadu_ps(c.col(4) + q), _mm_set1_ps(b.lo[1])));
    ok = _mm_and_ps(ok, _mm_cmple_ps(_mm_loadu_ps(c.col(2) + q), _mm_set1_ps(b.hi[2])));
    ok = _mm_and_ps(ok, _mm_cmpge_ps(_mm_loadu_ps(c.col(5) + q), _mm_set1_ps(b.lo[2])));
    m |= uint32_t(_mm_movemask_ps(ok)) << (4 * half);
  }
  return m;
#elif defined(__wasm_simd128__)
  // The same comparisons in wasm's 128-bit SIMD (a NaN compares false, as in SSE).
  uint32_t m = 0;
  for (int half = 0; half < 2; ++half) {
    const size_t q = first + 4 * size_t(half);
    v128_t ok = wasm_v128_and(wasm_f32x4_le(wasm_v128_load(c.col(0) + q), wasm_f32x4_splat(b.hi[0])),
                              wasm_f32x4_ge(wasm_v128_load(c.col(3) + q), wasm_f32x4_splat(b.lo[0])));
    ok = wasm_v128_and(ok, wasm_f32x4_le(wasm_v128_load(c.col(1) + q), wasm_f32x4_splat(b.hi[1])));
    ok = wasm_v128_and(ok, wasm_f32x4_ge(wasm_v128_load(c.col(4) + q), wasm_f32x4_splat(b.lo[1])));
    ok = wasm_v128_and(ok, wasm_f32x4_le(wasm_v128_load(c.col(2) + q), wasm_f32x4_splat(b.hi[2])));
    ok = wasm_v128_and(ok, wasm_f32x4_ge(wasm_v128_load(c.col(5) + q), wasm_f32x4_splat(b.lo[2])));
    m |= uint32_t(wasm_i32x4_bitmask(ok)) << (4 * half);
  }
  return m;
#else
  uint32_t m = 0;
  for (uint32_t i = 0; i < kLeaf; ++i) {
    const size_t q = first + i;
    m |= uint32_t((c.col(0)[q] <= b.hi[0]) & (c.col(3)[q] >= b.lo[0]) & (c.col(1)[q] <= b.hi[1]) &
                  (c.col(4)[q] >= b.lo[1]) & (c.col(2)[q] <= b.hi[2]) & (c.col(5)[q] >= b.lo[2]))
         << i;
  }
  return m;
#endif
}

inline int lowestBit(uint32_t m) {
#if defined(__GNUC__)
  return __builtin_ctz(m);
#else
  int i = 0;
  while (!(m & 1)) m >>= 1, ++i;
  return i;
#endif
}

constexpr uint32_t spread10(uint32_t x) {  // 10 bits to every third of 30
  x &= 0x3ff;
  x = (x | (x << 16)) & 0x030000ff;
  x = (x | (x << 8)) & 0x0300f00f;
  x = (x | (x << 4)) & 0x030c30c3;
  x = (x | (x << 2)) & 0x09249249;
  return x;
}
// spread10 of every 10-bit value (4 KiB): a load per coordinate of a Morton code, instead of
// a chain of eight dependent shifts and masks.
struct Spread10Table {
  uint32_t v[1024];
  constexpr Spread10Table() : v() {
    for (uint32_t x = 0; x < 1024; ++x) v[x] = spread10(x);
  }
};
constexpr Spread10Table kSpread10{};

// The hierarchy's Morton codes: the cell of a triangle's centroid in a 1024^3 grid over the
// mesh's box, its 10 bits an axis interleaved (x in bit 0). code() is what buildBvh uses
// (x and y two at a time where there is SIMD), scalarCode() the formula written out; they
// give the same value for every input (Geometry.MortonCodesAreTheScalarFormula).
struct MortonFrame {
  const float* lo;
  double scale[3];
#if defined(__SSE2__)
  __m128d loXY, scaleXY;
#elif defined(__wasm_simd128__)
  v128_t loXY, scaleXY;
#endif
  explicit MortonFrame(const Mesh& mesh) : lo(mesh.bboxMin) {
    const float* hi = mesh.bboxMax;
    for (int k = 0; k < 3; ++k) scale[k] = hi[k] > lo[k] ? 1023.0 / (double(hi[k]) - lo[k]) : 0;
#if defined(__SSE2__)
    loXY = _mm_set_pd(lo[1], lo[0]), scaleXY = _mm_set_pd(scale[1], scale[0]);
#elif defined(__wasm_simd128__)
    loXY = wasm_f64x2_make(lo[0], lo[1]), scaleXY = wasm_f64x2_make(scale[0], scale[1]);
#endif
  }
  // Axis k's 10 bits, spread to every third bit from bit k.
  uint32_t axisBits(const float* a, const float* b, const float* c, int k) const {
    double x = 0;
    x += a[k], x += b[k], x += c[k];
    const double q = (x / 3 - lo[k]) * scale[k];
    return kSpread10.v[q <= 0 ? 0 : q >= 1023 ? 1023 : uint32_t(q)] << k;
  }
  uint32_t scalarCode(const float* a, const float* b, const float* c) const {
    return axisBits(a, b, c, 0) | axisBits(a, b, c, 1) | axisBits(a, b, c, 2);
  }
  uint32_t code(const float* a, const float* b, const float* c) const {
#if defined(__SSE2__)
    // x and y in the two lanes of one register: the same operations in the same order as
    // axisBits (each lane rounds as the scalar code does), one division instead of two, and
    // the clamp (q <= 0 -> 0, q >= 1023 -> 1023) as a max and a min before the truncation.
    auto xy = [](const float* p) {
      return _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
    };
    const __m128d sum = _mm_add_pd(_mm_add_pd(_mm_add_pd(_mm_setzero_pd(), xy(a)), xy(b)), xy(c));
    const __m128d q = _mm_mul_pd(_mm_sub_pd(_mm_div_pd(sum, _mm_set1_pd(3)), loXY), scaleXY);
    const __m128i qi = _mm_cvttpd_epi32(_mm_min_pd(_mm_max_pd(q, _mm_setzero_pd()), _mm_set1_pd(1023)));
    return kSpread10.v[uint32_t(_mm_cvtsi128_si32(qi))] | kSpread10.v[uint32_t(_mm_cvtsi128_si32(_mm_srli_si128(qi, 4)))] << 1 |
           axisBits(a, b, c, 2);
#elif defined(__wasm_simd128__)
    // The same in wasm's f64x2: pmax(q, 0) is q < 0 ? 0 : q, pmin(x, 1023) is 1023 < x ? 1023 : x.
    auto xy = [](const float* p) { return wasm_f64x2_promote_low_f32x4(wasm_v128_load64_zero(p)); };
    const v128_t sum = wasm_f64x2_add(wasm_f64x2_add(wasm_f64x2_add(wasm_f64x2_splat(0), xy(a)), xy(b)), xy(c));
    const v128_t q = wasm_f64x2_mul(wasm_f64x2_sub(wasm_f64x2_div(sum, wasm_f64x2_splat(3)), loXY), scaleXY);
    const v128_t qi =
        wasm_i32x4_trunc_sat_f64x2_zero(wasm_f64x2_pmin(wasm_f64x2_pmax(q, wasm_f64x2_splat(0)), wasm_f64x2_splat(1023)));
    return kSpread10.v[uint32_t(wasm_i32x4_extract_lane(qi, 0))] | kSpread10.v[uint32_t(wasm_i32x4_extract_lane(qi, 1))] << 1 |
           axisBits(a, b, c, 2);
#else
    return scalarCode(a, b, c);
#endif
  }
};

#if defined(__wasm_simd128__)
// wasm: the boxes' minima and maxima as f32x4.pmin / pmax, one instruction each in the engine.
// Scalar std::min / std::max of floats compile to a compare and a select, which V8 turns into a
// branch per value, and the branches on a mesh's coordinates are not predictable: the
// hierarchy's boxes took 3-6 times their native time (bench/PROFILE.md). pmin(a, b) is
// b < a ? b : a, std::min(a, b) exactly, lane by lane.
inline v128_t xyz(const float* p) {  // lanes x, y, z, 0
  return wasm_f32x4_replace_lane(wasm_v128_load64_zero(p), 2, p[2]);
}
inline float lowest4(v128_t v) {  // the least of the four lanes
  v = wasm_f32x4_pmin(v, wasm_i32x4_shuffle(v, v, 2, 3, 0, 1));
  return wasm_f32x4_extract_lane(wasm_f32x4_pmin(v, wasm_i32x4_shuffle(v, v, 1, 0, 3, 2)), 0);
}
inline float highest4(v128_t v) {
  v = wasm_f32x4_pmax(v, wasm_i32x4_shuffle(v, v, 2, 3, 0, 1));
  return wasm_f32x4_extract_lane(wasm_f32x4_pmax(v, wasm_i32x4_shuffle(v, v, 1, 0, 3, 2)), 0);
}
inline Box boxOf(v128_t lo, v128_t hi) {  // lanes x, y, z of each
  return Box{{wasm_f32x4_extract_lane(lo, 0), wasm_f32x4_extract_lane(lo, 1), wasm_f32x4_extract_lane(lo, 2)},
             {wasm_f32x4_extract_lane(hi, 0), wasm_f32x4_extract_lane(hi, 1), wasm_f32x4_extract_lane(hi, 2)}};
}
#endif

uint32_t buildNodes(Bvh& bvh, uint32_t first, uint32_t end, uint32_t& next) {
  const uint32_t id = next++;
  Node& n = bvh.nodes[id];
  n.first = first;
  n.end = end;
  n.right = 0;
  if (end - first > kLeaf) {
    // Split at a multiple of kLeaf near the middle: leaves stay full.
    uint32_t leaves = (end - first + kLeaf - 1) / kLeaf;
    uint32_t mid = first + (leaves / 2) * kLeaf;
    const uint32_t left = buildNodes(bvh, first, mid, next);
    const uint32_t right = buildNodes(bvh, mid, end, next);
    Node& m = bvh.nodes[id];
    m.right = right;
    const Box &l = bvh.nodes[left].box, &r = bvh.nodes[right].box;
#if defined(__wasm_simd128__)
    m.box = boxOf(wasm_f32x4_pmin(xyz(l.lo), xyz(r.lo)), wasm_f32x4_pmax(xyz(l.hi), xyz(r.hi)));
#else
    for (int k = 0; k < 3; ++k) {
      m.box.lo[k] = std::min(l.lo[k], r.lo[k]);
      m.box.hi[k] = std::max(l.hi[k], r.hi[k]);
    }
#endif
  } else {
#if defined(__wasm_simd128__)
    if (bvh.columns.stride != 0 && end - first == kLeaf) {  // a full leaf: its 8 boxes, 4 at a time
      const BoxColumns& c = bvh.columns;
      for (int k = 0; k < 3; ++k) {
        const float *l = c.col(k) + first, *h = c.col(k + 3) + first;
        n.box.lo[k] = lowest4(wasm_f32x4_pmin(wasm_v128_load(l), wasm_v128_load(l + 4)));
        n.box.hi[k] = highest4(wasm_f32x4_pmax(wasm_v128_load(h), wasm_v128_load(h + 4)));
      }
      return id;
    }
#endif
    Box b = bvh.boxAt(first);
    for (uint32_t i = first + 1; i < end; ++i) {
      const Box c = bvh.boxAt(i);
      for (int k = 0; k < 3; ++k) {
        b.lo[k] = std::min(b.lo[k], c.lo[k]);
        b.hi[k] = std::max(b.hi[k], c.hi[k]);
      }
    }
    n.box = b;
  }
  return id;
}

// Sign mask of a triangle of the pass: bit 2k when its normal's coordinate k is > 0, bit
// 2k + 1 when it is < 0 (exact: normalSign).
inline uint8_t signMask(const float* a, const float* b, const float* c) {
  uint8_t m = 0;
  for (int k = 0; k < 3; ++k) {
    const int s = pred::normalSign(a, b, c, k);
    m |= uint8_t((s > 0 ? 1u : s < 0 ? 2u : 0u) << (2 * k));
  }
  return m;
}

using detail::aheadOf;
using detail::kAhead;
using detail::keepAlive;
using detail::touch;

// Builds the hierarchy over the triangles with valid[t] (non-degenerate, non-zero-area).
// columnar: the boxes go to bvh.columns (the intersection pass), else to bvh.box. The Morton
// codes and the boxes are computed by ranges on `threads` threads (the same result for every
// value). With `corner` (and `signs`), also each sorted position's welded corners (3, and one
// trailing 0 after the last) and its triangle's sign mask, read with its box.
Status buildBvh(const Welded& w, const Array<uint8_t>& valid, Bvh& bvh, bool columnar, unsigned threads = 1,
                Array<uint32_t>* corner = nullptr, Array<uint8_t>* signs = nullptr) {
  const uint32_t nt = w.mesh.nTriangles();
  const unsigned parts = detail::partsFor(detail::threadCount(threads), nt, detail::parallelGrain(32768));
  uint32_t firstOf[detail::kMaxThreads + 1] = {0};  // per part: the index of its first valid triangle
  detail::runParts(parts, [&](unsigned id) {
    const uint32_t end = uint32_t(detail::partBegin(nt, parts, id + 1));
    uint32_t c = 0;
    for (uint32_t t = uint32_t(detail::partBegin(nt, parts, id)); t < end; ++t) c += valid[t];
    firstOf[id + 1] = c;
  });
  for (unsigned i = 0; i < parts; ++i) firstOf[i + 1] += firstOf[i];
  const uint32_t n = firstOf[parts];
  // The sort's keys and its buffer (2n uint64): in the pass (columnar), the columns' own
  // storage (6 (n + kLeaf) floats, 24 bytes a position against the sort's 16), which the
  // gather fills once the sorted ids are in bvh.tri, so that the sort adds nothing to the
  // pass's peak memory (`info --intersections` of the 1M torus: 123.6 -> 118.8 MB peak RSS).
  // (Malloc'd storage, 8-byte aligned: the uint64 keys live there until the ids are out, and
  // a compiler barrier orders their last read before the gather's first float store.)
  Array<uint64_t> ownKeys;
  uint64_t* keys = nullptr;
  if (columnar) {
    bvh.columns.stride = size_t(n) + kLeaf;
    if (!bvh.columns.v.resize(6 * bvh.columns.stride)) return oom("the intersection hierarchy");
    detail::adviseSmallPages(bvh.columns.v.data(), bvh.columns.v.size() * sizeof(float));
    keys = reinterpret_cast<uint64_t*>(bvh.columns.v.data());
  } else {
    if (!bvh.box.resize(n) || !ownKeys.resize(2 * size_t(n))) return oom("the intersection hierarchy");
    keys = ownKeys.data();
  }
  if (!bvh.tri.resize(n)) return oom("the intersection hierarchy");
  // The pass's arrays (the columns, the sorted ids, the corners and the nodes) on small pages:
  // they are written in order once a call, and huge pages gave no warm gain there, while on a
  // VM a fresh huge page can cost 512 host faults: a process's first pass of the 1M tori took
  // 57-157 ms (bimodal) with them and 70-86 ms without (bench/PROFILE.md, *Stop 42*).
  if (columnar) detail::adviseSmallPages(bvh.tri.data(), bvh.tri.size() * sizeof(uint32_t));
  uint64_t* tmp = keys + n;
  const MortonFrame frame(w.mesh);
  detail::runParts(parts, [&](unsigned id) {
    const uint32_t end = uint32_t(detail::partBegin(nt, parts, id + 1));
    const uint32_t begin = uint32_t(detail::partBegin(nt, parts, id));
    uint32_t next = firstOf[id];
    detail::forChunks(begin, end, [&](size_t cb, size_t ce) {
      uint32_t i = next, sink = 0;
      for (uint32_t t = uint32_t(cb); t < ce; ++t) {
        for (auto [u, ue] = aheadOf(t, begin, end, kAhead); u < ue; ++u)
          for (int j = 0; j < 3; ++j) touch(w.p(w.v(u, j)), sink);
        if (!valid[t]) continue;
        const uint32_t code = frame.code(w.p(w.v(t, 0)), w.p(w.v(t, 1)), w.p(w.v(t, 2)));
        keys[i++] = uint64_t(code) << 32 | t;
      }
      next = i;
      keepAlive(sink);
    });
  });
  // Radix sort on the 30-bit code, stable (ties by triangle id): the keys go to buckets by
  // their top 10 bits, then each bucket is sorted by its low 20 bits in two passes of 10
  // (least significant first), where it stays in cache: the order an LSD sort of 3 passes
  // gives, with one pass over the whole array instead of three. The last pass writes the
  // triangle ids alone, into bvh.tri.
  uint32_t top[1025];
  std::memset(top, 0, sizeof top);
  detail::forChunks(0, n, [&](size_t b, size_t e) {
    for (size_t j = b; j < e; ++j) ++top[(keys[j] >> 52) + 1];
  });
  for (int d = 0; d < 1024; ++d) top[d + 1] += top[d];
  {
    uint32_t at[1024];
    std::memcpy(at, top, sizeof at);
    detail::forChunks(0, n, [&](size_t b, size_t e) {
      for (size_t j = b; j < e; ++j) tmp[at[keys[j] >> 52]++] = keys[j];
    });
  }
  uint32_t* sorted = bvh.tri.data();
  // A call per bucket (see forChunks).
  detail::forEachCall(0, 1024, [&](size_t d) {
    const uint32_t b = top[d], e = top[d + 1];
    if (e - b < 2) {
      if (e > b) sorted[b] = uint32_t(tmp[b]);
      return;
    }
    uint32_t count[2][1024];
    std::memset(count, 0, sizeof count);
    for (uint32_t j = b; j < e; ++j) {
      ++count[0][(tmp[j] >> 32) & 1023];
      ++count[1][(tmp[j] >> 42) & 1023];
    }
    for (auto& c : count) {
      uint32_t sum = b;
      for (uint32_t& x : c) {
        const uint32_t k = x;
        x = sum;
        sum += k;
      }
    }
    for (uint32_t j = b; j < e; ++j) keys[count[0][(tmp[j] >> 32) & 1023]++] = tmp[j];
    for (uint32_t j = b; j < e; ++j) sorted[count[1][(keys[j] >> 42) & 1023]++] = uint32_t(keys[j]);
  });
  ownKeys.release();
#if defined(__GNUC__)
  __asm__ __volatile__("" ::: "memory");  // the keys' last read comes before the columns' first store
#endif
  if (corner) {
    if (!corner->resize(3 * size_t(n) + 1) || !signs->resize(n)) return oom("the intersection hierarchy");
    detail::adviseSmallPages(corner->data(), corner->size() * sizeof(uint32_t));
    (*corner)[3 * size_t(n)] = 0;
  }
  if (columnar)
    for (int k = 0; k < 6; ++k)  // [0, n) of each column is written below
      for (uint32_t i = 0; i < kLeaf; ++i) bvh.columns.v[size_t(k) * bvh.columns.stride + n + i] = std::nanf("");
  const unsigned boxParts = detail::partsFor(detail::threadCount(threads), n, detail::parallelGrain(32768));
  // One sorted position: its box, and with `corner` its corners and sign mask.
  auto emit = [&](uint32_t j, const uint32_t* id, const float* const* p) {
    Box b;
#if defined(__wasm_simd128__)
    const v128_t p0 = xyz(p[0]), p1 = xyz(p[1]), p2 = xyz(p[2]);
    b = boxOf(wasm_f32x4_pmin(wasm_f32x4_pmin(p0, p1), p2), wasm_f32x4_pmax(wasm_f32x4_pmax(p0, p1), p2));
#else
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = std::min({p[0][k], p[1][k], p[2][k]});
      b.hi[k] = std::max({p[0][k], p[1][k], p[2][k]});
    }
#endif
    if (corner) {
      for (int c = 0; c < 3; ++c) (*corner)[3 * size_t(j) + c] = id[c];
      (*signs)[j] = signMask(p[0], p[1], p[2]);
    }
    if (columnar) {
      for (int k = 0; k < 3; ++k) {
        bvh.columns.v[size_t(k) * bvh.columns.stride + j] = b.lo[k];
        bvh.columns.v[size_t(k + 3) * bvh.columns.stride + j] = b.hi[k];
      }
    } else {
      bvh.box[j] = b;
    }
  };
  detail::runParts(boxParts, [&](unsigned id) {
    const uint32_t end = uint32_t(detail::partBegin(n, boxParts, id + 1));
    const uint32_t begin = uint32_t(detail::partBegin(n, boxParts, id));
    detail::forChunks(begin, end, [&](size_t cb, size_t ce) {
#if defined(__EMSCRIPTEN__)
      // wasm has no prefetch, and a touch is a load that the loop waits on (perf of V8's code:
      // a third of the gather's samples on the touches). In blocks instead: first every
      // record of the block, then every corner's position, each a run of independent loads
      // whose misses overlap, then the boxes from the copies, which are in cache.
      constexpr uint32_t kBlock = 64;
      uint32_t ids[3 * kBlock];
      float pos[9 * kBlock];
      for (uint32_t j0 = uint32_t(cb); j0 < ce; j0 += kBlock) {
        const uint32_t m = std::min<uint32_t>(kBlock, uint32_t(ce) - j0);
        const uint32_t* tris = w.mesh.triangles.data();
        for (uint32_t i = 0; i < m; ++i) {
          const uint32_t* r = tris + 3 * size_t(sorted[j0 + i]);
          ids[3 * i] = r[0], ids[3 * i + 1] = r[1], ids[3 * i + 2] = r[2];
        }
        if (w.weld)
          for (uint32_t i = 0; i < 3 * m; ++i) ids[i] = w.weld[ids[i]];
        for (uint32_t i = 0; i < 3 * m; ++i) {
          const float* q = w.p(ids[i]);
          pos[3 * i] = q[0], pos[3 * i + 1] = q[1], pos[3 * i + 2] = q[2];
        }
        for (uint32_t i = 0; i < m; ++i) {
          const float* p[3] = {pos + 9 * i, pos + 9 * i + 3, pos + 9 * i + 6};
          emit(j0 + i, ids + 3 * i, p);
        }
      }
#else
      // Natively, prefetches: a position's triangle record 2 kBoxLead positions ahead, then
      // its corners kBoxLead ahead. 4 kAhead: the record's load, which the corners' prefetch
      // waits on, was the loop's largest stall at kAhead (perf), and the 1M tori's pass took
      // 5-7 ms less (67.4-69.3 -> 61.8-64.4 ms in grid order, 90.8-97.0 -> 84.8-87.7 ms
      // shuffled, warm, alternated; 8 kAhead gained no more).
      constexpr uint32_t kBoxLead = 4 * kAhead;
      uint32_t sink = 0;
      for (uint32_t j = uint32_t(cb); j < ce; ++j) {
        // A chain of two: a triangle's record, then its corners' positions.
        for (auto [u, ue] = aheadOf(j, begin, end, 2 * kBoxLead); u < ue; ++u)
          touch(&w.mesh.triangles[3 * size_t(sorted[u])], sink);
        for (auto [u, ue] = aheadOf(j, begin, end, kBoxLead); u < ue; ++u) {
          const uint32_t tu = sorted[u];
          for (int c = 0; c < 3; ++c) touch(w.p(w.v(tu, c)), sink);
        }
        const uint32_t t = sorted[j];
        const uint32_t id[3] = {w.v(t, 0), w.v(t, 1), w.v(t, 2)};
        const float* p[3] = {w.p(id[0]), w.p(id[1]), w.p(id[2])};
        emit(j, id, p);
      }
      keepAlive(sink);
#endif
    });
  });
  if (n == 0) return {};  // no node
  const uint32_t leaves = (n + kLeaf - 1) / kLeaf;
  if (!bvh.nodes.resize(2 * size_t(leaves))) return oom("the intersection hierarchy");
  if (columnar) detail::adviseSmallPages(bvh.nodes.data(), bvh.nodes.size() * sizeof(Node));
  uint32_t next = 0;
  buildNodes(bvh, 0, n, next);
  bvh.nodes.shrink(next);
  return {};
}

Tri triOf(const Welded& w, uint32_t t) {
  Tri x;
  for (int c = 0; c < 3; ++c) {
    x.v[c] = w.v(t, c);
    x.p[c] = w.p(x.v[c]);
  }
  return x;
}

struct Found {
  uint64_t key;  // i << 32 | j
  double point[3];
  uint8_t kind;
};

// What the pair tests read: the hierarchy, the welded corners of each sorted position (one
// more entry: sharedCorners reads four) and the positions.
struct JoinInput {
  const Welded& w;
  const Bvh& bvh;
  const Array<uint32_t>& corner;
  const uint8_t* fan;  // per sorted position: bit c when corner c is a certified vertex (certifyFans); null: none
  const uint8_t* free;  // per node: 1 when no two of its triangles intersect (certifyPatches)
  const BoxColumns& boxes() const { return bvh.columns; }
  Tri triAt(uint32_t q) const {
    Tri x;
    for (int c = 0; c < 3; ++c) {
      x.v[c] = corner[3 * size_t(q) + c];
      x.p[c] = w.p(x.v[c]);
    }
    return x;
  }
  Box boxAt(uint32_t q) const {
    Box b;
    for (int k = 0; k < 3; ++k) b.lo[k] = boxes().col(k)[q], b.hi[k] = boxes().col(k + 3)[q];
    return b;
  }
};

// ---------------------------------------------------------------------------
// Fan certificates: the vertices around which no two triangles of the pass intersect, so
// that the join skips every pair sharing one (nearly all of a clean mesh's candidates).
//
// A vertex v is certified when its triangles form one closed manifold fan F and, along some
// coordinate axis k, with exact signs:
//  (1) every triangle (v, a, b) of F (in its own winding) projects with one strict
//      orientation s (normalSign(v, a, b, k): the normal's coordinate k), and
//  (2) the projected link (the sides a -> b opposite v, a closed polygon as F is a closed
//      fan) winds exactly once around proj(v), in the direction s.
// F is one closed fan of triangles of the pass, and holds all of them at v, when no side at
// v is other than interior (EdgeKind), v's outgoing half-edges form one vnext cycle
// (!vertexNonManifold: the topology's walk around v) and no zero-area triangle has corner v:
// then every non-degenerate triangle at v is in the cycle, and each is in the pass. (With
// interior sides only, each cycle's link is closed and, under (1), winds at least once, so
// (2) over all the triangles at v also rules out two cycles: the vertexNonManifold test is
// a cheap early no.)
// Why no pair sharing v then intersects: by (1) each projected triangle lies in the sector
// from proj(v) between the rays to proj(a) and proj(b), of angle in (0, pi), turning by s;
// the turns add up to 2 pi times the winding number, so by (2) the sectors go around
// proj(v) exactly once: their interiors are disjoint, and two of them meet only along the
// ray of a side v a_i they share (fan neighbours: sectors of angle < pi summing to one turn
// are at least three) or only at proj(v). A projection with a non-zero orientation is
// injective on the triangle, and the part of a projected triangle on a bounding ray of its
// sector is its projected side v a_i. So a 3D point common to two fan triangles projects
// to proj(v), and is v, or onto the projected shared side v a_i of both, and is on that side:
// within the convex hull of the corners they share. No pair sharing v is therefore a
// self-intersection (testPair would return -1; two triangles with the same three corners
// would have one sector). A triangle of the pass has three distinct welded corners, so it
// appears once in v's fan. The winding number is exact and a sum over the triangles, in any
// order: proj(v) is on no side by (1), and with a ray from proj(v) along the first projected
// axis (coordinate k + 1; y is coordinate k + 2), a side a -> b crosses it upwards when
// a.y <= v.y < b.y (v then on its left when s > 0) and downwards when b.y <= v.y < a.y (v on
// its right when s < 0): the winding number is the number of upward crossings for s > 0,
// minus the number of downward ones for s < 0. So one pass over the triangles, in the
// hierarchy's order (vertices near in space near in time, whatever the file's order),
// gathers per vertex and axis the signs seen and the crossings (up to 2), and no walk is
// needed.
namespace fan {
constexpr uint16_t kBad = 1u << 15;                                                  // a side or triangle that rules v out
inline constexpr unsigned signBit(int k, int s) { return 3u * unsigned(k) + (s > 0 ? 0u : s < 0 ? 1u : 2u); }  // bits 0-8
inline constexpr unsigned crossShift(int k) { return 9u + 2u * unsigned(k); }        // bits 9-14: crossings, 0-2
}  // namespace fan

// Certifies the vertices of the pass's triangles (`corner`: 3 welded ids each, n triangles):
// certified[v] = 1, else 0 (2 bytes per vertex). zeroArea: checkTriangles' list.
Status certifyVertices(const Welded& w, const Topology& topo, const Array<uint32_t>& zeroArea, const uint32_t* corner,
                       uint32_t n, Array<uint16_t>& state) {
  const uint32_t nv = topo.nVertices;
  if (!state.assign(nv, 0)) return oom("the fan certificates");
  if (topo.vertexNonManifold.size() != nv || 2 * size_t(topo.pairKind.size()) != topo.vert.size())
    return {};  // no topology to go by: nothing is certified
  for (size_t k = 0; k < topo.pairKind.size(); ++k)
    if (topo.pairKind[k] != uint8_t(EdgeKind::Interior))
      state[topo.vert[2 * k]] |= fan::kBad, state[topo.vert[2 * k + 1]] |= fan::kBad;
  for (uint32_t t : zeroArea)
    for (int c = 0; c < 3; ++c) state[w.v(t, c)] |= fan::kBad;
  for (uint32_t q = 0; q < n; ++q) {
    const uint32_t* id = corner + 3 * size_t(q);
    const float* p[3] = {w.p(id[0]), w.p(id[1]), w.p(id[2])};
    int sg[3];
    for (int k = 0; k < 3; ++k) sg[k] = pred::normalSign(p[0], p[1], p[2], k);  // the same for every corner
    for (int c = 0; c < 3; ++c) {
      const float *v = p[c], *a = p[(c + 1) % 3], *b = p[(c + 2) % 3];
      uint16_t st = state[id[c]];
      for (int k = 0; k < 3; ++k) {
        const int j = (k + 2) % 3;
        st |= uint16_t(1u << fan::signBit(k, sg[k]));
        const bool cross = sg[k] > 0 ? a[j] <= v[j] && v[j] < b[j] : b[j] <= v[j] && v[j] < a[j];
        if (cross && (st >> fan::crossShift(k) & 3) < 2) st = uint16_t(st + (1u << fan::crossShift(k)));
      }
      state[id[c]] = st;
    }
  }
  for (uint32_t v = 0; v < nv; ++v) {
    const unsigned st = state[v];
    bool ok = false;
    for (int k = 0; k < 3 && !(st & fan::kBad) && !topo.vertexNonManifold[v]; ++k) {
      const unsigned signs = st >> (3 * k) & 7;  // only s > 0 or only s < 0, and one crossing
      ok = ok || ((signs == 1 || signs == 2) && (st >> fan::crossShift(k) & 3) == 1);
    }
    state[v] = ok;
  }
  return {};
}

std::atomic<uint64_t> gFanCertified{0}, gFanSkipped{0};

// The certificates as `fan`: per sorted position, bit c when corner c is certified.
Status certifyFans(const Welded& w, const Topology& topo, const Array<uint32_t>& zeroArea,
                   const Array<uint32_t>& corner, uint32_t n, unsigned threads, Array<uint8_t>& fan) {
  Array<uint16_t> flag;
  if (Status s = certifyVertices(w, topo, zeroArea, corner.data(), n, flag); !s.ok()) return s;
  if (!fan.resize(n)) return oom("the fan certificates");
  uint64_t total = 0;
  for (uint16_t f : flag) total += f;
  gFanCertified.fetch_add(total, std::memory_order_relaxed);
  const unsigned parts = detail::partsFor(detail::threadCount(threads), n, detail::parallelGrain(32768));
  detail::runParts(parts, [&](unsigned id) {
    const uint32_t end = uint32_t(detail::partBegin(n, parts, id + 1));
    for (uint32_t q = uint32_t(detail::partBegin(n, parts, id)); q < end; ++q) {
      const uint32_t* c = &corner[3 * size_t(q)];
      fan[q] = uint8_t(flag[c[0]] | flag[c[1]] << 1 | flag[c[2]] << 2);
    }
  });
  return {};
}

// ---------------------------------------------------------------------------
// Patch certificates: nodes of the hierarchy no two of whose triangles intersect, so that
// the join skips every pair inside them (the pairs between two nodes it still tests).
//
// A node N is certified when, along some coordinate axis k and with exact signs:
//  (1) every triangle of N projects with one strict orientation s (normalSign(k) == s), and
//  (2) the sides of N's triangles that do not cancel (a side u -> v cancels against a side
//      v -> u of another triangle of N, by welded id; each edge may keep at most one side)
//      are its boundary B, and projected along k:
//      (a) two sides of B meet only in a corner they share, and two sides leaving or
//          entering one corner do not overlap (certifiedIn's sweep);
//      (b) at a corner that B leaves more than once, its sides alternate between leaving and
//          entering by angle; B is then cut into loops that do not cross, each leaving such
//          a corner by the side that bounds the same covered wedge as the side it came in by
//          (linkLoops);
//      (c) for each loop L, [L turns the way s does] + s * (the sum of the turns of the
//          other loops that wind around L) == 1.
// Why no two triangles of N then intersect. Let N's triangles be a 2-chain c (each with
// weight 1) and take s > 0 (s < 0 is the mirror image). In the plane, for a point p on no
// projected side, the number of projected triangles that cover p equals the winding number
// of the projected boundary of c around p (each triangle's indicator is the winding of its
// own sides, and the sum of the sides is the boundary, as the cancelled ones cancel). The
// loops of (b) do not cross, so each winds 0 or its turn around a point off it, and the
// winding of B is the sum over the loops. By (c) it is 1 just left of every side of B and so
// 0 just right of it; every bounded region between the loops borders a side, so it is 0 or
// 1 everywhere: the projected triangles' interiors are pairwise disjoint. Now let triangles
// A and B of N share a 3D point q, and p = proj(q). Near p each triangle containing p covers
// a sector: all of the plane (p inside it), a half-plane (p inside a side) or a wedge under
// pi (p a corner); the sectors are disjoint, and a triangle's sector is bounded by the rays
// of its sides through p. Such a side either cancels, and then the triangle on its other
// side (it runs the opposite way, so by (1) it lies on the other side of the side) has the
// adjacent sector, sharing that side's corners; or it is a side of the boundary, and by (a)
// the boundary rays at p all come from one boundary side through p or from one corner w of
// the boundary at p. Following the sectors around p from A through cancelled sides, and
// from B the same way, every triangle passed shares A's side through p, or A's corner at p
// (a corner of another id at p would bring a second fan of sectors around p, overlapping
// this one, or boundary sides meeting there, against (a)); the sectors do not overlap, so B
// shares with A the corner or the side whose projection holds p. The projection is
// injective on each triangle (1), so q, the point of A over p, is that corner or lies on
// that side: within the convex hull of the corners A and B share. Hence testPair returns -1
// for every pair of N (two triangles with the same corners would cover one sector twice).
// The same holds with zero-area, degenerate and skipped triangles present elsewhere: N
// holds only the pass's triangles.
// The nodes of kMinPatch to kMaxPatch positions are tried top down; a node whose triangles
// have a common strict sign along some axis (the AND of their sign masks, bottom up) is
// tried, and when it fails its children are (larger nodes inside a task are tried too when
// their triangles turn one way: patch::kTaskScale). Above those, a node whose two children are
// certified is tried as their union, from the children's boundaries (certifyUnion): on a
// clean mesh the patches grow to a large part of a shell, and the join skips the pairs
// between them too. Cost: one hash of N's sides and a grid over its boundary sides per node
// tried (O(n) on a smooth mesh, as each position is tried about once), and per union the
// length of its children's boundaries; memory: 1 byte per triangle for the sign masks, 2 per
// node, and the boundaries of the certified nodes (16 bytes a side).
namespace patch {
constexpr uint32_t kMinPatch = 64;  // smaller nodes are not tried (setPatchMinimumForTesting)
// The nodes of at most kMaxPatch positions are tried top down within a budget (certifyPatches);
// larger ones are tried as unions of certified children, or, inside a task, from their
// triangles when these all turn one way along an axis (setPatchTaskSizeForTesting).
constexpr uint32_t kMaxPatch = 8192;
// A task (run on one thread) is a subtree of at most kTaskScale * kMaxPatch positions. Its
// nodes above kMaxPatch are tried from their triangles when all of them, or all but a few,
// turn one way along an axis (certify), and only until a try that summed the node's sides
// fails: on a smooth mesh such a node is certified at once, instead of as unions of the
// kMaxPatch nodes below it, each of which merges and tests its children's boundaries again
// (the 1M torus: 32 tasks and 30 unions instead of 128 and 126; its pass about 15% faster,
// 25% with 1% of its triangles flipped). A failed try costs the hash of the node's sides, at
// most once per position (a node of parts of many small bodies: about 5% more on 400 spheres
// of 4,760 triangles).
constexpr uint32_t kTaskScale = 4;
constexpr size_t kMaxLoops = 32;  // more boundary loops: not tried (the test is quadratic in them)
constexpr uint32_t kChunk = 256;  // positions per run of the boundary's first level (its table: 24 KiB)
struct Slot {  // an edge's sum over a run of positions (PatchCertifier::partial)
  uint32_t lo, hi;  // the side's vertices, lo < hi
  int32_t net;      // sides lo -> hi minus sides hi -> lo
};
}  // namespace patch

// Sums per undirected edge (key lo << 32 | hi with lo < hi, so that 0 marks an empty slot)
// in an open-addressing table of a power-of-two size, and the slots in the order they were
// filled. Branch-free where it can be: the first visit of an edge and the second (its other
// side) come in no order a predictor learns.
struct EdgeSums {
  Array<uint64_t> key;
  Array<int32_t> net;
  Array<uint32_t> filled;
  size_t mask = 0, nFilled = 0;
  // Where key k's probe starts.
  static size_t home(uint64_t k, size_t mask) { return size_t((k * 0x9E3779B97F4A7C15ull) >> 40) & mask; }
  // Room for `adds` edges at most half full; false when it cannot be allocated.
  bool prepare(size_t adds) {
    size_t cap = 64;
    while (cap < 2 * adds) cap *= 2;
    // Both tables or neither: a failed second allocation must not leave `key` grown past
    // `net` (the next prepare would then skip the allocation and write through an empty net).
    if ((key.size() < cap || net.size() < cap) && (!key.assign(cap, 0) || !net.assign(cap, 0))) {
      key = Array<uint64_t>{};
      net = Array<int32_t>{};
      return false;
    }
    if (filled.size() < adds + 1 && !filled.resize(adds + 1)) return false;
    mask = cap - 1;
    nFilled = 0;
    return true;
  }
  void add(uint32_t lo, uint32_t hi, int32_t d) { nFilled = add(key.data(), net.data(), filled.data(), mask, nFilled, lo, hi, d); }
  // The same on the arrays, for a loop that keeps them and the count in registers (a store
  // through key.data() could be a store to nFilled, as far as the compiler knows).
  static size_t add(uint64_t* key, int32_t* net, uint32_t* filled, size_t mask, size_t nFilled, uint32_t lo,
                    uint32_t hi, int32_t d) {
    const uint64_t k = uint64_t(lo) << 32 | hi;
    size_t h = home(k, mask);
    uint64_t x = key[h];
    // One branch, nearly always taken the same way (a collision is rare): `x != 0 && x != k`
    // compiles to two, and the first of them goes either way.
    while ((x != 0) & (x != k)) h = (h + 1) & mask, x = key[h];
    key[h] = k;
    filled[nFilled] = uint32_t(h);  // kept when the slot was empty
    net[h] += d;
    return nFilled + (x == 0);
  }
  // The slot of edge (lo, hi), which was added.
  size_t find(uint32_t lo, uint32_t hi) const {
    const uint64_t k = uint64_t(lo) << 32 | hi;
    size_t h = home(k, mask);
    while (key[h] != k) h = (h + 1) & mask;
    return h;
  }
  // f(lo, hi, sum) for each edge, in the order they came; the table is empty after.
  template <class F>
  void drain(F&& f) {
    for (size_t i = 0; i < nFilled; ++i) {
      const uint32_t h = filled[i];
      f(uint32_t(key[h] >> 32), uint32_t(key[h]), net[h]);
      key[h] = 0;
      net[h] = 0;
    }
    nFilled = 0;
  }
};

struct PatchCertifier {
  PatchCertifier(const Welded& w_, const Array<uint32_t>& corner_) : w(w_), corner(corner_) {}
  const Welded& w;
  const Array<uint32_t>& corner;
  EdgeSums small;              // a run's edges (the first level)
  EdgeSums sums;               // the node's edges (the second level)
  Array<patch::Slot> partial;  // the runs' edges whose sum is not 0
  Array<uint64_t> sides;  // boundary sides: origin << 32 | destination, sorted
  Array<uint32_t> into;   // the sides by destination
  Array<uint32_t> next;   // per side: the side its loop takes next
  Array<uint8_t> taken;   // per side: in a loop already
  struct Ray {
    uint32_t side;
    bool out;  // the side leaves the corner (else it enters it)
  };
  Array<Ray> rays;          // the sides at one corner left more than once, by angle
  Array<uint32_t> loops;    // the loops' sides, loop after loop
  Array<uint32_t> loopEnd;  // per loop: its end in `loops`
  Array<uint64_t> byDest;     // the sides as destination << 32 | origin, sorted
  Array<uint8_t> owner;       // after merge(): per side, 0 from the first node, 1 from the second
  Array<uint32_t> slotSide;   // per slot of `sums`, in merge(): its side's index
  bool checked[2] = {false, false};  // sidesApart: the pairs of one node's sides passed already
  int axis = -1;                     // after a certificate: the axis it holds along
  Array<uint32_t> span;       // per side: its cells' range along i and along j (sidesApart)
  Array<uint32_t> cellStart;  // per cell: its first entry in cellItems, and one past the last
  Array<uint32_t> cellFill;
  Array<uint32_t> cellItems;  // per cell: the sides whose spans cover it

  uint32_t origin(size_t s) const { return uint32_t(sides[s] >> 32); }
  uint32_t dest(size_t s) const { return uint32_t(sides[s]); }
  // The sides of positions [first, end) that do not cancel, into `sides` (sorted by origin)
  // and `into` (their indices by destination). False when an edge keeps more than one side,
  // when fewer than 3 are left, or when a vertex is left and entered a different number of
  // times.
  // With `flip` (a sign mask bit), a triangle whose sign mask has that bit counts with its
  // sides reversed (the chain of the triangles wound to face one way along an axis).
  bool summed = false;  // whether boundary() ran since certify() began
  bool boundary(uint32_t first, uint32_t end, const uint8_t* signs = nullptr, uint8_t flip = 0) {
    summed = true;
    // Two levels, so that the table the triangles' sides go to stays in the first-level cache:
    // the sides of each run of kChunk positions are summed in a small table, and the edges
    // whose sum is not 0 (the run's boundary, short on a smooth mesh) are summed again over
    // the node in a table sized to them. The sums, and so the sides kept, are the same as
    // one table's.
    partial.clear();
    if (!small.prepare(3 * size_t(patch::kChunk)) || !partial.reserve(3 * size_t(end - first))) return false;
    uint64_t* key = small.key.data();
    int32_t* net = small.net.data();
    uint32_t* filled = small.filled.data();
    const size_t mask = small.mask;
    for (uint32_t c = first; c < end; c += patch::kChunk) {
      const uint32_t ce = std::min(end, c + patch::kChunk);
      size_t nFilled = 0;
      for (uint32_t q = c; q < ce; ++q) {
        const uint32_t* cq = &corner[3 * size_t(q)];
        const int32_t dir = signs && (signs[q] & flip) ? -1 : 1;
        // Side u -> v as edge (lo, hi) and +-dir, without a branch on u < v (it goes either
        // way, half the time).
        auto side = [&](uint32_t u, uint32_t v) {
          const uint32_t lo = std::min(u, v), hi = u ^ v ^ lo;
          const int32_t flipSide = -int32_t(u > v);  // 0 or -1
          nFilled = EdgeSums::add(key, net, filled, mask, nFilled, lo, hi, (dir ^ flipSide) - flipSide);
        };
        side(cq[0], cq[1]);
        side(cq[1], cq[2]);
        side(cq[2], cq[0]);
      }
      // The run's edges whose sum is not 0, into `partial` (reserved: 3 per position), each
      // slot emptied; without a branch on the sum (about one edge in four keeps one).
      patch::Slot* out = partial.data() + partial.size();
      size_t kept = 0;
      for (size_t f = 0; f < nFilled; ++f) {
        const uint32_t h = filled[f];
        const uint64_t k = key[h];
        const int32_t d = net[h];
        key[h] = 0;
        net[h] = 0;
        out[kept] = patch::Slot{uint32_t(k >> 32), uint32_t(k), d};
        kept += d != 0;
      }
      (void)partial.resize(partial.size() + kept);  // reserved
    }
    if (!sums.prepare(partial.size())) return false;
    for (const patch::Slot& sl : partial) sums.add(sl.lo, sl.hi, sl.net);
    return finishBoundary();
  }

  // The boundary of two certified nodes' union, from their boundaries (a and b: their
  // sides, origin << 32 | destination, sorted, then the same as destination << 32 | origin,
  // sorted; chains wound the same way): an edge's sum over the union is the sum of its sums
  // over the two, so the sides kept are those the triangles' own sides would give
  // (boundary() on the union's positions). Each side is kept from a or b, so `sides` and
  // `byDest` are merges of theirs, and `owner` says which of the two each side is from.
  bool merge(const uint64_t* a, size_t na, const uint64_t* b, size_t nb) {
    if (!sums.prepare(na + nb) || !sides.reserve(na + nb) || !byDest.reserve(na + nb) || !owner.reserve(na + nb) ||
        !into.reserve(na + nb) || (slotSide.size() < sums.key.size() && !slotSide.resize(sums.key.size())))
      return false;
    auto undirected = [](uint64_t x, uint32_t& lo, uint32_t& hi) {
      const uint32_t u = uint32_t(x >> 32), v = uint32_t(x);
      lo = std::min(u, v), hi = std::max(u, v);
      return u < v ? 1 : -1;
    };
    for (const uint64_t* x : {a, b})
      for (size_t i = 0, m = x == a ? na : nb; i < m; ++i) {
        uint32_t lo, hi;
        const int d = undirected(x[i], lo, hi);
        sums.add(lo, hi, d);
      }
    bool ok = true;
    for (size_t i = 0; i < sums.nFilled; ++i) {
      const int32_t net = sums.net[sums.filled[i]];
      if (net > 1 || net < -1) ok = false;  // a side in both: not a chain
    }
    // The sides left, in order: a merge of a's and b's (no side is in both now), and the same
    // by destination. f(side, from a, its edge's slot) for each.
    auto mergeLeft = [&](const uint64_t* x, const uint64_t* y, auto&& f) {
      for (size_t i = 0, j = 0; ok && (i < na || j < nb);) {
        const bool fromA = j == nb || (i < na && x[i] < y[j]);
        const uint64_t side = fromA ? x[i++] : y[j++];
        uint32_t lo, hi;
        (void)undirected(side, lo, hi);
        const size_t h = sums.find(lo, hi);
        if (sums.net[h] != 0) f(side, fromA, h);
      }
    };
    sides.clear(), byDest.clear(), owner.clear(), into.clear();
    mergeLeft(a, b, [&](uint64_t side, bool fromA, size_t h) {
      slotSide[h] = uint32_t(sides.size());
      (void)sides.push_back(side);  // reserved
      (void)owner.push_back(fromA ? 0 : 1);
    });
    mergeLeft(a + na, b + nb, [&](uint64_t side, bool, size_t h) {
      (void)byDest.push_back(side);  // reserved
      (void)into.push_back(slotSide[h]);
    });
    sums.drain([](uint32_t, uint32_t, int32_t) {});
    return ok && sides.size() >= 3 && readyForLoops() && fewPieces();
  }

  // With `sides` and `byDest` made: room for linkLoops, and whether every corner is entered as
  // often as it is left (the destinations, sorted, are the origins).
  bool readyForLoops() {
    const size_t n = sides.size();
    if (!next.resize(n) || !taken.resize(n) || !loops.reserve(n) || !loopEnd.reserve(n) || !rays.reserve(n))
      return false;
    for (size_t s = 0; s < n; ++s)
      if (uint32_t(byDest[s] >> 32) != origin(s)) return false;
    return true;
  }

  // Whether the boundary's sides, as a graph on its corners, have at most kMaxLoops connected
  // pieces. Each loop lies in one piece and each piece holds a loop, so with more pieces
  // certifiedIn would find more loops than it tests and fail along every axis: a node of many
  // separate pieces (parts of many small bodies) is refused here, before the grid of sides.
  // Needs `into` (side into[i] enters the corner that side i leaves).
  bool fewPieces() {
    const size_t n = sides.size();
    if (!piece.resize(n)) return false;
    auto find = [&](uint32_t x) {
      while (piece[x] != x) x = piece[x] = piece[piece[x]];
      return x;
    };
    // A corner is the run of sides leaving it (sides are sorted by origin): its first index.
    size_t pieces = 0;
    for (size_t s = 0; s < n; ++s) {
      const bool first = s == 0 || origin(s) != origin(s - 1);
      piece[s] = first ? uint32_t(s) : piece[s - 1];
      pieces += first;
    }
    for (size_t i = 0; i < n; ++i) {
      const uint32_t a = find(into[i]), b = find(uint32_t(i));
      if (a != b) piece[a] = b, --pieces;
    }
    return pieces <= patch::kMaxLoops;
  }
  Array<uint32_t> piece;  // fewPieces' union-find over side indices (a corner: its first side)

  // From the edges in `sums`: the sides that do not cancel, into `sides` and `into`, and the
  // checks boundary() describes. Empties `sums`.
  bool finishBoundary() {
    checked[0] = checked[1] = false;
    bool ok = true;
    sides.clear();
    if (!sides.reserve(sums.nFilled)) {
      sums.drain([](uint32_t, uint32_t, int32_t) {});
      return false;
    }
    sums.drain([&](uint32_t lo, uint32_t hi, int32_t net) {
      if (net == 0) return;
      if (net > 1 || net < -1) ok = false;
      (void)sides.push_back(net > 0 ? uint64_t(lo) << 32 | hi : uint64_t(hi) << 32 | lo);  // reserved
    });
    const size_t nb = sides.size();
    if (!ok || nb < 3) return false;
    std::sort(sides.begin(), sides.end());
    if (!byDest.resize(nb) || !into.resize(nb)) return false;
    for (size_t s = 0; s < nb; ++s) byDest[s] = sides[s] << 32 | sides[s] >> 32;
    std::sort(byDest.begin(), byDest.end());
    if (!readyForLoops()) return false;
    // The sides by destination (ties by origin), for the corners left more than once.
    for (size_t s = 0; s < nb; ++s) {
      const uint64_t side = byDest[s] << 32 | byDest[s] >> 32;
      into[s] = uint32_t(std::lower_bound(sides.begin(), sides.end(), side) - sides.begin());
    }
    return fewPieces();
  }

  // (2a) above: whether, projected along axis k, no two boundary sides meet other than in
  // a corner they share, and no two sides leaving or entering one corner overlap. The sides
  // go to the cells of a grid over the boundary's box (about one side a cell) that their
  // spans cover, and a pair is tested in the one cell where the overlap of their spans
  // begins: each pair whose spans overlap is tested once, whatever the boundary's shape (a
  // sweep along one axis meets every pair of sides along a line across it). False too past
  // a budget of cells and pairs (many sides in few cells): the node is then not certified.
  bool sidesApart(int k) {
    const size_t nb = sides.size();
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    float lo[2] = {w.p(origin(0))[i], w.p(origin(0))[j]}, hi[2] = {lo[0], lo[1]};
    for (size_t a = 1; a < nb; ++a) {  // every corner of the boundary is an origin
      const float* p = w.p(origin(a));
      lo[0] = std::min(lo[0], p[i]), hi[0] = std::max(hi[0], p[i]);
      lo[1] = std::min(lo[1], p[j]), hi[1] = std::max(hi[1], p[j]);
    }
    uint32_t g = 1;
    while (g < 1024 && size_t(g) * g < nb) ++g;
    double scale[2];
    for (int d = 0; d < 2; ++d) scale[d] = hi[d] > lo[d] ? g / (double(hi[d]) - lo[d]) : 0;
    // Monotone in x, so that overlapping spans share a cell.
    auto cell = [&](float x, int d) {
      const double q = (double(x) - lo[d]) * scale[d];
      return q <= 0 ? 0u : q >= g - 1 ? g - 1 : uint32_t(q);
    };
    if (!span.resize(4 * nb) || !cellStart.assign(size_t(g) * g + 1, 0)) return false;
    uint64_t entries = 0;
    for (size_t a = 0; a < nb; ++a) {
      const float *p = w.p(origin(a)), *q = w.p(dest(a));
      uint32_t* c = &span[4 * a];
      c[0] = cell(std::min(p[i], q[i]), 0), c[1] = cell(std::max(p[i], q[i]), 0);
      c[2] = cell(std::min(p[j], q[j]), 1), c[3] = cell(std::max(p[j], q[j]), 1);
      entries += uint64_t(c[1] - c[0] + 1) * (c[3] - c[2] + 1);
      if (entries > 16 * uint64_t(nb) + 4096) return false;
      for (uint32_t x = c[0]; x <= c[1]; ++x)
        for (uint32_t y = c[2]; y <= c[3]; ++y) ++cellStart[size_t(x) * g + y + 1];
    }
    for (size_t c = 0; c < size_t(g) * g; ++c) cellStart[c + 1] += cellStart[c];
    if (!cellItems.resize(entries) || !cellFill.resize(size_t(g) * g)) return false;
    for (size_t c = 0; c < size_t(g) * g; ++c) cellFill[c] = cellStart[c];
    for (size_t a = 0; a < nb; ++a) {
      const uint32_t* c = &span[4 * a];
      for (uint32_t x = c[0]; x <= c[1]; ++x)
        for (uint32_t y = c[2]; y <= c[3]; ++y) cellItems[cellFill[size_t(x) * g + y]++] = uint32_t(a);
    }
    uint64_t budget = 64 * uint64_t(nb) + 4096;
    for (uint32_t x = 0; x < g; ++x)
      for (uint32_t y = 0; y < g; ++y) {
        const uint32_t b0 = cellStart[size_t(x) * g + y], e0 = cellStart[size_t(x) * g + y + 1];
        for (uint32_t u = b0; u < e0; ++u) {
          const uint32_t a = cellItems[u];
          const uint32_t* ca = &span[4 * a];
          for (uint32_t v = u + 1; v < e0; ++v) {
            const uint32_t b = cellItems[v];
            const uint32_t* cb = &span[4 * b];
            // Tested here only when this is where their spans' overlap begins.
            if (std::max(ca[0], cb[0]) != x || std::max(ca[2], cb[2]) != y) continue;
            if ((checked[0] || checked[1]) && owner[a] == owner[b] && checked[owner[a]]) continue;
            if (--budget == 0) return false;
            if (!sidesApartPair(k, a, b)) return false;
          }
        }
      }
    return true;
  }

  // Whether sides a and b, projected along k, meet only in a corner they share, without
  // overlapping there (their spans need not overlap).
  bool sidesApartPair(int k, uint32_t a, uint32_t b) const {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const uint32_t au = origin(a), av = dest(a), bu = origin(b), bv = dest(b);
    const float *a0 = w.p(au), *a1 = w.p(av), *b0 = w.p(bu), *b1 = w.p(bv);
    if (std::max(a0[i], a1[i]) < std::min(b0[i], b1[i]) || std::max(b0[i], b1[i]) < std::min(a0[i], a1[i])) return true;
    if (std::max(a0[j], a1[j]) < std::min(b0[j], b1[j]) || std::max(b0[j], b1[j]) < std::min(a0[j], a1[j])) return true;
    // A shared corner c, with x and y the other ends: they overlap only along one ray.
    const uint32_t c = au == bu || au == bv ? au : av == bu || av == bv ? av : kInvalid;
    if (c == kInvalid) return !segSeg2d(k, a0, a1, b0, b1);
    const float* pc = w.p(c);
    const float* px = w.p(c == au ? av : au);
    const float* py = w.p(c == bu ? bv : bu);
    if (orient2dIn(k, pc, px, py) != 0) return true;
    const int m = pc[i] != px[i] ? i : j;  // c != x in projection (a side of a strict triangle)
    return !((px[m] < pc[m]) == (py[m] < pc[m]) && py[m] != pc[m]);
  }

  // Whether, projected along axis k, the boundary meets (2a), (2b) and (2c) above for
  // triangles that turn the way s.
  bool certifiedIn(int k, int s) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    if (!sidesApart(k)) return false;
    if (!linkLoops(k, s)) return false;
    // The loops do not cross: each is a (weakly) simple polygon, and its winding number is
    // 0 or its turn t (+1 counter-clockwise) off it. The triangles' count over a point is the
    // sum of the windings. It is 1 just left of every side (so 0 just right of it, and 0 or 1
    // everywhere, as every bounded region between the loops borders a side) when for each
    // loop L: [t(L) == s] + (sum of t(M) over the loops M around L) * s == 1.
    const size_t nl = loopEnd.size();
    if (nl > patch::kMaxLoops) return false;
    int turn[patch::kMaxLoops];
    size_t begin = 0;
    for (size_t l = 0; l < nl; ++l) {
      const size_t end = loopEnd[l];
      // The turn at its lowest corner (by i, then j), which it passes once.
      size_t best = begin;
      for (size_t x = begin + 1; x < end; ++x) {
        const float *p = w.p(origin(loops[x])), *q = w.p(origin(loops[best]));
        if (p[i] < q[i] || (p[i] == q[i] && p[j] < q[j])) best = x;
      }
      for (size_t x = begin; x < end; ++x)
        if (x != best && origin(loops[x]) == origin(loops[best])) return false;
      const size_t prev = best == begin ? end - 1 : best - 1;
      const int o = orient2dIn(k, w.p(origin(loops[prev])), w.p(origin(loops[best])), w.p(dest(loops[best])));
      if (o == 0) return false;  // cannot happen: no two sides from one corner overlap
      turn[l] = o;
      begin = end;
    }
    for (size_t l = 0; l < nl; ++l) {
      int around = 0;
      const size_t lb = l ? loopEnd[l - 1] : 0;
      for (size_t m = 0; m < nl; ++m) {
        if (m == l) continue;
        const size_t mb = m ? loopEnd[m - 1] : 0, me = loopEnd[m];
        // A corner of L that is not on M: M's winding there (L does not cross M).
        uint32_t v = kInvalid;
        for (size_t x = lb; x < loopEnd[l] && v == kInvalid; ++x) {
          const uint32_t c = origin(loops[x]);
          bool on = false;
          for (size_t y = mb; y < me && !on; ++y) on = origin(loops[y]) == c;
          if (!on) v = c;
        }
        if (v == kInvalid) return false;
        around += winding(k, w.p(v), mb, me);
      }
      if ((turn[l] == s ? 1 : 0) + around * s != 1) return false;
    }
    return true;
  }

  // The winding number of loop loops[b..e) around point p (on none of its sides), exactly:
  // crossings of the ray from p along +i, with p moved by (eps, eps^2) so that the ray meets
  // no corner.
  int winding(int k, const float* p, size_t b, size_t e) const {
    const int j = (k + 2) % 3;  // the ray runs along coordinate (k + 1) % 3
    int wn = 0;
    for (size_t x = b; x < e; ++x) {
      const float *u = w.p(origin(loops[x])), *v = w.p(dest(loops[x]));
      const bool uu = u[j] > p[j], vu = v[j] > p[j];
      if (uu == vu) continue;
      int o = orient2dIn(k, u, v, p);
      if (o == 0) o = v[j] > u[j] ? -1 : 1;  // the eps term: -(v.j - u.j)
      // Upwards (v above) with p on the left, or downwards with p on the right.
      if (vu && o > 0) ++wn;
      if (!vu && o < 0) --wn;
    }
    return wn;
  }

  // Cuts the sides into loops (`loops`, `loopEnd`) that do not cross: at a corner left more
  // than once, the sides around it must alternate between leaving and entering (by angle),
  // and a loop entering it leaves by the side that bounds the same covered wedge (the next
  // one clockwise for s > 0, counter-clockwise for s < 0). False when they do not alternate.
  bool linkLoops(int k, int s) {
    const size_t nb = sides.size();
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    size_t in = 0;  // into[in..]: the sides entering the corner at hand
    for (size_t a = 0; a < nb;) {
      const uint32_t v = origin(a);
      size_t e = a + 1;
      while (e < nb && origin(e) == v) ++e;
      while (in < nb && dest(into[in]) < v) ++in;
      if (e - a == 1) {
        next[into[in]] = uint32_t(a);
        ++in;
        a = e;
        continue;
      }
      // Corner v is left e - a times: its rays by angle (half-planes, then orientation).
      const float* pv = w.p(v);
      rays.clear();
      for (size_t x = a; x < e; ++x) (void)rays.push_back(Ray{uint32_t(x), true});  // reserved: nb
      for (size_t x = in; x < in + (e - a); ++x) (void)rays.push_back(Ray{into[x], false});
      auto end = [&](const Ray& r) { return w.p(r.out ? dest(r.side) : origin(r.side)); };
      auto half = [&](const float* x) { return x[j] > pv[j] || (x[j] == pv[j] && x[i] > pv[i]) ? 0 : 1; };
      std::sort(rays.begin(), rays.end(), [&](const Ray& x, const Ray& y) {
        const float *px = end(x), *py = end(y);
        const int hx = half(px), hy = half(py);
        if (hx != hy) return hx < hy;
        return orient2dIn(k, pv, px, py) > 0;
      });
      const size_t m = rays.size();
      for (size_t x = 0; x < m; ++x)
        if (rays[x].out == rays[(x + 1) % m].out) return false;
      for (size_t x = 0; x < m; ++x)
        if (!rays[x].out) next[rays[x].side] = rays[(s > 0 ? x + m - 1 : x + 1) % m].side;
      in += e - a;
      a = e;
    }
    loops.clear();
    loopEnd.clear();
    std::memset(taken.data(), 0, nb);
    for (size_t a = 0; a < nb; ++a) {
      if (taken[a]) continue;
      for (uint32_t x = uint32_t(a); !taken[x]; x = next[x]) {
        taken[x] = 1;
        (void)loops.push_back(x);  // reserved: nb
      }
      (void)loopEnd.push_back(uint32_t(loops.size()));
    }
    return true;
  }

  // `common`: the sign bits all the node's triangles have; `nonzero`: bit k when none of
  // them has a zero normal coordinate k. First the triangles as they are wound, along an axis
  // where they all turn one way; then, along an axis where they turn both ways but the
  // fewer turn the other way (flipped triangles in a mesh that is otherwise consistent), the
  // triangles wound to turn the way most do. A triangle's points are the same whichever way
  // it is wound, so the proof above holds for that chain as it stands, and the certificate
  // says the same of the node: no two of its triangles intersect.
  bool certify(uint32_t first, uint32_t end, uint8_t common, uint8_t nonzero, const uint8_t* signs) {
    flipped = 0;
    summed = false;
    if (common) {
      return boundary(first, end) && alongCommon(common, [&](int k, int s) {
        if (!certifiedIn(k, s)) return false;
        axis = k;
        return true;
      });
    }
    for (int k = 0; k < 3; ++k) {
      if (!(nonzero >> k & 1)) continue;
      uint32_t negative = 0;
      for (uint32_t q = first; q < end; ++q) negative += signs[q] >> (2 * k + 1) & 1;
      const uint32_t size = end - first;
      // Mostly one way: the few others are worth winding over (a fold, where the node's
      // triangles turn both ways in numbers, would fail the winding test anyway).
      const bool mostlyPositive = negative <= size / kMostlyOneWay;
      if (!mostlyPositive && size - negative > size / kMostlyOneWay) continue;
      const int s = mostlyPositive ? 1 : -1;
      const uint8_t flip = uint8_t(1u << (2 * k + (s > 0 ? 1 : 0)));
      if (boundary(first, end, signs, flip) && certifiedIn(k, s)) {
        flipped = flip;
        axis = k;
        return true;
      }
    }
    return false;
  }
  uint8_t flipped = 0;  // after certify() returned true: the flip it used (0: none)

  // Whether the union of two certified sibling nodes is certified, from their boundaries
  // (`a`, `b`: as merge() takes them), the axis each was certified along, and the flip each
  // was certified with (`flip`, the same for both): without a flip, along the axes and ways
  // all its triangles turn (`common`); with one, along its axis and way (the triangles turn
  // the other way only where that flip winds them over). Along a child's axis, the pairs of
  // its own sides passed sidesApart when it was certified, and are not tested again.
  bool certifyUnion(const uint64_t* a, size_t na, int axisA, const uint64_t* b, size_t nb, int axisB, uint8_t common,
                    uint8_t flip) {
    flipped = flip;
    if (!merge(a, na, b, nb)) return false;
    auto tryAxis = [&](int k, int s) {
      checked[0] = axisA == k;
      checked[1] = axisB == k;
      const bool ok = certifiedIn(k, s);
      checked[0] = checked[1] = false;
      if (ok) axis = k;
      return ok;
    };
    if (flip) {
      const int bit = lowestBit(flip);
      return tryAxis(bit / 2, bit & 1 ? 1 : -1);
    }
    return alongCommon(common, tryAxis);
  }
  // Whether f(k, s) holds for one of the axes k and ways s (+1, -1) whose bit 2k (s > 0) or
  // 2k + 1 (s < 0) is set in sign mask `common`, tried in that order.
  template <class F>
  static bool alongCommon(uint8_t common, F&& f) {
    for (int k = 0; k < 3; ++k)
      for (int s = 1; s >= -1; s -= 2)
        if ((common >> (2 * k + (s > 0 ? 0 : 1)) & 1) && f(k, s)) return true;
    return false;
  }
  // The wound-over certificate is tried when at most 1/kMostlyOneWay of a node's triangles
  // turn the other way.
  static constexpr uint32_t kMostlyOneWay = 8;
};

std::atomic<uint64_t> gPatchPositions{0};
std::atomic<bool> gPatchesOff{false};
std::atomic<uint32_t> gPatchMinimum{0};   // 0: patch::kMinPatch
std::atomic<uint32_t> gPatchTaskSize{0};  // 0: patch::kMaxPatch
std::atomic<uint32_t> gPatchTaskScale{0};  // 0: patch::kTaskScale
std::atomic<uint64_t> gPatchLarge{0};
std::atomic<uint64_t> gPatchUnions{0};
std::atomic<bool> gPatchUnionsOff{false};

// The roots of the subtrees that certifyPatches hands out: from the root down, a node
// skip(node) rules out is passed over, and a node of at most `most` positions (or a leaf) is a
// root; larger ones are split. False when out of memory.
template <class Skip>
bool subtreeRoots(const Bvh& bvh, uint32_t most, Skip&& skip, Array<uint32_t>& roots) {
  uint32_t todo[128];
  int sp = 0;
  todo[sp++] = 0;
  while (sp > 0) {
    const uint32_t id = todo[--sp];
    const Node& nd = bvh.nodes[id];
    if (skip(nd)) continue;
    if (nd.end - nd.first <= most || !nd.right) {
      if (!roots.push_back(id)) return false;
    } else {
      todo[sp++] = nd.right;
      todo[sp++] = id + 1;
    }
  }
  return true;
}

// f(certifier, part, root, nodes) for each of `roots` (a subtree's node ids are root to
// root + nodes - 1), the parts taking them in turn, each with a certifier of its own.
template <class F>
void eachSubtree(const Welded& w, const Bvh& bvh, const Array<uint32_t>& corner, unsigned parts,
                 const Array<uint32_t>& roots, F&& f) {
  std::atomic<uint32_t> next{0};
  detail::runParts(parts, [&](unsigned part) {
    PatchCertifier pc(w, corner);
    for (;;) {
      const uint32_t t = next.fetch_add(1, std::memory_order_relaxed);
      if (t >= roots.size()) break;
      const Node& top = bvh.nodes[roots[t]];
      f(pc, part, roots[t], 2 * ((top.end - top.first + kLeaf - 1) / kLeaf) - 1);
    }
  });
}

// Per node: 1 when no two of its triangles intersect (the certificate above); `signs`: per
// sorted position, signMask of its triangle; `inPatches`: the positions in certified nodes.
// The subtrees of at most kTaskScale * kMaxPatch positions are independent tasks: each
// computes its nodes' masks bottom up, tries its nodes above kMaxPatch whose triangles turn
// one way (patch::kTaskScale), and below the others tries the subtrees of at most kMaxPatch
// top down, each within a budget of 4 times its positions (a region where the tries keep
// failing, a soup, stops trying), so that the result is the same on any number of threads.
Status certifyPatches(const Welded& w, const Bvh& bvh, const Array<uint32_t>& corner, const Array<uint8_t>& signs,
                      unsigned threads, Array<uint8_t>& free, uint64_t& inPatches) {
  inPatches = 0;
  const uint32_t nn = uint32_t(bvh.nodes.size());
  if (!free.assign(nn, 0)) return oom("the patch certificates");
  if (nn == 0 || gPatchesOff.load(std::memory_order_relaxed)) return {};
  const uint32_t minPatch = gPatchMinimum.load(std::memory_order_relaxed) ? gPatchMinimum.load() : patch::kMinPatch;
  const uint32_t maxPatch = gPatchTaskSize.load(std::memory_order_relaxed) ? gPatchTaskSize.load() : patch::kMaxPatch;
  Array<uint32_t> tasks;  // subtree roots
  const uint32_t scale = gPatchTaskScale.load(std::memory_order_relaxed) ? gPatchTaskScale.load() : patch::kTaskScale;
  auto small = [&](const Node& nd) { return nd.end - nd.first < minPatch; };
  if (!subtreeRoots(bvh, scale * maxPatch, small, tasks)) return oom("the patch certificates");
  // Per node: the sign bits common to its triangles, and bit k when none has a zero normal
  // coordinate k.
  Array<uint8_t> nodeSigns, nodeNonzero;
  if (!nodeSigns.resize(nn) || !nodeNonzero.resize(nn)) return oom("the patch certificates");
  const uint32_t n = bvh.nodes[0].end;
  const unsigned parts = detail::partsFor(detail::threadCount(threads), n, detail::parallelGrain(32768));
  std::atomic<uint64_t> certified{0};
  // Per part: the boundaries of the nodes it certified, for the unions above the tasks.
  struct Kept {
    uint32_t node;
    uint8_t flip;
    int8_t axis;
    size_t first, count;  // its sides in the part's `keptSides`, then as many by destination
  };
  // The tasks' in [part], the unions' in [kMaxThreads + part].
  Array<Kept> kept[2 * detail::kMaxThreads];
  Array<uint64_t> keptSides[2 * detail::kMaxThreads];
  auto keep = [](const PatchCertifier& pc, uint32_t id, Array<Kept>& k, Array<uint64_t>& ks) {
    const size_t at = ks.size(), n = pc.sides.size();
    if (!ks.reserve(at + 2 * n) || !k.push_back(Kept{id, pc.flipped, int8_t(pc.axis), at, n})) return;
    for (uint64_t x : pc.sides) (void)ks.push_back(x);   // reserved
    for (uint64_t x : pc.byDest) (void)ks.push_back(x);  // reserved
  };
  eachSubtree(w, bvh, corner, parts, tasks, [&](PatchCertifier& pc, unsigned part, uint32_t root, uint32_t nodes) {
    for (uint32_t id = root + nodes; id-- > root;) {
      const Node& nd = bvh.nodes[id];
      if (nd.right) {
        nodeSigns[id] = nodeSigns[id + 1] & nodeSigns[nd.right];
        nodeNonzero[id] = nodeNonzero[id + 1] & nodeNonzero[nd.right];
      } else {
        uint8_t m = 0x3f, z = 0x7;
        for (uint32_t q = nd.first; q < nd.end; ++q) {
          const uint8_t g = signs[q];
          m &= g;
          z &= uint8_t(((g | g >> 1) & 1) | ((g >> 1 | g >> 2) & 2) | ((g >> 2 | g >> 3) & 4));
        }
        nodeSigns[id] = m;
        nodeNonzero[id] = z;
      }
    }
    uint64_t positions = 0;
    auto take = [&](uint32_t id) {
      const Node& nd = bvh.nodes[id];
      free[id] = 1;
      positions += nd.end - nd.first;
      keep(pc, id, kept[part], keptSides[part]);
    };
    // A subtree of at most maxPatch positions: its nodes top down, within a budget of 4 times
    // its positions.
    auto budgeted = [&](uint32_t sub) {
      const uint64_t budget = 4 * uint64_t(bvh.nodes[sub].end - bvh.nodes[sub].first);
      uint64_t tried = 0;
      uint32_t todo[64];
      int sp = 0;
      todo[sp++] = sub;
      while (sp > 0) {
        const uint32_t id = todo[--sp];
        const Node& nd = bvh.nodes[id];
        if (nd.end - nd.first < minPatch) continue;
        if ((nodeSigns[id] || nodeNonzero[id]) && tried < budget &&
            (tried += nd.end - nd.first, pc.certify(nd.first, nd.end, nodeSigns[id], nodeNonzero[id], signs.data()))) {
          take(id);
          continue;
        }
        if (nd.right) {
          todo[sp++] = nd.right;
          todo[sp++] = id + 1;
        }
      }
    };
    // Above maxPatch, top down: a node whose triangles all turn one way along an axis, or all
    // but a few (certify), is tried, outside the budget, until one such try fails after
    // summing its sides (patch::kTaskScale); the subtrees of at most maxPatch below the
    // others are tried as above.
    uint32_t todo[64];
    int sp = 0;
    bool largeFailed = false;
    todo[sp++] = root;
    while (sp > 0) {
      const uint32_t id = todo[--sp];
      const Node& nd = bvh.nodes[id];
      if (nd.end - nd.first < minPatch) continue;
      if (nd.end - nd.first <= maxPatch || !nd.right) {
        budgeted(id);
        continue;
      }
      if (!largeFailed && (nodeSigns[id] || nodeNonzero[id]) &&
          pc.certify(nd.first, nd.end, nodeSigns[id], nodeNonzero[id], signs.data())) {
        take(id);
        gPatchLarge.fetch_add(1, std::memory_order_relaxed);
        continue;
      }
      largeFailed = largeFailed || pc.summed;
      todo[sp++] = nd.right;
      todo[sp++] = id + 1;
    }
    certified.fetch_add(positions, std::memory_order_relaxed);
  });
  inPatches = certified.load();
  gPatchPositions.fetch_add(inPatches, std::memory_order_relaxed);
  // Above the tasks, bottom up: a node whose two children are certified (with the same flip)
  // is tried as their union, from their boundaries, so that the join skips the pairs
  // between them too. A clean mesh's tasks then join into patches of a large part of a
  // shell (the 1M-triangle torus: 126 unions, up to its two halves). The children stay certified;
  // their positions are counted once.
  if (gPatchUnionsOff.load(std::memory_order_relaxed)) return {};
  Array<uint32_t> at;  // per node: its entry in `kept` (list << 24 | index), or kInvalid
  if (!at.assign(nn, kInvalid)) return {};  // only the unions are lost
  for (unsigned part = 0; part < parts; ++part)
    for (size_t i = 0; i < kept[part].size() && i < (1u << 24); ++i)
      at[kept[part][i].node] = uint32_t(part) << 24 | uint32_t(i);
  // Node id as the union of its children, when both are certified; its boundary goes to list
  // kMaxThreads + part. Reads only its children's entries.
  auto tryUnion = [&](PatchCertifier& pc, uint32_t id, unsigned part) {
    const Node& nd = bvh.nodes[id];
    if (!nd.right || nd.end - nd.first <= maxPatch) return;  // a leaf, or in a task
    const uint32_t l = at[id + 1], r = at[nd.right];
    if (l == kInvalid || r == kInvalid) return;
    const Kept &kl = kept[l >> 24][l & 0xffffff], &kr = kept[r >> 24][r & 0xffffff];
    if (kl.flip != kr.flip) return;
    nodeSigns[id] = nodeSigns[id + 1] & nodeSigns[nd.right];
    if (!kl.flip && !nodeSigns[id]) return;
    if (!pc.certifyUnion(keptSides[l >> 24].data() + kl.first, kl.count, kl.axis, keptSides[r >> 24].data() + kr.first,
                         kr.count, kr.axis, nodeSigns[id], kl.flip))
      return;
    free[id] = 1;
    gPatchUnions.fetch_add(1, std::memory_order_relaxed);
    const unsigned list = detail::kMaxThreads + part;
    const uint32_t index = uint32_t(kept[list].size());
    if (index >= (1u << 24)) return;
    keep(pc, id, kept[list], keptSides[list]);
    if (kept[list].size() > index) at[id] = uint32_t(list) << 24 | index;
  };
  // The subtrees of at most `most` positions above the tasks are independent: the parts take
  // them in turn, each bottom up; then this thread the nodes above them. Each union depends
  // only on its children, so the result is the same on any number of threads.
  const uint32_t most = std::max(2 * maxPatch, n / (4 * parts));
  Array<uint32_t> subtrees;
  auto inTask = [&](const Node& nd) { return !nd.right || nd.end - nd.first <= maxPatch; };
  if (!subtreeRoots(bvh, most, inTask, subtrees)) return {};
  eachSubtree(w, bvh, corner, parts, subtrees, [&](PatchCertifier& pc, unsigned part, uint32_t root, uint32_t nodes) {
    for (uint32_t id = root + nodes; id-- > root;) tryUnion(pc, id, part);
  });
  PatchCertifier pc(w, corner);
  for (uint32_t id = nn; id-- > 0;)
    if (bvh.nodes[id].end - bvh.nodes[id].first > most) tryUnion(pc, id, 0);
  return {};
}
}  // namespace

Status geometry_detail::mortonCodesForTesting(const Mesh& mesh, Array<uint32_t>& fast, Array<uint32_t>& scalar) {
  const uint32_t nt = mesh.nTriangles();
  if (!fast.resize(nt) || !scalar.resize(nt)) return oom("the Morton codes");
  const MortonFrame frame(mesh);
  const Welded w{mesh, nullptr};
  for (uint32_t t = 0; t < nt; ++t) {
    const Tri x = triOf(w, t);
    fast[t] = frame.code(x.p[0], x.p[1], x.p[2]);
    scalar[t] = frame.scalarCode(x.p[0], x.p[1], x.p[2]);
  }
  return {};
}

Status geometry_detail::fanCertificatesForTesting(const Mesh& mesh, const Topology& topo, const TriangleChecks& checks,
                                                  Array<uint8_t>& certified) {
  const Welded w{mesh, weldOf(&topo)};
  Array<uint8_t> zero;
  Array<uint32_t> corner;
  if (!zero.assign(mesh.nTriangles(), 0) || !corner.reserve(3 * size_t(mesh.nTriangles())))
    return oom("the fan certificates");
  for (uint32_t t : checks.zeroArea) zero[t] = 1;
  for (uint32_t t = 0; t < mesh.nTriangles(); ++t) {
    const uint32_t a = w.v(t, 0), b = w.v(t, 1), c = w.v(t, 2);
    if (a != b && b != c && a != c && !zero[t]) (void)corner.push_back(a), (void)corner.push_back(b), (void)corner.push_back(c);
  }
  Array<uint16_t> state;
  if (Status s = certifyVertices(w, topo, checks.zeroArea, corner.data(), uint32_t(corner.size() / 3), state); !s.ok())
    return s;
  if (!certified.resize(state.size())) return oom("the fan certificates");
  for (size_t v = 0; v < state.size(); ++v) certified[v] = uint8_t(state[v]);
  return {};
}
uint64_t geometry_detail::fanCertifiedVerticesForTesting() { return gFanCertified.load(std::memory_order_relaxed); }
uint64_t geometry_detail::fanSkippedPairsForTesting() { return gFanSkipped.load(std::memory_order_relaxed); }
uint64_t geometry_detail::patchCertifiedPositionsForTesting() {
  return gPatchPositions.load(std::memory_order_relaxed);
}
void geometry_detail::setPatchCertificatesForTesting(bool on) { gPatchesOff.store(!on, std::memory_order_relaxed); }
void geometry_detail::setPatchMinimumForTesting(uint32_t positions) {
  gPatchMinimum.store(positions, std::memory_order_relaxed);
}
uint64_t geometry_detail::patchLargeNodesForTesting() { return gPatchLarge.load(std::memory_order_relaxed); }
void geometry_detail::setPatchTaskSizeForTesting(uint32_t positions, uint32_t scale) {
  gPatchTaskSize.store(positions, std::memory_order_relaxed);
  gPatchTaskScale.store(scale, std::memory_order_relaxed);
}
uint64_t geometry_detail::patchUnionsForTesting() { return gPatchUnions.load(std::memory_order_relaxed); }
void geometry_detail::setPatchUnionsForTesting(bool on) { gPatchUnionsOff.store(!on, std::memory_order_relaxed); }

namespace {

// One run of the self-join from a (node, node) pair: its pairs found, its work (pair tests
// of overlapping boxes) and why it stopped. The serial pass is one run from the root; the
// threaded one runs tasks (pairs below the root) and adds up their counts.
struct JoinRun {
  Array<Found> found;
  uint64_t work = 0;
  uint64_t sinceProgress = 0;  // positions joined since the last progress report
  uint64_t maxWork = ~uint64_t(0), maxFound = ~uint64_t(0);  // stop past these (the serial limits)
  uint64_t fanSkipped = 0;  // pairs skipped by a certified vertex (a test hook's count)
  bool stop = false, outOfMemory = false;
};

// The exact tests of positions p < q (a's corners ma shared with b's mb), for the pairs the
// join does not skip; out of line, so that the skipping loop (testMask) stays small.
STLTOPO_NOINLINE void testPositions(const JoinInput& in, JoinRun& r, uint32_t p, uint32_t q, unsigned ma,
                                    unsigned mb) {
  const Tri a = in.triAt(p), b = in.triAt(q);
  if (ma && neighboursApart(a, b, ma, mb)) return;
  Found f;
  const int kind = testPair(a, b, f.point);
  if (kind < 0) return;
  const uint32_t ti = in.bvh.tri[p], tj = in.bvh.tri[q];
  f.key = ti < tj ? uint64_t(ti) << 32 | tj : uint64_t(tj) << 32 | ti;
  f.kind = uint8_t(kind);
  if (!r.found.push_back(f)) {
    r.outOfMemory = r.stop = true;
    return;
  }
  if (r.found.size() >= r.maxFound) r.stop = true;
}

// Tests p against the positions of the leaf from `first` in `mask` (their boxes overlap
// p's), in increasing order, until the run stops. Each counts as work (the limit), then the
// pairs of one duplicate group and those sharing a certified vertex (testPair would return
// -1 for them) are skipped.
inline void testMask(const JoinInput& in, JoinRun& r, uint32_t p, uint32_t first, uint32_t mask) {
  const uint32_t* cp = &in.corner[3 * size_t(p)];
  const unsigned fan = in.fan ? in.fan[p] : 0u;
  for (; mask && !r.stop; mask &= mask - 1) {
    const uint32_t q = first + uint32_t(lowestBit(mask));
    if (++r.work > r.maxWork) {
      r.stop = true;
      return;
    }
    unsigned ma, mb;
    sharedCorners(cp, &in.corner[3 * size_t(q)], ma, mb);
    if (ma == 7) continue;  // one duplicate group
    if (ma & fan) {
      ++r.fanSkipped;
      continue;
    }
    testPositions(in, r, p, q, ma, mb);
  }
}

// The positions a (node, node) pair covers: the size of its part of the join.
inline uint32_t pairSize(const Bvh& bvh, uint64_t pair) {
  const Node &A = bvh.nodes[uint32_t(pair >> 32)], &B = bvh.nodes[uint32_t(pair)];
  return uint32_t(pair >> 32) == uint32_t(pair) ? A.end - A.first : (A.end - A.first) + (B.end - B.first);
}

// A self-join of the hierarchy from `start`: (node, node) pairs on an explicit stack; a
// pair of the same node stands for the pairs inside it. Each pair of positions is tested
// once. A pop pushes at most 3 pairs one level deeper (the depth of a pair: the sum of its
// nodes' depths, at most 2 * 30 for 2^32 triangles) and the next pop takes one of them, so
// at most 2 wait per level: the stack never holds more than 121 entries.
// With `tasks`, pairs of at most `taskSize` positions are not joined but appended to it, in
// the order the join would have reached them: joining the tasks one after another then makes
// the same tests in the same order. `tick` is called after each leaf's tests (progress).
template <class Tick>
void joinFrom(const JoinInput& in, JoinRun& r, uint64_t start, Array<uint64_t>* tasks, uint32_t taskSize,
              Tick&& tick) {
  const Bvh& bvh = in.bvh;
  const BoxColumns& boxes = in.boxes();
  uint64_t todo[256];
  int sp = 0;
  todo[sp++] = start;
  while (sp > 0 && !r.stop) {
    const uint64_t top = todo[--sp];
    if (tasks && pairSize(bvh, top) <= taskSize) {
      if (!tasks->push_back(top)) r.outOfMemory = r.stop = true;
      continue;
    }
    const uint32_t ia = uint32_t(top >> 32), ib = uint32_t(top);
    const Node& A = bvh.nodes[ia];
    const Node& B = bvh.nodes[ib];
    if (ia == ib) {
      if (in.free[ia]) continue;  // a certified patch: no pair inside it intersects
      if (A.right) {
        const uint32_t l = ia + 1, rt = A.right;
        todo[sp++] = uint64_t(l) << 32 | rt;
        todo[sp++] = uint64_t(rt) << 32 | rt;
        todo[sp++] = uint64_t(l) << 32 | l;
      } else {
        // The pairs p < q inside the leaf, p-major, as two nested loops over positions.
        const uint32_t all = (1u << (A.end - A.first)) - 1;
        for (uint32_t p = A.first; p < A.end && !r.stop; ++p) {
          const uint32_t later = all & ~((2u << (p - A.first)) - 1);
          if (later) testMask(in, r, p, A.first, overlapMask(boxes, A.first, in.boxAt(p)) & later);
        }
        r.sinceProgress += A.end - A.first;
        tick(ia);
      }
      continue;
    }
    if (!overlaps(A.box, B.box)) continue;
    if (!A.right && !B.right) {
      // Only the members of each leaf whose box meets the other leaf's box can pair; p-major,
      // q increasing, as two nested loops over positions.
      const uint32_t qs = overlapMask(boxes, B.first, A.box) & ((1u << (B.end - B.first)) - 1);
      if (qs) {
        uint32_t ps = overlapMask(boxes, A.first, B.box) & ((1u << (A.end - A.first)) - 1);
        for (; ps && !r.stop; ps &= ps - 1) {
          const uint32_t p = A.first + uint32_t(lowestBit(ps));
          testMask(in, r, p, B.first, overlapMask(boxes, B.first, in.boxAt(p)) & qs);
        }
      }
      r.sinceProgress += A.end - A.first;
      tick(ia);
    } else if (A.right && (!B.right || A.end - A.first >= B.end - B.first)) {
      todo[sp++] = uint64_t(A.right) << 32 | ib;
      todo[sp++] = uint64_t(ia + 1) << 32 | ib;
    } else {
      todo[sp++] = uint64_t(ia) << 32 | B.right;
      todo[sp++] = uint64_t(ia) << 32 | (ib + 1);
    }
  }
}

// The join on `parts` threads: the pairs of up to `taskSize` positions below the root
// become tasks, which the threads take in turn. Every task is joined whole, so the pairs
// found are the serial join's (in another order: the caller sorts them), and the work the
// sum of the tasks'. The serial limits apply to those sums: when they are reached (or nearly:
// the threads stop early once the totals they have published pass them), `limited` is set
// and the caller runs the serial join, whose truncated list depends on its order.
// Progress is reported (and cancelled) on the calling thread only: part 0.
struct ParallelJoin {
  ParallelJoin(const JoinInput& i, uint64_t mw, uint64_t mf, const IntersectionOptions& o)
      : in(i), maxWork(mw), maxFound(mf), options(o) {}
  const JoinInput& in;
  uint64_t maxWork, maxFound;
  const IntersectionOptions& options;
  Array<uint64_t> tasks;
  JoinRun runs[detail::kMaxThreads];  // one per part
  std::atomic<uint32_t> next{0}, done{0};
  std::atomic<uint64_t> workPublished{0}, foundPublished{0};
  std::atomic<bool> halt{false};
  unsigned nRuns = 0;
  uint64_t work = 0;  // the tasks' work, summed
  bool limited = false, cancelled = false, outOfMemory = false;

  void part(unsigned id) {
    JoinRun& r = runs[id];
    uint64_t workSeen = 0, foundSeen = 0;
    auto publish = [&] {
      const uint64_t wk = workPublished.fetch_add(r.work - workSeen, std::memory_order_relaxed) + (r.work - workSeen);
      const uint64_t fd =
          foundPublished.fetch_add(r.found.size() - foundSeen, std::memory_order_relaxed) + (r.found.size() - foundSeen);
      workSeen = r.work, foundSeen = r.found.size();
      if (wk > maxWork || fd >= maxFound) halt.store(true, std::memory_order_relaxed);
    };
    auto tick = [&](uint32_t) {
      if (r.work - workSeen >= 4096) {
        publish();
        if (halt.load(std::memory_order_relaxed)) r.stop = true;
      }
    };
    for (;;) {
      if (halt.load(std::memory_order_relaxed)) break;
      const uint32_t t = next.fetch_add(1, std::memory_order_relaxed);
      if (t >= tasks.size()) break;
      joinFrom(in, r, tasks[t], nullptr, 0, tick);
      publish();
      if (r.outOfMemory) halt.store(true, std::memory_order_relaxed);
      if (r.stop) break;
      const uint32_t finished = done.fetch_add(1, std::memory_order_relaxed) + 1;
      if (id == 0 && options.progress && !options.progress(options.user, double(finished) / double(tasks.size()))) {
        cancelled = true;
        halt.store(true, std::memory_order_relaxed);
        break;
      }
    }
  }

  // Runs the tasks; false when the serial join must decide (a limit, or nothing to gain).
  Status run(unsigned parts, uint32_t taskSize) {
    JoinRun split;
    joinFrom(in, split, 0, &tasks, taskSize, [](uint32_t) {});
    if (split.outOfMemory) return oom("the intersection tasks");
    nRuns = parts;
    detail::runParts(parts, [this](unsigned id) { part(id); });
    for (unsigned i = 0; i < nRuns; ++i) outOfMemory = outOfMemory || runs[i].outOfMemory;
    if (outOfMemory) return oom("the intersection list");
    if (cancelled) return Status::error(Code::Aborted, "aborted: the intersection pass was stopped by the caller");
    uint64_t found = 0;
    work = 0;
    for (unsigned i = 0; i < nRuns; ++i) work += runs[i].work, found += runs[i].found.size();
    limited = halt.load() || work > maxWork || found >= maxFound;
    return {};
  }
};

}  // namespace

Status findIntersections(const Mesh& mesh, const Topology& topo, const TriangleChecks& checks, Intersections& out,
                         const IntersectionOptions& options) {
  out = Intersections{};
  if (Status s = checkWeld(mesh, &topo); !s.ok()) return s;
  const uint32_t nt = mesh.nTriangles();
  const Welded w{mesh, weldOf(&topo)};
  Array<uint8_t> valid;
  if (!valid.assign(nt, 1) || !out.triangleIntersects.assign(nt, 0)) return oom("the intersection flags");
  if (topo.triangleDegenerate.size() == nt) {
    // The topology's flags are this rule on the same welded corners (validate() checks them
    // so): a byte per triangle read instead of its three corners.
    const uint8_t* degenerate = topo.triangleDegenerate.data();
    detail::forChunks(0, nt, [&](size_t t0, size_t t1) {
      for (size_t t = t0; t < t1; ++t) valid[t] = uint8_t(degenerate[t] == 0);
    });
  } else {
    detail::forChunks(0, nt, [&](size_t t0, size_t t1) {
      for (uint32_t t = uint32_t(t0); t < t1; ++t) {
        uint32_t a = w.v(t, 0), b = w.v(t, 1), c = w.v(t, 2);
        if (a == b || b == c || a == c) valid[t] = 0;
      }
    });
  }
  for (uint32_t t : checks.zeroArea) {
    if (t >= nt) return Status::error(Code::InvalidArgument, "the triangle checks are not this mesh's");
    valid[t] = 0;
  }
  Bvh bvh;
  // The hierarchy, with the corners of each sorted position and its triangle's sign mask.
  Array<uint32_t> corner;
  Array<uint8_t> signs;
  if (Status s = buildBvh(w, valid, bvh, true, options.threads, &corner, &signs); !s.ok()) return s;
  valid.release();
  const uint32_t n = uint32_t(bvh.tri.size());
  Array<uint8_t> free;
  uint64_t inPatches = 0;
  if (Status s = certifyPatches(w, bvh, corner, signs, options.threads, free, inPatches); !s.ok()) return s;
  signs.release();
  // The fan certificates pay where the join still meets many pairs: when patches hold all but
  // at most 1/16 of the positions, the pairs left (between patches, and in the rest) are few,
  // and neighboursApart decides those that share corners (the result is the same).
  // (Without them, no array: the join reads no fan bits, rather than a megabyte of zeros.)
  Array<uint8_t> fan;
  const bool fans = inPatches < n - n / 16;
  if (fans) {
    if (Status s = certifyFans(w, topo, checks.zeroArea, corner, n, options.threads, fan); !s.ok()) return s;
  }
  const JoinInput in{w, bvh, corner, fans ? fan.data() : nullptr, free.data()};
  const uint64_t maxFound = options.maxPairs;
  const uint64_t maxWork = geometry_detail::workLimit(options.maxPairs, nt);

  // Threads: a part per thread, each taking tasks of about 1/64 of a part's positions.
  const unsigned parts = detail::partsFor(detail::threadCount(options.threads), n, detail::parallelGrain(32768));
  Array<Found> found;
  bool complete = true, cancelled = false;
  bool serial = parts <= 1 || n == 0;
  if (!serial) {
    ParallelJoin pj(in, maxWork, maxFound, options);
    const uint32_t taskSize = std::max<uint32_t>(4 * kLeaf, n / (64 * parts));
    if (Status s = pj.run(parts, taskSize); !s.ok()) return s;
    if (pj.limited) {
      serial = true;  // the truncated list is the serial join's
    } else {
      size_t total = 0;
      for (unsigned i = 0; i < pj.nRuns; ++i) total += pj.runs[i].found.size();
      if (!found.reserve(total)) return oom("the intersection list");
      out.work = pj.work;
      for (unsigned i = 0; i < pj.nRuns; ++i) {
        for (const Found& f : pj.runs[i].found) (void)found.push_back(f);  // reserved
        gFanSkipped.fetch_add(pj.runs[i].fanSkipped, std::memory_order_relaxed);
      }
    }
  }
  if (serial && n > 0) {
    JoinRun r;
    r.maxWork = maxWork;
    r.maxFound = maxFound;
    const uint64_t progressEvery = 1u << 18;
    joinFrom(in, r, 0, nullptr, 0, [&](uint32_t ia) {
      if (r.sinceProgress >= progressEvery && options.progress) {
        r.sinceProgress = 0;
        // The fraction: the positions below the current leaf's are done, roughly.
        if (!options.progress(options.user, double(bvh.nodes[ia].first) / n)) cancelled = r.stop = true;
      }
    });
    if (r.outOfMemory) return oom("the intersection list");
    gFanSkipped.fetch_add(r.fanSkipped, std::memory_order_relaxed);
    complete = !r.stop;
    out.work = r.work;
    found = std::move(r.found);
  }
  if (cancelled) return Status::error(Code::Aborted, "aborted: the intersection pass was stopped by the caller");
  out.complete = complete;
  std::sort(found.begin(), found.end(), [](const Found& x, const Found& y) { return x.key < y.key; });
  const size_t np = found.size();
  if (!out.pairs.resize(2 * np) || !out.kinds.resize(np) || !out.points.resize(3 * np))
    return oom("the intersection list");
  for (size_t i = 0; i < np; ++i) {
    const Found& f = found[i];
    const uint32_t ti = uint32_t(f.key >> 32), tj = uint32_t(f.key);
    out.pairs[2 * i] = ti;
    out.pairs[2 * i + 1] = tj;
    out.kinds[i] = f.kind;
    for (int c = 0; c < 3; ++c) out.points[3 * i + c] = f.point[c];
    geometry_detail::countPair(out, ti, tj, f.kind);
  }
  if (options.progress && !options.progress(options.user, 1.0))
    return Status::error(Code::Aborted, "aborted: the intersection pass was stopped by the caller");
  return {};
}

// ---------------------------------------------------------------------------
// Shell nesting.

namespace {

// The sign of orient2d(p, u, v) in the (y, z) plane with p moved by (eps, eps^2), eps
// infinitesimal (simulation of simplicity): never 0 unless u and v project to one point.
int perturbedSide(const float* p, const float* u, const float* v) {
  int s = pred::orient2d(p[1], p[2], u[1], u[2], v[1], v[2]);
  if (s) return s;
  if (u[2] != v[2]) return u[2] > v[2] ? 1 : -1;
  if (v[1] != u[1]) return v[1] > u[1] ? 1 : -1;
  return 0;
}

// Whether the ray from p along +x, p perturbed as above, crosses triangle t: 1 yes, 0 no,
// -1 when p lies on t (never for a p off the surface).
int rayHits(const float* p, const Tri& t) {
  const int s0 = perturbedSide(p, t.p[0], t.p[1]);
  const int s1 = perturbedSide(p, t.p[1], t.p[2]);
  const int s2 = perturbedSide(p, t.p[2], t.p[0]);
  if (s0 == 0 || s0 != s1 || s1 != s2) return 0;
  // Inside the projection, whose orientation s0 is the sign of the normal's x. The plane
  // is crossed at x > p.x when p lies on the side the normal's x points away from.
  const int o = pred::orient3d(t.p[0], t.p[1], t.p[2], p);
  if (o == 0) return -1;
  return o != s0 ? 1 : 0;
}

}  // namespace

Status findShellNesting(const Mesh& mesh, const Topology& topo, const Array<Shell>& shells, const Intersections& found,
                        ShellNesting& out) {
  out = ShellNesting{};
  if (Status s = checkWeld(mesh, &topo); !s.ok()) return s;
  const uint32_t nt = mesh.nTriangles(), ns = uint32_t(shells.size());
  if (topo.triangleShell.size() != nt || ns != topo.nShells || found.triangleIntersects.size() != nt)
    return Status::error(Code::InvalidArgument, "shell nesting needs the shells and the intersections of this mesh");
  const Welded w{mesh, weldOf(&topo)};
  // What each shell intersects.
  Array<uint64_t> links;  // s << 32 | k for shells s != k that intersect
  if (!out.selfIntersects.assign(ns, 0)) return oom("the shell nesting");
  for (size_t i = 0; i < found.nPairs(); ++i) {
    const uint32_t a = topo.triangleShell[found.pairs[2 * i]], b = topo.triangleShell[found.pairs[2 * i + 1]];
    if (a == b) {
      out.selfIntersects[a] = 1;
    } else if (!links.push_back(uint64_t(a) << 32 | b) || !links.push_back(uint64_t(b) << 32 | a)) {
      return oom("the shell nesting");
    }
  }
  std::sort(links.begin(), links.end());
  size_t nl = size_t(std::unique(links.begin(), links.end()) - links.begin());
  if (!out.intersectsOffsets.assign(size_t(ns) + 1, 0) || !out.intersectsShells.resize(nl))
    return oom("the shell nesting");
  for (size_t i = 0; i < nl; ++i) {
    ++out.intersectsOffsets[(links[i] >> 32) + 1];
    out.intersectsShells[i] = uint32_t(links[i]);
  }
  for (uint32_t s = 0; s < ns; ++s) out.intersectsOffsets[s + 1] += out.intersectsOffsets[s];
  links.release();
  if (!out.parent.assign(ns, kInvalid) || !out.depth.assign(ns, kInvalid)) return oom("the shell nesting");
  // The candidates: closed shells that meet no other shell.
  Array<uint8_t> candidate;
  if (!candidate.assign(ns, 0)) return oom("the shell nesting");
  uint32_t nCand = 0;
  for (uint32_t s = 0; s < ns; ++s) {
    candidate[s] = shells[s].closed() && out.intersectsOffsets[s + 1] == out.intersectsOffsets[s];
    nCand += candidate[s];
  }
  if (nCand == 0) return {};
  if (nCand == 1) {
    // One candidate: no other candidate's triangles can surround it (the rays below only
    // count the other candidates' triangles), so it is at the top level; no hierarchy needed.
    for (uint32_t s = 0; s < ns; ++s)
      if (candidate[s]) out.depth[s] = 0;
    return {};
  }
  // Shells that share a vertex are never nested: per vertex, its first shell; a pair is
  // recorded when a vertex is used by another one.
  Array<uint32_t> vshell;
  Array<uint64_t> touching;
  if (!vshell.assign(mesh.nVertices(), kInvalid)) return oom("the shell nesting");
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t s = topo.triangleShell[t];
    if (s == kInvalid || !candidate[s]) continue;
    for (int c = 0; c < 3; ++c) {
      uint32_t& vs = vshell[w.v(t, c)];
      if (vs == kInvalid)
        vs = s;
      else if (vs != s && (!touching.push_back(uint64_t(vs) << 32 | s) || !touching.push_back(uint64_t(s) << 32 | vs)))
        return oom("the shell nesting");
    }
  }
  std::sort(touching.begin(), touching.end());
  touching.shrink(size_t(std::unique(touching.begin(), touching.end()) - touching.begin()));
  // A hierarchy over the candidates' triangles (zero-area ones have no projected area and
  // are never crossed; degenerate ones belong to no shell).
  Array<uint8_t> valid;
  if (!valid.assign(nt, 0)) return oom("the shell nesting");
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t s = topo.triangleShell[t];
    valid[t] = s != kInvalid && candidate[s];
  }
  Bvh bvh;
  if (Status s = buildBvh(w, valid, bvh, false); !s.ok()) return s;
  valid.release();
  // One ray per candidate shell, from its lowest triangle's first corner; the parity of
  // the crossings per other shell says whether that shell contains it.
  Array<uint32_t> inside;  // per candidate shell: the shells containing it, in list form
  Array<uint32_t> insideOff;
  if (!insideOff.assign(size_t(ns) + 1, 0)) return oom("the shell nesting");
  Array<uint32_t> hits;
  uint32_t stack[64];
  for (uint32_t a = 0; a < ns; ++a) {
    insideOff[a + 1] = insideOff[a];
    if (!candidate[a]) continue;
    const float* p = w.p(w.v(shells[a].firstTriangle, 0));
    hits.clear();
    bool onSurface = false;
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0 && !onSurface) {
      const Node& node = bvh.nodes[stack[--sp]];
      const Box& b = node.box;
      if (b.hi[0] < p[0] || b.lo[1] > p[1] || b.hi[1] < p[1] || b.lo[2] > p[2] || b.hi[2] < p[2]) continue;
      if (node.right) {
        stack[sp++] = node.right;
        stack[sp++] = uint32_t(&node - bvh.nodes.data()) + 1;
        continue;
      }
      for (uint32_t q = node.first; q < node.end; ++q) {
        const Box& tb = bvh.box[q];
        if (tb.hi[0] < p[0] || tb.lo[1] > p[1] || tb.hi[1] < p[1] || tb.lo[2] > p[2] || tb.hi[2] < p[2]) continue;
        const uint32_t t = bvh.tri[q];
        const uint32_t s = topo.triangleShell[t];
        if (s == a) continue;
        const int h = rayHits(p, triOf(w, t));
        if (h == 0) continue;
        // A shell that shares a vertex with a is never a's container, and p may be that
        // vertex: its triangles there hold p, which must not void a's other answers.
        if (std::binary_search(touching.begin(), touching.end(), uint64_t(a) << 32 | s)) continue;
        if (h < 0) onSurface = true;
        if (h > 0 && !hits.push_back(s)) return oom("the shell nesting");
      }
    }
    // p on a shell that shares no vertex with a: a triangle of a touches it, a pair, so a is
    // no candidate; cannot happen.
    if (onSurface) continue;
    std::sort(hits.begin(), hits.end());
    for (size_t i = 0; i < hits.size();) {
      size_t j = i;
      while (j < hits.size() && hits[j] == hits[i]) ++j;
      const uint32_t b = hits[i];
      if ((j - i) % 2 == 1) {
        if (!inside.push_back(b)) return oom("the shell nesting");
        ++insideOff[a + 1];
      }
      i = j;
    }
  }
  // depth = the number of shells around; parent = the one of them with the largest depth.
  for (uint32_t a = 0; a < ns; ++a) {
    if (!candidate[a]) continue;
    out.depth[a] = insideOff[a + 1] - insideOff[a];
  }
  for (uint32_t a = 0; a < ns; ++a) {
    if (!candidate[a]) continue;
    uint32_t best = kInvalid;
    for (uint32_t i = insideOff[a]; i < insideOff[a + 1]; ++i) {
      const uint32_t b = inside[i];
      if (best == kInvalid || out.depth[b] > out.depth[best] || (out.depth[b] == out.depth[best] && b < best)) best = b;
    }
    out.parent[a] = best;
  }
  return {};
}

namespace {
// isSolid's conditions that need no shell.
bool solidButForShells(const Topology& topo, const TriangleChecks& checks, const Intersections& found) {
  return topo.watertight() && topo.manifold() && checks.zeroArea.empty() && checks.nDuplicateTriangles == 0 &&
         found.complete && found.nPairs() == 0;
}
}  // namespace

bool isSolid(const Topology& topo, const TriangleChecks& checks, const Intersections& found, const Array<Shell>& shells,
             const ShellNesting& nesting) {
  if (!solidButForShells(topo, checks, found)) return false;
  if (!nesting.isOf(shells.size())) return false;
  for (size_t s = 0; s < shells.size(); ++s) {
    if (nesting.depth[s] == kInvalid) return false;
    const Orientation o = shells[s].orientation();
    if (o != (nesting.depth[s] % 2 == 0 ? Orientation::Outward : Orientation::Inward)) return false;
  }
  return true;
}

Status analyzeGeometry(const Mesh& mesh, const Topology& topo, GeometryReport& out,
                       const IntersectionOptions& options) {
  return analyzeGeometry(mesh, topo, out, options, true);
}

Status analyzeGeometry(const Mesh& mesh, const Topology& topo, GeometryReport& out, const IntersectionOptions& options,
                       bool shellList) {
  out.solid = false;
  out.shells = Array<Shell>{};
  out.nesting = ShellNesting{};
  Status s = checkTriangles(mesh, &topo, out.checks, options.threads);
  if (s.ok()) s = analyzeGeometryAfterChecks(mesh, topo, out, options, shellList);
  return s;
}

Status analyzeGeometryAfterChecks(const Mesh& mesh, const Topology& topo, GeometryReport& out,
                                  const IntersectionOptions& options, bool shellList) {
  out.solid = false;
  out.shells = Array<Shell>{};
  out.nesting = ShellNesting{};
  Status s = findIntersections(mesh, topo, out.checks, out.intersections, options);
  if (s.ok())
    s = shellList ? geometry_detail::finishGeometry(mesh, topo, out) : geometry_detail::finishSolid(mesh, topo, out);
  return s;
}

Status geometry_detail::finishSolid(const Mesh& mesh, const Topology& topo, GeometryReport& out) {
  out.solid = false;
  // Without isSolid's conditions that need no shell, no shell pass.
  const TriangleChecks& checks = out.checks;
  const Intersections& found = out.intersections;
  if (!solidButForShells(topo, checks, found)) return {};
  Array<Shell> shells;
  ShellNesting nesting;
  Status s = watertightShells(mesh, topo, shells);
  if (s.ok()) s = findShellNesting(mesh, topo, shells, found, nesting);
  if (s.ok()) out.solid = isSolid(topo, checks, found, shells, nesting);
  return s;
}

Status geometry_detail::finishGeometry(const Mesh& mesh, const Topology& topo, GeometryReport& out) {
  out.solid = false;
  Status s = findShellsAndDefects(mesh, topo, &out.shells, nullptr);
  if (s.ok()) s = findShellNesting(mesh, topo, out.shells, out.intersections, out.nesting);
  if (s.ok()) out.solid = isSolid(topo, out.checks, out.intersections, out.shells, out.nesting);
  return s;
}

}  // namespace stltopo
