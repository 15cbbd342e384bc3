// The mesh builder's cold half: reservation, the weld table's growth, solids, warnings and
// the colour decoding. (Its threaded read, hot, is mesh_builder_threads.cpp.)
#include "mesh_builder.h"

namespace stltopo::detail {


void trim(const char*& b, const char*& e) {
  auto ws = [](unsigned char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; };
  while (b < e && ws(*b)) ++b;
  while (e > b && ws(e[-1])) --e;
}

bool Builder::reserveTriangles(uint64_t n) {
  if (n > opt.maxTriangles) n = opt.maxTriangles;
  if (n <= mesh.nTriangles()) return true;
  plannedTriangles = n;
  uint64_t v = n / 2 + 16;
  if (!mesh.triangles.reserve(size_t(n) * 3) || !mesh.attributes.reserve(size_t(n)) ||
      (opt.keepNormals && !mesh.normals.reserve(size_t(n) * 3)) || !mesh.positions.reserve(size_t(v) * 3) ||
      !growTable(uint32_t(std::min<uint64_t>(v, 1u << 30)))) {
    error = oom("the mesh arrays");
    return false;
  }
  return true;
}

void Builder::dropArrays() {
  mesh = Mesh{};
  releaseWeld();
}

bool Builder::growSlots(Array<Slot>& t, uint32_t& mask, uint32_t forVertices) {
  size_t want = 64;
  while (want < size_t(forVertices) * 2) want *= 2;
  if (want <= t.size()) return true;
  Array<Slot> g;
  if (!g.assign(want, Slot{0, 0, 0, kInvalid})) return false;
  const uint32_t m = uint32_t(want - 1);
  for (const Slot& slot : t) {
    if (slot.id == kInvalid) continue;
    uint32_t i = slotHash(slot) & m;
    while (g[i].id != kInvalid) i = (i + 1) & m;
    g[i] = slot;
  }
  t = std::move(g);
  mask = m;
  return true;
}

bool Builder::growTable(uint32_t forVertices, uint64_t trianglesDone) {
  if (recent.empty() && !recent.assign(kRecent, Slot{0, 0, 0, kInvalid})) return false;
  // A soup: at least 31/32 of the corners so far were new vertices, over a thousand triangles
  // or more. Its table would double from reserveTriangles's half a vertex a triangle to three,
  // each doubling a fresh table filled again (a 1M soup: 16 -> 128 MB). A file that welds
  // after a soup-like start gets a table larger than it needs (at most for 3 vertices a
  // triangle, as a soup's); when that cannot be had, the table doubles as before.
  const uint64_t t = trianglesDone;
  if (t >= 1024 && plannedTriangles > t && uint64_t(forVertices) * 32 >= 93 * t) {
    const uint64_t want = std::min<uint64_t>(uint64_t(forVertices) + 3 * (plannedTriangles - t), 1u << 30);
    if (growSlots(table, mask, uint32_t(want))) {
      (void)mesh.positions.reserve(size_t(want) * 3);  // else it grows as it goes
      return true;
    }
  }
  return growSlots(table, mask, forVertices);
}


bool Builder::beginSolid(const char* name, size_t nameBytes, const PartColor* color) {
  Solid s;
  s.firstTriangle = mesh.nTriangles();
  PartColor pc = color ? *color : PartColor{};
  if (!tryAssign(s.name, name, nameBytes) || !tryPushBack(mesh.solids, std::move(s)) ||
      !tryPushBack(partColors, std::move(pc))) {
    if (mesh.solids.size() > partColors.size()) mesh.solids.pop_back();
    error = oom("the solid list");
    return false;
  }
  solidOpen = true;
  return true;
}

void Builder::endSolid() {
  if (!solidOpen) return;
  Solid& s = mesh.solids.back();
  s.triangleCount = mesh.nTriangles() - s.firstTriangle;
  solidOpen = false;
}

bool Builder::decodeColors() {
  bool magics = false;
  for (const PartColor& p : partColors) magics |= p.magics;
  ColorConvention conv =
      magics ? ColorConvention::Magics : (anyVisCamBit ? ColorConvention::VisCam : ColorConvention::None);
  mesh.colorConvention = conv;
  if (conv == ColorConvention::None) return true;
  uint32_t nt = mesh.nTriangles();
  if (!mesh.colors.assign(size_t(nt) * 3, 0) || !mesh.colorValid.assign(nt, 0)) return false;
  for (size_t s = 0; s < mesh.solids.size(); ++s) {
    const Solid& so = mesh.solids[s];
    const PartColor& pc = partColors[s];
    for (uint32_t t = so.firstTriangle; t < so.firstTriangle + so.triangleCount; ++t) {
      unsigned a = mesh.attributes[t];
      uint8_t* rgb = mesh.colors.data() + size_t(t) * 3;
      if (pc.magics) {
        if (a & 0x8000u) {
          rgb[0] = pc.rgb[0];
          rgb[1] = pc.rgb[1];
          rgb[2] = pc.rgb[2];
        } else {
          rgb[0] = c5(a & 31u);
          rgb[1] = c5((a >> 5) & 31u);
          rgb[2] = c5((a >> 10) & 31u);
        }
        mesh.colorValid[t] = 1;
      } else if (conv == ColorConvention::VisCam && (a & 0x8000u)) {
        rgb[0] = c5((a >> 10) & 31u);
        rgb[1] = c5((a >> 5) & 31u);
        rgb[2] = c5(a & 31u);
        mesh.colorValid[t] = 1;
      }
    }
  }
  return true;
}

bool Builder::addWarning(Code c, const std::string& msg, uint64_t offset, uint64_t line) {
  if (!tryPushBack(mesh.warnings, Status::error(c, msg, offset, line))) {
    error = oom("the warning list");
    return false;
  }
  return true;
}

}  // namespace stltopo::detail
