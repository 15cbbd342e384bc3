// Fuzz target 2: streaming. The input is
//   [flags] [n chunk-size bytes] [STL bytes]
// with n = (flags & 7) + 1. The STL bytes are fed to a Reader in chunks of those sizes
// (cycled; a size byte b means b bytes, 0 = an empty feed()). The outcome must equal
// readStl() on the whole buffer: the same Status (code, message, location) or the same
// mesh bit for bit, the same warnings and the same JSON report.
//   flags & 0x08: keepNormals        flags & 0x10: pass sizeHint = size
//   flags & 0x20: maxBytes = size    flags & 0x40: reuse the Reader via reset()
//   flags & 0x80: the Reader, and the streamed mesh's topologies, on 3 threads, with every
//                 threaded stage split down to single items (setParallelGrainForTesting(1)):
//                 the threaded read (both of its ways, ranges and pieces, as the batches go)
//                 must give the one-thread whole read's outcome
#include <algorithm>
#include <vector>

#include "fuzz_common.h"

using namespace stltopo;

namespace {

Status readChunked(Reader& r, const uint8_t* p, size_t size, const uint8_t* sizes, size_t nSizes, Mesh& out) {
  size_t i = 0, k = 0, idle = 0;
  while (i < size) {
    size_t c = sizes[k++ % nSizes];
    if (c == 0 && ++idle > nSizes) c = 1;  // every size byte is 0: still make progress
    if (c > 0) idle = 0;
    c = std::min(c, size - i);
    Status s = r.feed(p + i, c);
    i += c;
    if (!s.ok()) {
      // The error is sticky: feed() and finish() keep returning it.
      Status again = r.feed(p, 0);
      FUZZ_CHECK(fuzz::sameStatus(again, s));
      Mesh m;
      Status f = r.finish(m);
      FUZZ_CHECK(fuzz::sameStatus(f, s));
      return s;
    }
  }
  return r.finish(out);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  uint8_t flags = data[0];
  size_t nSizes = size_t(flags & 7) + 1;
  if (size < 1 + nSizes) return 0;
  const uint8_t* sizes = data + 1;
  const uint8_t* p = data + 1 + nSizes;
  size_t n = size - 1 - nSizes;

  ReadOptions o;
  o.keepNormals = (flags & 0x08) != 0;
  if (flags & 0x20) o.maxBytes = n;
  Mesh whole;
  Status ws = readStl(p, n, whole, o);

  static const bool grain = (setParallelGrainForTesting(1), true);
  (void)grain;
  const unsigned threads = (flags & 0x80) ? 3 : 1;
  ReadOptions so = o;
  so.threads = threads;
  if (flags & 0x10) so.sizeHint = n;
  Reader r(so);
  Mesh streamed;
  Status ss = readChunked(r, p, n, sizes, nSizes, streamed);
  if (!fuzz::sameStatus(ws, ss)) {
    std::fprintf(stderr, "whole:    %s\nstreamed: %s\n", ws.message.c_str(), ss.message.c_str());
    FUZZ_CHECK(fuzz::sameStatus(ws, ss));
  }
  if (!ws.ok()) {
    fuzz::checkError(ws);
    FUZZ_CHECK(streamed.nTriangles() == 0 && streamed.solids.empty());
  } else {
    fuzz::checkMesh(whole, o);
    fuzz::checkSameMesh(whole, streamed);
    Topology tw, ts;
    fuzz::checkTopology(whole, TopologyOptions{}, tw);
    TopologyOptions tso;
    tso.threads = threads;
    FUZZ_CHECK(buildTopology(streamed, ts, tso).ok());
    FUZZ_CHECK(fuzz::sameArray(tw.next, ts.next) && fuzz::sameArray(tw.prev, ts.prev) &&
               fuzz::sameArray(tw.vert, ts.vert) && fuzz::sameArray(tw.face, ts.face) &&
               fuzz::sameArray(tw.pairKind, ts.pairKind) && fuzz::sameArray(tw.vertexHalfedge, ts.vertexHalfedge) &&
               fuzz::sameArray(tw.loopHalfedges, ts.loopHalfedges) &&
               fuzz::sameArray(tw.triangleShell, ts.triangleShell));
    FUZZ_CHECK(infoJson("f", whole, &tw) == infoJson("f", streamed, &ts));
    // The exact geometry is the same for every chunking.
    TopologyOptions to;
    to.triangleShell = true;
    to.prevAndFace = false;
    Topology gw, gs;
    TopologyOptions tos = to;
    tos.threads = threads;
    FUZZ_CHECK(buildTopology(whole, gw, to).ok() && buildTopology(streamed, gs, tos).ok());
    Array<Shell> sw, sst;
    Defects dw, ds;
    FUZZ_CHECK(findShellsAndDefects(whole, gw, &sw, &dw).ok() && findShellsAndDefects(streamed, gs, &sst, &ds).ok());
    FUZZ_CHECK(fuzz::checkGeometry(whole, gw, sw, dw) == fuzz::checkGeometry(streamed, gs, sst, ds));
  }
  // finish() twice is an API error, not a crash.
  Mesh again;
  FUZZ_CHECK(r.finish(again).code == Code::InvalidArgument);

  if (flags & 0x40) {
    // After reset() the same Reader gives the same result again, in one feed.
    r.reset();
    Mesh m2;
    Status s2 = n > 0 ? r.feed(p, n) : Status{};
    if (s2.ok()) s2 = r.finish(m2);
    FUZZ_CHECK(fuzz::sameStatus(ws, s2));
    if (ws.ok()) fuzz::checkSameMesh(whole, m2);
  }
  return 0;
}
