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

#include <algorithm>
#include <cstddef>
#include <cstring>

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

// The exact determinants in 128-bit integers, for the common inputs whose float32
// coordinates span at most kSpan bits from the largest to the smallest unit in the last
// place (a mesh's nearby corners almost always do): each coordinate is then an integer of at
// most kSpan bits in units of the smallest ulp, and the determinant fits an __int128.
// False when the inputs span more (the expansions decide those).
namespace {

constexpr int kSpan = 40;

// A float32 as m * 2^e, m an integer with |m| < 2^24 (0 for zero: e is then ignored).
struct Fixed {
  int32_t m;
  int e;
};
inline Fixed fixedOf(float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  const int exp = int((bits >> 23) & 0xff);
  int32_t mant = int32_t(bits & 0x7fffff);
  if (exp != 0) mant |= 0x800000;
  if (bits >> 31) mant = -mant;
  return {mant, (exp == 0 ? 1 : exp) - 150};
}

// The coordinates as integers in units of 2^emin, or false when they span more than kSpan bits.
template <int N>
bool toIntegers(const float* const (&v)[N], int64_t (&out)[N]) {
  Fixed f[N];
  int emin = 1 << 30, emax = -(1 << 30);
  for (int i = 0; i < N; ++i) {
    f[i] = fixedOf(*v[i]);
    if (f[i].m == 0) continue;
    emin = std::min(emin, f[i].e);
    emax = std::max(emax, f[i].e);
  }
  if (emin > emax) emin = emax = 0;  // all zero
  if (emax - emin + 24 > kSpan) return false;
  for (int i = 0; i < N; ++i) out[i] = f[i].m == 0 ? 0 : int64_t(f[i].m) * (int64_t(1) << (f[i].e - emin));
  return true;
}

inline int sign128(__int128 x) { return x > 0 ? 1 : x < 0 ? -1 : 0; }

}  // namespace

int orient3dExact(const float* a, const float* b, const float* c, const float* d);

int orient2dExact(double ax, double ay, double bx, double by, double cx, double cy) {
  // The inputs are float32 values (orient2d is only called on float32 coordinates).
  const float f[6] = {float(ax), float(ay), float(bx), float(by), float(cx), float(cy)};
  if (double(f[0]) == ax && double(f[1]) == ay && double(f[2]) == bx && double(f[3]) == by && double(f[4]) == cx &&
      double(f[5]) == cy) {
    const float* const v[6] = {&f[0], &f[1], &f[2], &f[3], &f[4], &f[5]};
    int64_t i[6];
    if (toIntegers(v, i)) {
      const __int128 ux = i[2] - i[0], uy = i[3] - i[1], vx = i[4] - i[0], vy = i[5] - i[1];
      return sign128(ux * vy - uy * vx);
    }
  }
  return orient2dExpansion(ax, ay, bx, by, cx, cy);
}

namespace {
// (b - a) x (c - a) in the plane, exactly: at most 16 components (out needs 24).
int cross2(double ax, double ay, double bx, double by, double cx, double cy, double* out) {
  const D ux(bx, ax), uy(by, ay), vx(cx, ax), vy(cy, ay);
  return crossTerm(ux, vy, uy, vx, out);
}

// |p - q|^2, exactly: each difference in at most 2 components, its square in at most 8, the
// sum in at most 24 (out needs 24).
int distance2(const float* p, const float* q, double* out) {
  double sq[2 * 2 * 2 + 1];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const D e(p[k], q[k]);
    n = addTo(n, out, mul(e.n, e.c, e.n, e.c, sq), sq);
  }
  return n;
}

// -tol^2, exactly: 2 components.
void minusSquare(double tol, double (&out)[2]) {
  twoProduct(tol, tol, out[1], out[0]);
  out[0] = -out[0], out[1] = -out[1];
}
}  // namespace

int orient2dExpansion(double ax, double ay, double bx, double by, double cx, double cy) {
  double det[24];
  const int n = cross2(ax, ay, bx, by, cx, cy, det);
  return sign(n, det);
}

int orient3dExact(const float* a, const float* b, const float* c, const float* d) {
  const float* const v[12] = {&a[0], &a[1], &a[2], &b[0], &b[1], &b[2], &c[0], &c[1], &c[2], &d[0], &d[1], &d[2]};
  int64_t i[12];
  if (toIntegers(v, i)) {
    // |coordinate| < 2^40: differences < 2^41, minors < 2^83, terms < 2^124, the sum < 2^126.
    const __int128 ux = i[3] - i[0], uy = i[4] - i[1], uz = i[5] - i[2];
    const __int128 vx = i[6] - i[0], vy = i[7] - i[1], vz = i[8] - i[2];
    const __int128 wx = i[9] - i[0], wy = i[10] - i[1], wz = i[11] - i[2];
    return sign128(wx * (uy * vz - uz * vy) + wy * (uz * vx - ux * vz) + wz * (ux * vy - uy * vx));
  }
  return orient3dExpansion(a, b, c, d);
}

int orient3dExpansion(const float* a, const float* b, const float* c, const float* d) {
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

int normalsDotExpansion(const float* a, const float* b, const float* c, const float* d, const float* e,
                        const float* f) {
  // Normal coordinate k of each triangle is the cross product of its projection onto the axes
  // (k + 1, k + 2) (at most 16 components); each product of two at most 2 * 16 * 16 + 1.
  double n1[24], n2[24], t[2 * 16 * 16 + 1], acc[3 * (2 * 16 * 16 + 1)];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const int i = k == 2 ? 0 : k + 1, j = k == 0 ? 2 : k - 1;
    const int l1 = cross2(a[i], a[j], b[i], b[j], c[i], c[j], n1);
    const int l2 = cross2(d[i], d[j], e[i], e[j], f[i], f[j], n2);
    n = addTo(n, acc, mul(l1, n1, l2, n2, t), t);
  }
  return sign(n, acc);
}

int normalDotExact(const float* n, const float* a, const float* b, const float* c) {
  // Normal coordinate k is the cross product of the projection onto the axes (k + 1, k + 2)
  // (at most 16 components), times n_k at most 32.
  double m[24], t[2 * 24], acc[3 * 2 * 24];
  int len = 0;
  for (int k = 0; k < 3; ++k) {
    const int i = k == 2 ? 0 : k + 1, j = k == 0 ? 2 : k - 1;
    const int mn = cross2(a[i], a[j], b[i], b[j], c[i], c[j], m);
    len = addTo(len, acc, scale(mn, m, n[k], t), t);
  }
  return sign(len, acc);
}

int dotSignExact(const float* v, const float* a, const float* b) {
  // Each product of two exact differences has at most 8 components.
  double acc[3 * 8], t[8];
  int len = 0;
  for (int k = 0; k < 3; ++k) {
    const D p(v[k], a[k]), q(b[k], a[k]);
    len = addTo(len, acc, mul(p.n, p.c, q.n, q.c, t), t);
  }
  return sign(len, acc);
}

bool withinLineDistanceExact(const float* v, const float* a, const float* b, double tol) {
  // |(v - a) x (b - a)|^2: each coordinate a cross term of the projection (at most 16
  // components), its square at most 2 * 16 * 16 + 1. Then minus tol^2 (2) times |b - a|^2
  // (three squares of exact differences: at most 24).
  constexpr int kSquare = 2 * 16 * 16 + 1;
  double m[24], sq[kSquare], acc[3 * kSquare + 2 * 2 * 24 + 1], len2[3 * 8], tt[2], rhs[2 * 2 * 24 + 1];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const int i = k == 2 ? 0 : k + 1, j = k == 0 ? 2 : k - 1;
    const int mn = cross2(a[i], a[j], v[i], v[j], b[i], b[j], m);
    n = addTo(n, acc, mul(mn, m, mn, m, sq), sq);
  }
  const int ln = distance2(b, a, len2);
  minusSquare(tol, tt);
  const int rn = mul(2, tt, ln, len2, rhs);
  n = addTo(n, acc, rn, rhs);
  return sign(n, acc) <= 0;
}

void VolumeSum::add(const float* a, const float* b, const float* c) {
  // det(a, b, c) = ax by cz - ax bz cy - ay bx cz + ay bz cx + az bx cy - az by cx
  static constexpr int kTerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  static constexpr bool kMinus[6] = {false, true, true, false, false, true};
  const Fixed fa[3] = {fixedOf(a[0]), fixedOf(a[1]), fixedOf(a[2])};
  const Fixed fb[3] = {fixedOf(b[0]), fixedOf(b[1]), fixedOf(b[2])};
  const Fixed fc[3] = {fixedOf(c[0]), fixedOf(c[1]), fixedOf(c[2])};
  for (int t = 0; t < 6; ++t) {
    const Fixed &x = fa[kTerm[t][0]], &y = fb[kTerm[t][1]], &z = fc[kTerm[t][2]];
    if (x.m == 0 || y.m == 0 || z.m == 0) continue;
    const __int128 m = __int128(int64_t(x.m) * y.m) * z.m;  // |m| < 2^72
    const bool minus = (m < 0) != kMinus[t];
    const unsigned __int128 mag = m < 0 ? (unsigned __int128)(-m) : (unsigned __int128)m;
    const int pos = x.e + y.e + z.e - kLowExponent;  // >= 0: every e >= -149
    const int q = pos / 64, r = pos % 64;
    const uint64_t m0 = uint64_t(mag), m1 = uint64_t(mag >> 64);  // m1 < 2^8
    uint64_t part[3] = {m0, m1, 0};
    if (r != 0) part[0] = m0 << r, part[1] = (m0 >> (64 - r)) | (m1 << r), part[2] = m1 >> (64 - r);
    // add (or subtract) part at word q, carrying (or borrowing) through the words above
    uint64_t carry = 0;
    for (int i = q; i < kWords; ++i) {
      const uint64_t v = i - q < 3 ? part[i - q] : 0;
      if (i - q >= 3 && carry == 0) break;
      if (!minus) {
        const uint64_t s1 = words_[i] + v, c1 = s1 < v;
        const uint64_t s2 = s1 + carry, c2 = s2 < carry;
        words_[i] = s2, carry = c1 | c2;
      } else {
        const uint64_t d1 = words_[i] - v, b1 = words_[i] < v;
        const uint64_t d2 = d1 - carry, b2 = d1 < carry;
        words_[i] = d2, carry = b1 | b2;
      }
    }
  }
}

int VolumeSum::sign() const {
  if (words_[kWords - 1] >> 63) return -1;
  for (int i = 0; i < kWords; ++i)
    if (words_[i]) return 1;
  return 0;
}

int distance2Exact(const float* p, const float* q, double tol) {
  double acc[3 * 8 + 2], t[2];  // |p - q|^2 (24 components) minus tol^2 (2)
  const int n = distance2(p, q, acc);
  minusSquare(tol, t);
  return sign(addTo(n, acc, 2, t), acc);
}

int normalsDot(const float* a, const float* b, const float* c, const float* d, const float* e, const float* f) {
  // Each normal coordinate l - r is within 3u (|l| + |r|) of the true one (Shewchuk's
  // orient2d bound, u = 2^-53); the dot product of the two then within about 9u of the sum
  // over k of (|l1| + |r1|)(|l2| + |r2|). The filter allows 16u.
  const double ux = double(b[0]) - a[0], uy = double(b[1]) - a[1], uz = double(b[2]) - a[2];
  const double vx = double(c[0]) - a[0], vy = double(c[1]) - a[1], vz = double(c[2]) - a[2];
  const double px = double(e[0]) - d[0], py = double(e[1]) - d[1], pz = double(e[2]) - d[2];
  const double qx = double(f[0]) - d[0], qy = double(f[1]) - d[1], qz = double(f[2]) - d[2];
  const double l1[3] = {uy * vz, uz * vx, ux * vy}, r1[3] = {uz * vy, ux * vz, uy * vx};
  const double l2[3] = {py * qz, pz * qx, px * qy}, r2[3] = {pz * qy, px * qz, py * qx};
  double dot = 0, perm = 0;
  for (int k = 0; k < 3; ++k) {
    dot += (l1[k] - r1[k]) * (l2[k] - r2[k]);
    perm += (std::fabs(l1[k]) + std::fabs(r1[k])) * (std::fabs(l2[k]) + std::fabs(r2[k]));
  }
  const double bound = 1.7763568394002505e-15 * perm;  // 16u
  if (dot > bound) return 1;
  if (-dot > bound) return -1;
  return normalsDotExpansion(a, b, c, d, e, f);
}

}  // namespace stltopo::pred
