#include "weld_tolerance.h"

#include <cmath>

namespace stltopo::detail {
namespace {

// The grid cell of a coordinate. Far from the origin in units of tol (or tol tiny) the
// float spacing at x exceeds tol, so only vertices with exactly this coordinate can be
// within tol: those are keyed by the value, outside the range of the regular cells,
// instead of clamped (a clamped cell would collect every such vertex and make the search
// quadratic).
inline int64_t cellOf(double x, double tol) {
  double c = std::floor(x / tol);
  if (std::fabs(c) <= 0x1p40) return int64_t(c);
  int64_t k = (int64_t(1) << 42) + int64_t(bitCast<uint32_t>(std::fabs(float(x))));
  return x < 0 ? -k : k;
}

// The occupied cells: open addressing on the cell key, each slot holding the cell's most
// recent representative (the others follow through `chain`). Sized once for every
// vertex, so it never grows: the load stays at or below one half.
struct CellTable {
  struct Slot {
    int64_t x, y, z;
    uint32_t head;  // kInvalid: empty slot
  };
  Array<Slot> slots;
  uint64_t mask = 0;

  bool init(uint32_t nVertices) {
    size_t n = 16;
    while (n < size_t(nVertices) * 2) n *= 2;
    if (!slots.assign(n, Slot{0, 0, 0, kInvalid})) return false;
    mask = n - 1;
    return true;
  }
  static uint64_t hash(int64_t x, int64_t y, int64_t z) {
    uint64_t h = uint64_t(x) * 0x9E3779B97F4A7C15ull;
    h ^= uint64_t(y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= uint64_t(z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return h ^ (h >> 29);
  }
  // The slot of cell (x, y, z): its own when occupied, else the empty one it would take.
  Slot& find(int64_t x, int64_t y, int64_t z) {
    uint64_t i = hash(x, y, z) & mask;
    for (;;) {
      Slot& s = slots[i];
      if (s.head == kInvalid || (s.x == x && s.y == y && s.z == z)) return s;
      i = (i + 1) & mask;
    }
  }
};

}  // namespace

uint32_t toleranceWeld(const Mesh& mesh, double tol, Array<uint32_t>& rep) {
  uint32_t nv = mesh.nVertices();
  if (!rep.resize(nv)) return kInvalid;
  Array<uint32_t> chain;  // next representative in the same cell
  CellTable cells;
  if (!chain.assign(nv, kInvalid) || !cells.init(nv)) return kInvalid;
  const float* p = mesh.positions.data();
  double tol2 = tol * tol;
  uint32_t nReps = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    double x = p[3 * v], y = p[3 * v + 1], z = p[3 * v + 2];
    int64_t kx = cellOf(x, tol), ky = cellOf(y, tol), kz = cellOf(z, tol);
    uint32_t best = kInvalid;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const CellTable::Slot& s = cells.find(kx + dx, ky + dy, kz + dz);
          for (uint32_t r = s.head; r != kInvalid; r = chain[r]) {
            double ex = p[3 * r] - x, ey = p[3 * r + 1] - y, ez = p[3 * r + 2] - z;
            if (ex * ex + ey * ey + ez * ez <= tol2 && r < best) best = r;
          }
        }
    if (best != kInvalid) {
      rep[v] = best;
    } else {
      rep[v] = v;
      ++nReps;
      CellTable::Slot& s = cells.find(kx, ky, kz);
      if (s.head == kInvalid) {
        s = CellTable::Slot{kx, ky, kz, v};
      } else {
        chain[v] = s.head;
        s.head = v;
      }
    }
  }
  return nReps;
}

}  // namespace stltopo::detail
