// Exact geometric predicates on float32 points (private to the core).
//
// Every function returns the exact sign of its determinant: a floating-point filter
// decides the clear cases, and expansion arithmetic (Shewchuk's two-sum/two-product
// expansions, written out in predicates.cpp) decides the rest. There is no epsilon
// anywhere. The inputs are float32 values, which are exact doubles; the filters' error
// bounds are Shewchuk's for double inputs, and no product of at most three float32
// differences can underflow or overflow a double, so the bounds hold for every input.
#pragma once

#include <cmath>
#include <cstdint>

namespace stltopo::pred {

// The exact signs, for the rare inputs the filters cannot decide: in 128-bit integers when the
// coordinates span at most 40 bits of magnitude (almost always), else in expansion arithmetic.
int orient2dExact(double ax, double ay, double bx, double by, double cx, double cy);
int orient3dExact(const float* a, const float* b, const float* c, const float* d);
// The expansion arithmetic alone (for any inputs; the tests compare the two stages).
int orient2dExpansion(double ax, double ay, double bx, double by, double cx, double cy);
int orient3dExpansion(const float* a, const float* b, const float* c, const float* d);

// A zero bound decides exactly too (zeroTerms): the bound is 0 only when every product in the
// determinant is 0, and a computed product of float32 differences is 0 only when a factor is
// exactly 0 (a difference of two floats rounds to 0 only when they are equal, and no product
// of at most three of them underflows), so the exact determinant is 0. Points on one axis-
// aligned line or plane (a flat face of a CAD part) are decided so without the exact stage.

// Sign of (b - a) x (c - a) in the plane (ax, ay) ...: > 0 when a, b, c turn
// counter-clockwise.
// (Always inlined: the triangle checks, compiled at -Oz in wasm, call it once per triangle.)
__attribute__((always_inline)) inline int orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double l = (bx - ax) * (cy - ay), r = (by - ay) * (cx - ax);
  const double det = l - r;
  const double bound = 3.3306690738754716e-16 * (std::fabs(l) + std::fabs(r));  // (3 + 16 eps) eps
  if (det > bound) return 1;
  if (-det > bound) return -1;
  if (bound == 0) return 0;  // zeroTerms
  return orient2dExact(ax, ay, bx, by, cx, cy);
}

// Sign of det[b - a, c - a, d - a] = ((b - a) x (c - a)) . (d - a): > 0 when d lies on the
// side the normal of the triangle (a, b, c) points to (counter-clockwise seen from d).
inline int orient3d(const float* a, const float* b, const float* c, const float* d) {
  const double ux = double(b[0]) - a[0], uy = double(b[1]) - a[1], uz = double(b[2]) - a[2];
  const double vx = double(c[0]) - a[0], vy = double(c[1]) - a[1], vz = double(c[2]) - a[2];
  const double wx = double(d[0]) - a[0], wy = double(d[1]) - a[1], wz = double(d[2]) - a[2];
  const double m1 = uy * vz, m2 = uz * vy, m3 = uz * vx, m4 = ux * vz, m5 = ux * vy, m6 = uy * vx;
  const double det = wx * (m1 - m2) + wy * (m3 - m4) + wz * (m5 - m6);
  const double perm = std::fabs(wx) * (std::fabs(m1) + std::fabs(m2)) +
                      std::fabs(wy) * (std::fabs(m3) + std::fabs(m4)) + std::fabs(wz) * (std::fabs(m5) + std::fabs(m6));
  const double bound = 7.7715611723761027e-16 * perm;  // (7 + 56 eps) eps
  if (det > bound) return 1;
  if (-det > bound) return -1;
  if (bound == 0) return 0;  // zeroTerms
  return orient3dExact(a, b, c, d);
}

// Sign of |p - q|^2 - tol^2: <= 0 when p and q lie within distance tol of each other (the
// tolerance weld's rule). tol2 is fl(tol * tol), computed once by the caller. The computed
// sum of squares is within 5u of the true one (u = 2^-53: three rounded differences, their
// squares, two additions; all terms are >= 0), tol2 within u, and their difference within u
// more: the filter allows 10u of s + tol2. No float32 difference squared underflows or
// overflows a double; a tol2 of infinity (tol above 1e154) holds every distance.
int distance2Exact(const float* p, const float* q, double tol);
inline bool withinDistance(const float* p, const float* q, double tol, double tol2) {
  const double ex = double(p[0]) - q[0], ey = double(p[1]) - q[1], ez = double(p[2]) - q[2];
  const double s = ex * ex + ey * ey + ez * ez;
  if (tol2 == HUGE_VAL) return true;
  const double d = s - tol2, bound = 1.1102230246251565e-15 * (s + tol2);  // 10u
  if (d > bound) return false;
  if (-d > bound) return true;
  return distance2Exact(p, q, tol) <= 0;
}

// Sign of (v - a) . (b - a): > 0 when v projects onto the ray from a through b beyond a. The
// differences are within u of the true ones, the products within 3u, the sum within 5u of the
// sum of the products' magnitudes: the filter allows 8u.
int dotSignExact(const float* v, const float* a, const float* b);
inline int dotSign(const float* v, const float* a, const float* b) {
  double t = 0, mag = 0;
  for (int k = 0; k < 3; ++k) {
    const double p = (double(v[k]) - a[k]) * (double(b[k]) - a[k]);
    t += p;
    mag += std::fabs(p);
  }
  const double bound = 8.8817841970012523e-16 * mag;  // 8u
  if (t > bound) return 1;
  if (-t > bound) return -1;
  if (bound == 0) return 0;  // zeroTerms: every product exactly 0
  return dotSignExact(v, a, b);
}

// Whether v lies within distance tol of the line through a and b (a != b): |(v - a) x (b - a)|^2
// <= tol^2 |b - a|^2 (Lagrange's identity: the squared distance times |b - a|^2), exactly. tol2
// is fl(tol * tol). For v farther than tol from a (the stitch step's case), so that tol^2
// |b - a|^2 stays below 2^518 and nothing overflows. The filter: a cross product coordinate
// l - r is within 4u (|l| + |r|) =: 4u P_k, its square within 9u P_k^2, their sum within 11u of
// the sum of the P_k^2; |b - a|^2 within 5u, tol2 within u, their product within 7u: the
// filter allows 16u of both sums.
bool withinLineDistanceExact(const float* v, const float* a, const float* b, double tol);
inline bool withinLineDistance(const float* v, const float* a, const float* b, double tol, double tol2) {
  double u[3], w[3], len2 = 0;
  for (int k = 0; k < 3; ++k) {
    u[k] = double(v[k]) - a[k];
    w[k] = double(b[k]) - a[k];
    len2 += w[k] * w[k];
  }
  double cross2 = 0, perm2 = 0;
  for (int k = 0; k < 3; ++k) {
    const int i = k == 2 ? 0 : k + 1, j = k == 0 ? 2 : k - 1;
    const double l = u[i] * w[j], r = u[j] * w[i];
    cross2 += (l - r) * (l - r);
    perm2 += (std::fabs(l) + std::fabs(r)) * (std::fabs(l) + std::fabs(r));
  }
  const double rhs = tol2 * len2, d = cross2 - rhs, bound = 1.7763568394002505e-15 * (perm2 + rhs);  // 16u
  if (d > bound) return false;
  if (-d > bound) return true;
  return withinLineDistanceExact(v, a, b, tol);
}

// The sum of det(a, b, c) = a . (b x c) over triangles (six times the signed volume of the
// tetrahedra (origin, a, b, c)), exactly: a fixed-point integer of kWords 64-bit words in two's
// complement, whose bit 0 weighs 2^kLowExponent. Each of a determinant's six products of three
// float32 values is an integer below 2^72 times 2^e with e >= -447 (3 x -149) and e + 72 <=
// 384, and 2^32 triangles add at most 35 bits: the bits from 2^-447 to 2^420 and a sign fit in
// 14 words. For the rare shells whose rounded volume is too close to 0 to tell its sign.
class VolumeSum {
 public:
  void add(const float* a, const float* b, const float* c);
  int sign() const;  // -1, 0 or 1

 private:
  static constexpr int kWords = 14, kLowExponent = -447;
  uint64_t words_[kWords] = {};
};

// orient3d(a, b, c, d) for many d against one plane (a, b, c): the cross products are
// computed once. side(d) gives exactly what orient3d(a, b, c, d) gives: the same
// floating-point determinant and bound, and the same exact fallback.
struct Plane {
  const float *a, *b, *c;
  double ax, ay, az;  // a, as doubles (the same values)
  double nx, ny, nz, px, py, pz;
  Plane(const float* a_, const float* b_, const float* c_) : a(a_), b(b_), c(c_), ax(a[0]), ay(a[1]), az(a[2]) {
    const double ux = double(b[0]) - ax, uy = double(b[1]) - ay, uz = double(b[2]) - az;
    const double vx = double(c[0]) - ax, vy = double(c[1]) - ay, vz = double(c[2]) - az;
    const double m1 = uy * vz, m2 = uz * vy, m3 = uz * vx, m4 = ux * vz, m5 = ux * vy, m6 = uy * vx;
    nx = m1 - m2, ny = m3 - m4, nz = m5 - m6;
    px = std::fabs(m1) + std::fabs(m2), py = std::fabs(m3) + std::fabs(m4), pz = std::fabs(m5) + std::fabs(m6);
  }
  int side(const float* d) const {
    const double wx = double(d[0]) - ax, wy = double(d[1]) - ay, wz = double(d[2]) - az;
    const double det = wx * nx + wy * ny + wz * nz;
    const double bound = 7.7715611723761027e-16 * (std::fabs(wx) * px + std::fabs(wy) * py + std::fabs(wz) * pz);
    if (det > bound) return 1;
    if (-det > bound) return -1;
    if (bound == 0) return 0;  // zeroTerms
    return orient3dExact(a, b, c, d);
  }
};

// The same determinant in floating point (not exact), for constructing points.
inline double orient3dApprox(const float* a, const float* b, const float* c, const float* d) {
  const double ux = double(b[0]) - a[0], uy = double(b[1]) - a[1], uz = double(b[2]) - a[2];
  const double vx = double(c[0]) - a[0], vy = double(c[1]) - a[1], vz = double(c[2]) - a[2];
  const double wx = double(d[0]) - a[0], wy = double(d[1]) - a[1], wz = double(d[2]) - a[2];
  return wx * (uy * vz - uz * vy) + wy * (uz * vx - ux * vz) + wz * (ux * vy - uy * vx);
}

// Coordinate k of the normal (b - a) x (c - a), exactly: the orientation of the
// triangle projected along axis k onto the coordinates (k + 1, k + 2) mod 3.
__attribute__((always_inline)) inline int normalSign(const float* a, const float* b, const float* c, int k) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  return orient2d(a[i], a[j], b[i], b[j], c[i], c[j]);
}

// Sign of the dot product of the normals of triangles (a, b, c) and (d, e, f):
// ((b - a) x (c - a)) . ((e - d) x (f - d)). < 0 when the normals make an angle of more than
// 90 degrees; 0 when they are perpendicular or one triangle has no normal. A filter, then
// expansion arithmetic (the degree-4 determinant does not fit the 128-bit integer path).
int normalsDot(const float* a, const float* b, const float* c, const float* d, const float* e, const float* f);
int normalsDotExpansion(const float* a, const float* b, const float* c, const float* d, const float* e, const float* f);

// Sign of n . ((b - a) x (c - a)) for a float32 vector n (a facet's stored normal), exactly, in
// expansion arithmetic: < 0 when n points against the triangle's winding, 0 when it is
// perpendicular or the triangle has no normal. For finite n. The filter before it is
// detail::normalMismatch (triangle_figures.h), on the cross product the readers compute anyway.
int normalDotExact(const float* n, const float* a, const float* b, const float* c);

// Whether a, b, c lie on one line (equal points included): (b - a) x (c - a) == 0.
// (A loop, so that code compiled for size, where normalSign is inlined, holds one copy of it.)
inline bool collinear(const float* a, const float* b, const float* c) {
  for (int k = 0; k < 3; ++k)
    if (normalSign(a, b, c, k) != 0) return false;
  return true;
}

}  // namespace stltopo::pred
