// One triangle's figures, shared by the reader, the shells and the report. Private (not
// installed).
#pragma once

#include <cmath>

#include "predicates.h"

namespace stltopo::detail {

// The formulas of Mesh::area, Mesh::volume and Mesh::normalMismatches, in float64 from
// float32 corners: the cross product n = (b - a) x (c - a), the area |n| / 2, and the signed
// volume of the tetrahedron (origin, a, b, c). Every figure of the library goes through
// here, so that they agree to the bit.
struct TriangleFigures {
  double nx, ny, nz, area, volume;
  // |l| + |r| of each normal coordinate l - r (l, r: the two products): the error bound of
  // normalMismatch's filter. Callers that do not read them pay nothing (inlined, dead).
  double px, py, pz;
};
// The signed volume of the tetrahedron (origin, a, b, c): TriangleFigures::volume.
inline double triangleVolume(const float* a, const float* b, const float* c) {
  double ax = a[0], ay = a[1], az = a[2], bx = b[0], by = b[1], bz = b[2], cx = c[0], cy = c[1], cz = c[2];
  return (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0;
}
inline TriangleFigures triangleFigures(const float* a, const float* b, const float* c) {
  double ax = a[0], ay = a[1], az = a[2], bx = b[0], by = b[1], bz = b[2], cx = c[0], cy = c[1], cz = c[2];
  double ux = bx - ax, uy = by - ay, uz = bz - az, wx = cx - ax, wy = cy - ay, wz = cz - az;
  TriangleFigures f;
  const double m1 = uy * wz, m2 = uz * wy, m3 = uz * wx, m4 = ux * wz, m5 = ux * wy, m6 = uy * wx;
  f.nx = m1 - m2;
  f.ny = m3 - m4;
  f.nz = m5 - m6;
  f.px = std::fabs(m1) + std::fabs(m2);
  f.py = std::fabs(m3) + std::fabs(m4);
  f.pz = std::fabs(m5) + std::fabs(m6);
  f.area = 0.5 * std::sqrt(f.nx * f.nx + f.ny * f.ny + f.nz * f.nz);
  f.volume = triangleVolume(a, b, c);
  return f;
}
// Whether a stored normal n points against the winding of the triangle (a, b, c) whose
// figures are f (Mesh::normalMismatches): n . ((b - a) x (c - a)) < 0, exactly. A filter on
// the cross product f holds, then pred::normalDotExact for the close cases. The bound: the
// differences are within u of the true ones (u = 2^-53), each product of two within 3u, a
// normal coordinate l - r within 4u (|l| + |r|) (f.px, f.py, f.pz); times the exact n_k and
// summed, the dot product is within 7u of the sum over k of |n_k| (|l_k| + |r_k|) (plus
// O(u^2)): the filter allows 10u. A zero bound means every product is exactly 0 (as in
// pred::orient3d's zeroTerms), so the dot product is. A non-finite n has no exact sign: the
// dot product in double decides it (a NaN: not a mismatch).
inline bool normalMismatch(const float* n, const TriangleFigures& f, const float* a, const float* b, const float* c) {
  const double n0 = n[0], n1 = n[1], n2 = n[2];
  const double dot = n0 * f.nx + n1 * f.ny + n2 * f.nz;
  const double bound = 1.1102230246251565e-15 * (std::fabs(n0) * f.px + std::fabs(n1) * f.py + std::fabs(n2) * f.pz);
  // Decided: beyond the bound; exactly 0 when the bound is (zeroTerms: a zero normal too, never
  // a mismatch); n not finite (an infinite or NaN bound): the sign in double.
  if (!(std::fabs(dot) <= bound) || bound == 0 || bound == HUGE_VAL) return dot < 0;
  return pred::normalDotExact(n, a, b, c) < 0;
}

}  // namespace stltopo::detail
