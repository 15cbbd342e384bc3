// Prints a 64-bit FNV-1a hash and the length of every array that the reader and the
// topology produce for each file: exact weld (full and report-only topology), a tolerance
// weld, and keepNormals; with triangleShell and the defect lists. Two builds of the code that print the same lines
// produce the same arrays. Used to prove that a change which should keep the output does (see scripts/snapshot.sh).
#include <cstdio>
#include <string>
#include <vector>

#include "stltopo/stltopo.h"

namespace {
template <class A>
void put(const char* name, const A& a) {
  uint64_t h = 1469598103934665603ull;
  const unsigned char* p = reinterpret_cast<const unsigned char*>(a.data());
  size_t n = a.size() * sizeof(a[0]);
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  std::printf(" %s=%zu:%016llx", name, a.size(), static_cast<unsigned long long>(h));
}
// Every topology is built with triangleShell, and its shells and defects are printed too.
void topo(const char* label, const stltopo::Mesh& m, stltopo::TopologyOptions o) {
  stltopo::Topology t;
  o.triangleShell = true;
  stltopo::Status s = stltopo::buildTopology(m, t, o);
  std::printf(" %s:%s", label, stltopo::codeName(s.code));
  if (!s.ok()) return;
  put("next", t.next);
  put("prev", t.prev);
  put("vert", t.vert);
  put("face", t.face);
  put("pairKind", t.pairKind);
  put("triangleHalfedge", t.triangleHalfedge);
  put("vertexHalfedge", t.vertexHalfedge);
  put("vertexWeld", t.vertexWeld);
  put("loopHalfedge", t.loopHalfedge);
  put("loopOffsets", t.loopOffsets);
  put("loopHalfedges", t.loopHalfedges);
  put("loopIsSeam", t.loopIsSeam);
  put("loopPerimeter", t.loopPerimeter);
  put("triangleDegenerate", t.triangleDegenerate);
  put("vertexNonManifold", t.vertexNonManifold);
  std::printf(" counts=%u,%u,%u,%u,%u,%u,%u,%u,%u,%u", t.nEdges, t.nBoundaryEdges, t.nNonManifoldEdges,
              t.nInconsistentEdges, t.nNonManifoldVertices, t.nDegenerate, t.nShells, t.nUsedVertices, t.nHoles,
              t.nSeams);
  put("triangleShell", t.triangleShell);
  stltopo::Defects d;
  s = stltopo::findShellsAndDefects(m, t, nullptr, &d);
  std::printf(" shells:%s", stltopo::codeName(s.code));
  put("nonManifoldEdgeVertices", d.nonManifoldEdgeVertices);
  put("nonManifoldEdgeOffsets", d.nonManifoldEdgeOffsets);
  put("nonManifoldEdgeTriangles", d.nonManifoldEdgeTriangles);
  put("inconsistentEdgeVertices", d.inconsistentEdgeVertices);
  put("inconsistentEdgeTriangles", d.inconsistentEdgeTriangles);
  put("nonManifoldVertices", d.nonManifoldVertices);
  put("nonManifoldVertexCycles", d.nonManifoldVertexCycles);
  put("degenerateTriangles", d.degenerateTriangles);
  put("degenerateCorners", d.degenerateCorners);
  put("loopShell", d.loopShell);
}
}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    FILE* f = std::fopen(argv[i], "rb");
    if (!f) {
      std::printf("%s: cannot open\n", argv[i]);
      continue;
    }
    std::vector<uint8_t> buf;
    unsigned char tmp[65536];
    size_t n;
    while ((n = std::fread(tmp, 1, sizeof tmp, f)) > 0) buf.insert(buf.end(), tmp, tmp + n);
    std::fclose(f);
    stltopo::ReadOptions ro;
    ro.keepNormals = true;
    stltopo::Mesh m;
    stltopo::Status s = stltopo::readStl(buf.data(), buf.size(), m, ro);
    std::printf("%s read:%s", argv[i], stltopo::codeName(s.code));
    if (s.ok()) {
      put("positions", m.positions);
      put("triangles", m.triangles);
      put("attributes", m.attributes);
      put("normals", m.normals);
      put("colors", m.colors);
      put("colorValid", m.colorValid);
      topo("exact", m, {});
      stltopo::TopologyOptions lean;
      lean.prevAndFace = false;
      topo("lean", m, lean);
      stltopo::TopologyOptions tol;
      tol.tolerance = 1e-3;
      topo("tol", m, tol);
    }
    std::printf("\n");
  }
}
