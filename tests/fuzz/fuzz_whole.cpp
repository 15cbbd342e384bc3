// Fuzz target 1: the whole buffer. Read, weld, build the topology, validate() it and
// render the JSON report. A read error must carry a known code and a message.
// Reads with a triangle limit must respect it and otherwise agree.
#include "fuzz_common.h"

using namespace stltopo;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ReadOptions o;
  Mesh m;
  Status s = readStl(data, size, m, o);
  if (!s.ok()) {
    fuzz::checkError(s);
    return 0;
  }
  fuzz::checkMesh(m, o);
  Topology t;
  fuzz::checkTopology(m, TopologyOptions{}, t);
  fuzz::checkShells(m, TopologyOptions{}, t);

  // maxTriangles = exactly enough (and keepNormals, which only adds the normals array)
  // reads the same; one fewer never yields more triangles.
  ReadOptions ol = o;
  ol.maxTriangles = m.nTriangles();
  ol.keepNormals = true;
  Mesh ml;
  Status sl = readStl(data, size, ml, ol);
  FUZZ_CHECK(sl.ok());
  fuzz::checkMesh(ml, ol);
  ml.normals.release();
  fuzz::checkSameMesh(m, ml);
  if (m.nTriangles() > 0) {
    ol.maxTriangles = m.nTriangles() - 1;
    Mesh ms;
    Status ss = readStl(data, size, ms, ol);
    if (ss.ok())
      fuzz::checkMesh(ms, ol);
    else
      fuzz::checkError(ss);
  }
  return 0;
}
