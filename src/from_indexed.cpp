// A Mesh from an indexed triangle list (see stltopo/indexed.h): the checks, then the
// triangles through the mesh builder, as a parser hands them over.
#include <cmath>
#include <cstring>

#include "mesh_builder.h"
#include "solid_parts.h"
#include "stltopo/indexed.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "text_format.h"
#include "try_alloc.h"

namespace stltopo {

using detail::Builder;
using detail::format;

namespace {

constexpr uint64_t kMaxElements = 0xFFFFFFFEull;  // 2^32 - 2: ids stay below the sentinels

Status check(const IndexedMesh& in) {
  if (in.positionsLength % 3 != 0 || in.trianglesLength % 3 != 0)
    return Status::error(Code::InvalidArgument,
                         format("positions (%zu values) and triangles (%zu values) must hold 3 values per element",
                                in.positionsLength, in.trianglesLength));
  const uint64_t nv = in.positionsLength / 3, nt = in.trianglesLength / 3;
  if (nv > kMaxElements || nt > kMaxElements)
    return Status::error(Code::TooLarge, format("%llu vertices and %llu triangles: at most 2^32 - 2 of each",
                                                (unsigned long long)nv, (unsigned long long)nt));
  if ((nv > 0 && !in.positions) || (nt > 0 && !in.triangles) || (in.nSolids > 0 && !in.solids))
    return Status::error(Code::InvalidArgument, "a null array with a non-zero length");
  if (in.attributes && in.colors)
    return Status::error(Code::InvalidArgument, "attributes and colors together: colours become the attribute words");
  if (in.colorValid && !in.colors) return Status::error(Code::InvalidArgument, "colorValid without colors");
  for (uint64_t v = 0; v < nv; ++v) {
    const float* p = in.positions + 3 * v;
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(p[k])) {
        Status s = Status::error(Code::NonFinite, format("vertex %llu has a non-finite coordinate (%c = %g)",
                                                         (unsigned long long)v, "xyz"[k], double(p[k])));
        s.element = uint32_t(v);
        return s;
      }
  }
  for (uint64_t t = 0; t < nt; ++t)
    for (int c = 0; c < 3; ++c)
      if (in.triangles[3 * t + c] >= nv)
        return Status::error(Code::InvalidIndex,
                             format("triangle %llu corner %d is vertex %u, but there are %llu vertices",
                                    (unsigned long long)t, c, in.triangles[3 * t + c], (unsigned long long)nv),
                             kNoOffset, 0, uint32_t(t));
  return Status{};
}

}  // namespace

Status meshFromIndexed(const IndexedMesh& in, Mesh& out, Array<uint32_t>* vertexMap, const IndexedOptions& options) {
  Status s = check(in);
  if (!s.ok()) return s;
  const uint32_t nv = uint32_t(in.positionsLength / 3), nt = uint32_t(in.trianglesLength / 3);
  Array<detail::SolidPart> parts;
  s = detail::solidParts(in.solids, in.nSolids, nt, parts);
  if (!s.ok()) return s;
  ReadOptions ro;
  ro.maxTriangles = nt;
  Builder b(ro);
  Array<uint32_t> map;
  const bool weld = options.weld == Weld::Exact;
  if (!b.reserveTriangles(nt) || !map.resize(nv) || (!weld && !b.mesh.positions.resize(in.positionsLength)))
    return detail::oom("the mesh arrays");
  if (weld) {
    for (uint32_t v = 0; v < nv; ++v) map[v] = kInvalid;
  } else {
    // The caller's vertices as they are: positions and bounding box over all of them.
    if (nv > 0) std::memcpy(b.mesh.positions.data(), in.positions, in.positionsLength * sizeof(float));
    for (uint32_t v = 0; v < nv; ++v) {
      map[v] = v;
      for (int k = 0; k < 3; ++k) {
        float x = in.positions[3 * size_t(v) + k];
        if (v == 0 || x < b.mesh.bboxMin[k]) b.mesh.bboxMin[k] = x;
        if (v == 0 || x > b.mesh.bboxMax[k]) b.mesh.bboxMax[k] = x;
      }
    }
  }
  static const float kNoNormal[3] = {0, 0, 0};
  for (const detail::SolidPart& p : parts) {
    const std::string* name = p.solid == kInvalid ? nullptr : &in.solids[p.solid].name;
    if (!b.beginSolid(name ? name->data() : "", name ? name->size() : 0, nullptr)) return b.error;
    for (uint32_t t = p.first; t < p.first + p.count; ++t) {
      const uint32_t* ids = in.triangles + 3 * size_t(t);
      float v[9];
      for (int c = 0; c < 3; ++c) std::memcpy(v + 3 * c, in.positions + 3 * size_t(ids[c]), 3 * sizeof(float));
      uint16_t word = in.attributes ? in.attributes[t] : 0;
      if (in.colors && (!in.colorValid || in.colorValid[t])) word = Builder::visCamWord(in.colors + 3 * size_t(t));
      if (weld) {
        if (!b.add(kNoNormal, v, word, kNoOffset, 0)) return b.error;
        for (int c = 0; c < 3; ++c) map[ids[c]] = b.mesh.triangles[3 * size_t(t) + c];
      } else {
        // Capacity reserved above.
        (void)b.mesh.triangles.resize(3 * (size_t(t) + 1));
        std::memcpy(b.mesh.triangles.data() + 3 * size_t(t), ids, 3 * sizeof(uint32_t));
        (void)b.mesh.attributes.push_back(word);
        b.figures(kNoNormal, v, word);
      }
    }
    b.endSolid();
  }
  if (in.colors) {
    Mesh& m = b.mesh;
    m.colorConvention = ColorConvention::VisCam;
    if (!m.colors.resize(3 * size_t(nt)) || !m.colorValid.resize(nt)) return detail::oom("the colour arrays");
    if (nt > 0) std::memcpy(m.colors.data(), in.colors, 3 * size_t(nt));
    for (uint32_t t = 0; t < nt; ++t) m.colorValid[t] = in.colorValid ? (in.colorValid[t] ? 1 : 0) : 1;
  } else if (!b.decodeColors()) {
    return detail::oom("the colour arrays");
  }
  b.releaseWeld();
  out = std::move(b.mesh);
  if (vertexMap) *vertexMap = std::move(map);
  return Status{};
}

}  // namespace stltopo
