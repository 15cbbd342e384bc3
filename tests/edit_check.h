// Test helper for the EditableMesh: compares an edited mesh with a fresh buildTopology of
// its compacted form, array by array. Shared by test_edit.cpp and the fuzz target.
#pragma once

#include <string>

#include "edit.h"
#include "stl_gen.h"

namespace editcheck {

// "" when the edited mesh is consistent: its own validate() holds, toMesh()'s topology
// equals buildTopology(toMesh()'s mesh) in every array and count, and stats() and loops()
// agree with that build. Else the first difference.
inline std::string differenceFromRebuild(stltopo::EditableMesh& em) {
  using namespace stltopo;
  Status s = em.validate();
  if (!s.ok()) return "validate: " + s.message;
  Mesh m;
  Topology t;
  s = em.toMesh(m, &t);
  if (!s.ok()) return "toMesh: " + s.message;
  Topology f;
  s = buildTopology(m, f);
  if (!s.ok()) return "buildTopology: " + s.message;
#define EDITCHECK_SAME(x) \
  if (!gen::sameArray(t.x, f.x)) return "array " #x " differs from a fresh build";
  EDITCHECK_SAME(next) EDITCHECK_SAME(prev) EDITCHECK_SAME(vert) EDITCHECK_SAME(face) EDITCHECK_SAME(pairKind)
  EDITCHECK_SAME(triangleHalfedge) EDITCHECK_SAME(vertexHalfedge) EDITCHECK_SAME(vertexWeld)
  EDITCHECK_SAME(loopHalfedge) EDITCHECK_SAME(loopOffsets) EDITCHECK_SAME(loopHalfedges) EDITCHECK_SAME(loopIsSeam)
  EDITCHECK_SAME(loopPerimeter) EDITCHECK_SAME(triangleDegenerate) EDITCHECK_SAME(vertexNonManifold)
#undef EDITCHECK_SAME
#define EDITCHECK_COUNT(x) \
  if (t.x != f.x) return "count " #x " differs from a fresh build: " + std::to_string(t.x) + " vs " + std::to_string(f.x);
  EDITCHECK_COUNT(nTriangles) EDITCHECK_COUNT(nVertices) EDITCHECK_COUNT(nEdges) EDITCHECK_COUNT(nBoundaryEdges)
  EDITCHECK_COUNT(nNonManifoldEdges) EDITCHECK_COUNT(nInconsistentEdges) EDITCHECK_COUNT(nNonManifoldVertices)
  EDITCHECK_COUNT(nDegenerate) EDITCHECK_COUNT(nShells) EDITCHECK_COUNT(nUsedVertices) EDITCHECK_COUNT(nHoles)
  EDITCHECK_COUNT(nSeams)
#undef EDITCHECK_COUNT
  if (infoJson("f", m, &t) != infoJson("f", m, &f)) return "infoJson differs from a fresh build";
  if (em.infoJson("f") != infoJson("f", m, &f)) return "EditableMesh::infoJson differs from a fresh build";
  const EditStats& st = em.stats();
  if (st.triangles != f.nTriangles || st.vertices != f.nVertices || st.degenerate != f.nDegenerate ||
      st.edges != f.nEdges || st.boundaryEdges != f.nBoundaryEdges || st.nonManifoldEdges != f.nNonManifoldEdges ||
      st.inconsistentEdges != f.nInconsistentEdges || st.nonManifoldVertices != f.nNonManifoldVertices ||
      st.usedVertices != f.nUsedVertices || st.holes != f.nHoles || st.seams != f.nSeams || st.shells != f.nShells ||
      st.eulerCharacteristic != f.eulerCharacteristic() || st.watertight != f.watertight() || st.manifold != f.manifold())
    return "stats() differ from a fresh build";
  const EditLoops& l = em.loops();
  if (!gen::sameArray(l.loopOffsets, f.loopOffsets) || !gen::sameArray(l.loopIsSeam, f.loopIsSeam) ||
      !gen::sameArray(l.loopPerimeter, f.loopPerimeter))
    return "loops() differ from a fresh build";
  for (uint32_t h = 0; h < l.nLoops(); ++h)
    for (uint32_t i = l.loopOffsets[h]; i < l.loopOffsets[h + 1]; ++i) {
      uint32_t e = l.loopHalfedges[i];
      if (em.face(e) != (kLoopFaceBit | h)) return "face of a loop half-edge is not its loop";
    }
  return "";
}

}  // namespace editcheck
