// Fuzz target 3: the tolerance weld. The input is [mode] [mantissa] [STL bytes]; the two
// leading bytes choose TopologyOptions::tolerance, from 2^-160 to 2^79 plus the edge
// cases 0, negative, NaN, +Inf, the smallest denormal and DBL_MAX. validate() must pass
// and the weld map must be a valid, distance-respecting representative map.
#include <cfloat>
#include <limits>

#include "fuzz_common.h"

using namespace stltopo;

namespace {

double toleranceOf(uint8_t mode, uint8_t mant) {
  switch (mode) {
    case 240: return 0;
    case 241: return -1;
    case 242: return std::numeric_limits<double>::quiet_NaN();
    case 243: return std::numeric_limits<double>::infinity();
    case 244: return std::numeric_limits<double>::denorm_min();
    case 245: return DBL_MAX;
    case 246: return 1e-300;
    case 247: return FLT_MIN;
    default: break;
  }
  if (mode > 247) return std::ldexp(1.0 + mant / 256.0, int(mode) - 252);  // 2^-4 .. 2^3
  return std::ldexp(1.0 + mant / 256.0, int(mode) - 160);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  double tol = toleranceOf(data[0], data[1]);
  const uint8_t* p = data + 2;
  size_t n = size - 2;
  ReadOptions o;
  Mesh m;
  Status s = readStl(p, n, m, o);
  if (!s.ok()) {
    fuzz::checkError(s);
    return 0;
  }
  fuzz::checkMesh(m, o);
  TopologyOptions to;
  to.tolerance = tol;
  Topology t;
  fuzz::checkTopology(m, to, t);
  fuzz::checkShells(m, to, t);

  const uint32_t nv = m.nVertices();
  FUZZ_CHECK(t.vertexWeld.size() == nv);
  bool welding = tol > 0;  // NaN and negatives mean the exact weld
  for (uint32_t v = 0; v < nv; ++v) {
    uint32_t r = t.vertexWeld[v];
    if (!welding) {
      FUZZ_CHECK(r == v);
      continue;
    }
    FUZZ_CHECK(r <= v);                // the lowest-id representative
    FUZZ_CHECK(t.vertexWeld[r] == r);  // representatives represent themselves
    double dx = double(m.positions[3 * r]) - m.positions[3 * v];
    double dy = double(m.positions[3 * r + 1]) - m.positions[3 * v + 1];
    double dz = double(m.positions[3 * r + 2]) - m.positions[3 * v + 2];
    FUZZ_CHECK(dx * dx + dy * dy + dz * dz <= tol * tol);
  }
  // A deterministic weld: a second build gives the same map.
  Topology t2;
  FUZZ_CHECK(buildTopology(m, t2, to).ok());
  FUZZ_CHECK(fuzz::sameArray(t.vertexWeld, t2.vertexWeld) && fuzz::sameArray(t.next, t2.next));
  return 0;
}
