// One triangle's figures, shared by the reader, the shells and the report. Private (not
// installed).
#pragma once

#include <cmath>

namespace stltopo::detail {

// The formulas of Mesh::area, Mesh::volume and Mesh::normalMismatches, in float64 from
// float32 corners: the cross product n = (b - a) x (c - a), the area |n| / 2, and the signed
// volume of the tetrahedron (origin, a, b, c). Every figure of the library goes through
// here, so that they agree to the bit.
struct TriangleFigures {
  double nx, ny, nz, area, volume;
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
  f.nx = uy * wz - uz * wy;
  f.ny = uz * wx - ux * wz;
  f.nz = ux * wy - uy * wx;
  f.area = 0.5 * std::sqrt(f.nx * f.nx + f.ny * f.ny + f.nz * f.nz);
  f.volume = triangleVolume(a, b, c);
  return f;
}
// Whether a stored normal n points against the winding (Mesh::normalMismatches).
inline bool normalMismatch(const float* n, const TriangleFigures& f) {
  return (n[0] != 0.0f || n[1] != 0.0f || n[2] != 0.0f) &&
         double(n[0]) * f.nx + double(n[1]) * f.ny + double(n[2]) * f.nz < 0;
}

}  // namespace stltopo::detail
