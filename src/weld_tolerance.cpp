#include "weld_tolerance.h"

#include <cmath>

#include "predicates.h"

namespace stltopo::detail {
namespace {

// The grid cell of a coordinate. Far from the origin in units of tol (or tol tiny) the
// float spacing at x exceeds tol, so only vertices with exactly this coordinate can be
// within tol: those are keyed by the value, outside the range of the regular cells,
// instead of clamped (a clamped cell would collect every such vertex and make the search
// quadratic).
//
// Cells are 4·tol wide, so on each axis a point lies within tol of its cell's lower side
// only in the cell's first quarter, and of its upper side only in the last: the search
// visits its own cell and, per axis, a neighbour only on such a side (1.5 cells per axis on
// average, 3.4 in all, against 27 for cells of width tol: each is a random probe of the
// cell table, and those probes were the cost). A quarter is widened by kMargin of a cell,
// so that rounding of x / (4·tol) can never leave a representative within tol unvisited.
// Which cells are visited never changes the result, only how fast it comes: the rule is
// "the lowest-id representative within tol", and every one is in a visited cell.
// Representatives are more than tol apart, so a cell holds a bounded number of them.
struct Cell {
  int64_t key;  // the cell index, or a far key (see above)
  int lo, hi;   // the neighbours to visit along this axis: key + lo .. key + hi
};
constexpr double kCellWidth = 4;  // in units of tol
constexpr double kMargin = 1.0 / 1024;
inline Cell cellOf(double x, double tol) {
  double q = x / (kCellWidth * tol);
  double c = std::floor(q);
  if (std::fabs(c) <= 0x1p40) {
    double f = q - c;  // in [0, 1]
    constexpr double kReach = 1 / kCellWidth + kMargin;
    return {int64_t(c), f < kReach ? -1 : 0, f > 1 - kReach ? 1 : 0};
  }
  int64_t k = (int64_t(1) << 42) + int64_t(bitCast<uint32_t>(std::fabs(float(x))));
  return {x < 0 ? -k : k, 0, 0};
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
  // A bit per hash of every occupied cell, some 16 bits per vertex (at most 8 MB): small
  // enough to stay in the cache, so that the probe of an empty neighbour (most of them,
  // when tol is below the edge lengths) seldom reaches the slots at all.
  Array<uint64_t> occupied;
  uint64_t bitMask = 0;

  bool init(uint32_t nVertices) {
    size_t n = 16;
    while (n < size_t(nVertices) * 2) n *= 2;
    size_t bits = 1024;
    while (bits < size_t(nVertices) * 16 && bits < (size_t(1) << 26)) bits *= 2;
    if (!slots.assign(n, Slot{0, 0, 0, kInvalid}) || !occupied.assign(bits / 64, 0)) return false;
    mask = n - 1;
    bitMask = bits - 1;
    return true;
  }
  bool mayHold(uint64_t h) const { return (occupied[(h & bitMask) >> 6] >> (h & 63)) & 1; }
  void mark(uint64_t h) { occupied[(h & bitMask) >> 6] |= uint64_t(1) << (h & 63); }
  static uint64_t hash(int64_t x, int64_t y, int64_t z) {
    uint64_t h = uint64_t(x) * 0x9E3779B97F4A7C15ull;
    h ^= uint64_t(y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= uint64_t(z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return h ^ (h >> 29);
  }
  // The slot of cell (x, y, z), whose hash is h: its own when occupied, else the empty one
  // it would take.
  Slot& find(int64_t x, int64_t y, int64_t z, uint64_t h) {
    uint64_t i = h & mask;
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
    Cell cx = cellOf(x, tol), cy = cellOf(y, tol), cz = cellOf(z, tol);
    int64_t kx = cx.key, ky = cy.key, kz = cz.key;
    uint32_t best = kInvalid;
    for (int dx = cx.lo; dx <= cx.hi; ++dx)
      for (int dy = cy.lo; dy <= cy.hi; ++dy)
        for (int dz = cz.lo; dz <= cz.hi; ++dz) {
          uint64_t h = CellTable::hash(kx + dx, ky + dy, kz + dz);
          if (!cells.mayHold(h)) continue;
          const CellTable::Slot& s = cells.find(kx + dx, ky + dy, kz + dz, h);
          for (uint32_t r = s.head; r != kInvalid; r = chain[r]) {
            if (r < best && pred::withinDistance(p + 3 * size_t(r), p + 3 * size_t(v), tol, tol2)) best = r;
          }
        }
    if (best != kInvalid) {
      rep[v] = best;
    } else {
      rep[v] = v;
      ++nReps;
      uint64_t h = CellTable::hash(kx, ky, kz);
      CellTable::Slot& s = cells.find(kx, ky, kz, h);
      if (s.head == kInvalid) {
        s = CellTable::Slot{kx, ky, kz, v};
        cells.mark(h);
      } else {
        chain[v] = s.head;
        s.head = v;
      }
    }
  }
  return nReps;
}

}  // namespace stltopo::detail
