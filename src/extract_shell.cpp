// extractShell: one shell as a mesh of its own (for `stltopo split` and the JS extractShell).
#include "stltopo/mesh.h"
#include "stltopo/shells.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"
#include "text_format.h"
#include "triangle_figures.h"
#include "try_alloc.h"

namespace stltopo {

Status extractShell(const Mesh& mesh, const Topology& topo, uint32_t shell, Mesh& out) {
  out = Mesh{};
  const uint32_t nt = mesh.nTriangles(), nv = mesh.nVertices();
  if (topo.triangleShell.size() != nt || topo.nTriangles != nt || topo.nVertices != nv)
    return Status::error(Code::InvalidArgument,
                         "the topology has no triangleShell (TopologyOptions::triangleShell = false)");
  if (shell >= topo.nShells)
    return Status::error(Code::InvalidArgument,
                         detail::format("shell %u does not exist (the mesh has %u)", shell, topo.nShells));
  const char* const kMesh = "the shell's mesh";  // what out-of-memory names
  const uint32_t* ts = topo.triangleShell.data();
  const bool normals = mesh.normals.size() == size_t(nt) * 3;
  const bool colors = mesh.colorConvention != ColorConvention::None && mesh.colors.size() == size_t(nt) * 3 &&
                      mesh.colorValid.size() == nt;
  uint32_t n = 0;
  for (uint32_t t = 0; t < nt; ++t) n += ts[t] == shell;
  // newId[v]: the vertex's id in the shell, numbered by first appearance in corner order.
  Array<uint32_t> newId;
  if (!newId.assign(nv, kInvalid) || !out.triangles.reserve(size_t(n) * 3) || !out.attributes.reserve(n) ||
      (normals && !out.normals.reserve(size_t(n) * 3)) ||
      (colors && (!out.colors.reserve(size_t(n) * 3) || !out.colorValid.reserve(n))))
    return detail::oom(kMesh);
  out.format = mesh.format;
  out.colorConvention = colors ? mesh.colorConvention : ColorConvention::None;
  size_t solid = 0;
  uint32_t nOut = 0, lastSolid = kInvalid;
  for (uint32_t t = 0; t < nt; ++t) {
    if (ts[t] != shell) continue;
    const uint32_t* c = mesh.triangles.data() + size_t(t) * 3;
    for (int k = 0; k < 3; ++k) {
      uint32_t& id = newId[c[k]];
      if (id == kInvalid) {
        id = out.nVertices();
        const float* p = mesh.positions.data() + size_t(c[k]) * 3;
        for (int i = 0; i < 3; ++i)
          if (!out.positions.push_back(p[i])) return detail::oom(kMesh);
      }
      (void)out.triangles.push_back(id);  // reserved
    }
    (void)out.attributes.push_back(mesh.attributes[t]);
    if (normals)
      for (int i = 0; i < 3; ++i) (void)out.normals.push_back(mesh.normals[size_t(t) * 3 + i]);
    if (colors) {
      for (int i = 0; i < 3; ++i) (void)out.colors.push_back(mesh.colors[size_t(t) * 3 + i]);
      (void)out.colorValid.push_back(mesh.colorValid[t]);
    }
    // The solids it has triangles in, in order, each with the count of its triangles there.
    while (solid < mesh.solids.size() &&
           t >= uint64_t(mesh.solids[solid].firstTriangle) + mesh.solids[solid].triangleCount)
      ++solid;
    uint32_t solidOfT =
        solid < mesh.solids.size() && t >= mesh.solids[solid].firstTriangle ? uint32_t(solid) : kInvalid;
    if (solidOfT != kInvalid) {
      if (solidOfT != lastSolid) {
        Solid part;
        const std::string& name = mesh.solids[solidOfT].name;
        part.firstTriangle = nOut;
        if (!detail::tryAssign(part.name, name.data(), name.size()) ||
            !detail::tryPushBack(out.solids, std::move(part)))
          return detail::oom(kMesh);
      }
      ++out.solids.back().triangleCount;
    }
    lastSolid = solidOfT;
    ++nOut;
    const float *a = mesh.positions.data() + size_t(c[0]) * 3, *b = mesh.positions.data() + size_t(c[1]) * 3,
                *d = mesh.positions.data() + size_t(c[2]) * 3;
    const detail::TriangleFigures fig = detail::triangleFigures(a, b, d);
    out.area += fig.area;
    out.volume += fig.volume;
    if (normals && detail::normalMismatch(mesh.normals.data() + size_t(t) * 3, fig, a, b, d)) ++out.normalMismatches;
  }
  const float* p = out.positions.data();
  for (uint32_t v = 0; v < out.nVertices(); ++v)
    for (int k = 0; k < 3; ++k) {
      float x = p[size_t(v) * 3 + k];
      if (v == 0 || x < out.bboxMin[k]) out.bboxMin[k] = x;
      if (v == 0 || x > out.bboxMax[k]) out.bboxMax[k] = x;
    }
  return Status{};
}

}  // namespace stltopo
