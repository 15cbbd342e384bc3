// The exact fallbacks of predicates.h: expansion arithmetic (J. R. Shewchuk, "Adaptive
// Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997).
//
// An expansion is a sum of doubles, stored in increasing magnitude with no two
// components overlapping; its sign is the sign of its largest component. Two-sum and
// two-product give the exact result of one addition or multiplication as two doubles;
// everything else is built from them. Only the rare undecided inputs come here, so the
// code favours plainness (no adaptive stages, no fast-expansion-sum).
//
// Exactness needs round-to-nearest double arithmetic with no fused multiply-add and no
// extended precision: the build passes -ffp-contract=off, and x86-64 and wasm use SSE /
// IEEE doubles.
#include "predicates.h"

#include <cstddef>

namespace stltopo::pred {
namespace {

// a + b = x + y exactly, x = fl(a + b).
inline void twoSum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

// Splits a into hi + lo, each with at most 26 significant bits (Dekker).
inline void split(double a, double& hi, double& lo) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  const double big = c - a;
  hi = c - big;
  lo = a - hi;
}

// a * b = x + y exactly, x = fl(a * b).
inline void twoProduct(double a, double b, double& x, double& y) {
  x = a * b;
  double ahi, alo, bhi, blo;
  split(a, ahi, alo);
  split(b, bhi, blo);
  const double err1 = x - ahi * bhi, err2 = err1 - alo * bhi, err3 = err2 - ahi * blo;
  y = alo * blo - err3;
}

// Expansions live in caller-provided arrays (length returned); no copies of whole
// buffers. Differences of float32 values are usually exact doubles, so most expansions
// here have a handful of components.

// h = e + b, in place allowed (h == e): h needs room for elen + 1.
int grow(int elen, const double* e, double b, double* h) {
  double q = b;
  int k = 0;
  for (int i = 0; i < elen; ++i) {
    double sum, err;
    twoSum(q, e[i], sum, err);
    q = sum;
    if (err != 0) h[k++] = err;
  }
  if (q != 0 || k == 0) h[k++] = q;
  return k;
}

// e += f in place: e needs room for elen + flen.
int addTo(int elen, double* e, int flen, const double* f) {
  for (int i = 0; i < flen; ++i) elen = grow(elen, e, f[i], e);
  return elen;
}

// h = e * b (scale-expansion with zero elimination): h needs 2 * elen.
int scale(int elen, const double* e, double b, double* h) {
  int k = 0;
  double q, hh;
  twoProduct(e[0], b, q, hh);
  if (hh != 0) h[k++] = hh;
  for (int i = 1; i < elen; ++i) {
    double p1, p0, sum;
    twoProduct(e[i], b, p1, p0);
    twoSum(q, p0, sum, hh);
    if (hh != 0) h[k++] = hh;
    twoSum(p1, sum, q, hh);
    if (hh != 0) h[k++] = hh;
  }
  if (q != 0 || k == 0) h[k++] = q;
  return k;
}

// h = e * f: h needs 2 * elen * flen + 1.
int mul(int elen, const double* e, int flen, const double* f, double* h) {
  double part[2 * 48];
  h[0] = 0;
  int hlen = 1;
  for (int i = 0; i < flen; ++i) {
    const int n = scale(elen, e, f[i], part);
    hlen = addTo(hlen, h, n, part);
  }
  return hlen;
}

// The exact difference a - b: 1 or 2 components.
int diff(double a, double b, double* h) {
  double x, y;
  twoSum(a, -b, x, y);
  if (y == 0) {
    h[0] = x;
    return 1;
  }
  h[0] = y;
  h[1] = x;
  return 2;
}

int sign(int n, const double* e) {
  for (int i = n - 1; i >= 0; --i) {
    if (e[i] > 0) return 1;
    if (e[i] < 0) return -1;
  }
  return 0;
}

struct D {  // an exact difference
  double c[2];
  int n;
  D(double a, double b) { n = diff(a, b, c); }
};

// p * q - r * s: at most 16 components (out needs 24: room for the in-place sums).
int crossTerm(const D& p, const D& q, const D& r, const D& s, double* out) {
  double b[12];
  int n = mul(p.n, p.c, q.n, q.c, out);
  int m = mul(r.n, r.c, s.n, s.c, b);
  for (int i = 0; i < m; ++i) b[i] = -b[i];
  return addTo(n, out, m, b);
}

}  // namespace

int orient2dExact(double ax, double ay, double bx, double by, double cx, double cy) {
  const D ux(bx, ax), uy(by, ay), vx(cx, ax), vy(cy, ay);
  double det[24];
  const int n = crossTerm(ux, vy, uy, vx, det);
  return sign(n, det);
}

int orient3dExact(const float* a, const float* b, const float* c, const float* d) {
  const D ux(b[0], a[0]), uy(b[1], a[1]), uz(b[2], a[2]);
  const D vx(c[0], a[0]), vy(c[1], a[1]), vz(c[2], a[2]);
  const D wx(d[0], a[0]), wy(d[1], a[1]), wz(d[2], a[2]);
  double m[24], t[2 * 2 * 24 + 1], acc[3 * 97];
  int mn = crossTerm(uy, vz, uz, vy, m);
  int n = mul(wx.n, wx.c, mn, m, acc);
  mn = crossTerm(uz, vx, ux, vz, m);
  int tn = mul(wy.n, wy.c, mn, m, t);
  n = addTo(n, acc, tn, t);
  mn = crossTerm(ux, vy, uy, vx, m);
  tn = mul(wz.n, wz.c, mn, m, t);
  n = addTo(n, acc, tn, t);
  return sign(n, acc);
}

}  // namespace stltopo::pred
