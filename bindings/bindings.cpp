// Embind bindings for the wasm build. Raw, underscore-prefixed API only: the
// friendly JavaScript API lives in web/src (core.js). Nothing here throws; every
// failure comes back as a status object ({code, message, offset?, line?,
// triangle?, element?}) or null for success.
//
// Typed arrays leave wasm memory in one of two ways (see array()):
//   copy = true : a view is taken and slice()d in the same expression, so the JS
//                 array owns its bytes and never detaches;
//   copy = false: a borrowed view into wasm memory. It detaches when memory grows
//                 (emscripten#6747) and dangles after the session is deleted.
#include <emscripten/bind.h>
#include <emscripten/heap.h>
#include <emscripten/val.h>
#include <malloc.h>

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "stltopo.h"

using emscripten::typed_memory_view;
using emscripten::val;

namespace {

using stltopo::Array;
using stltopo::Code;
using stltopo::Status;

val statusToJs(const Status& s) {
  if (s.ok()) return val::null();
  val o = val::object();
  o.set("code", val(stltopo::codeName(s.code)));
  o.set("message", val(s.message));
  if (s.offset != stltopo::kNoOffset) o.set("offset", val(double(s.offset)));
  if (s.line != 0) o.set("line", val(double(s.line)));
  if (s.triangle != stltopo::kInvalid) o.set("triangle", val(s.triangle));
  if (s.element != stltopo::kInvalid) o.set("element", val(s.element));
  return o;
}

Status makeStatus(Code c, const char* message) {
  Status s;
  s.code = c;
  s.message = std::string(stltopo::codeName(c)) + ": " + message;
  return s;
}

template <class T>
val arrayToJs(const Array<T>& a, bool copy) {
  val v(typed_memory_view(a.size(), a.data()));
  return copy ? v.call<val>("slice") : v;
}

// One load: a streaming reader, then the mesh and (optionally) its topology.
// Also used the other way round by validate() on JS-owned copies: upload()
// allocates the arrays, JS fills them, validate() checks them.
class Session {
 public:
  Session(double maxTriangles, double maxBytes, double sizeHint, bool keepNormals) {
    options_.maxTriangles = maxTriangles >= 0 && maxTriangles <= 4294967295.0 ? uint32_t(maxTriangles) : options_.maxTriangles;
    options_.maxBytes = !(maxBytes > 0) ? 0 : maxBytes >= 18446744073709551615.0 ? ~uint64_t(0) : uint64_t(maxBytes);
    options_.sizeHint = sizeHint > 0 ? uint64_t(sizeHint) : 0;
    options_.keepNormals = keepNormals;
    reader_ = new (std::nothrow) stltopo::Reader(options_);
  }
  ~Session() {
    delete reader_;
    std::free(input_);
  }

  // A writable view of n bytes of the input buffer; null when it cannot be
  // allocated. JS must fill it before its next call into wasm.
  val buffer(size_t n) {
    if (n > inputCap_) {
      void* p = std::realloc(input_, n);
      if (!p) return val::null();
      input_ = static_cast<uint8_t*>(p);
      inputCap_ = n;
    }
    return val(typed_memory_view(n, input_));
  }

  // Feeds the first n bytes of the input buffer.
  val feed(size_t n) {
    if (!reader_) return statusToJs(makeStatus(Code::OutOfMemory, "could not allocate the reader"));
    if (n > inputCap_) return statusToJs(makeStatus(Code::InvalidArgument, "feed() larger than buffer()"));
    return remember(reader_->feed(input_, n));
  }

  // Completes the read, frees the reader and builds the topology when asked
  // (prevAndFace false: without the prev and face arrays, see TopologyOptions).
  val finish(bool topology, double tolerance, bool prevAndFace) {
    if (!reader_) return statusToJs(makeStatus(Code::OutOfMemory, "could not allocate the reader"));
    std::free(input_);
    input_ = nullptr;
    inputCap_ = 0;
    Status s = reader_->finish(mesh_);
    bytesRead_ = double(reader_->bytesRead());
    delete reader_;
    reader_ = nullptr;
    if (!s.ok()) return remember(s);
    if (topology) {
      stltopo::TopologyOptions to;
      to.tolerance = tolerance > 0 ? tolerance : 0;
      to.prevAndFace = prevAndFace;
      s = stltopo::buildTopology(mesh_, topo_, to);
      if (!s.ok()) return remember(s);
      hasTopology_ = true;
    }
    return val::null();
  }

  double bytesRead() const { return reader_ ? double(reader_->bytesRead()) : bytesRead_; }

  // Scalars and small lists of the result.
  val meta() const {
    val o = val::object();
    o.set("format", val(stltopo::formatName(mesh_.format)));
    o.set("colorConvention", val(stltopo::colorConventionName(mesh_.colorConvention)));
    o.set("nVertices", val(mesh_.nVertices()));
    o.set("nTriangles", val(mesh_.nTriangles()));
    o.set("hasTopology", val(hasTopology_));
    o.set("hasNormals", val(!mesh_.normals.empty() || (options_.keepNormals && mesh_.nTriangles() == 0)));
    val solids = val::array();
    for (const stltopo::Solid& s : mesh_.solids) {
      val so = val::object();
      so.set("name", val(s.name));
      so.set("firstTriangle", val(s.firstTriangle));
      so.set("triangleCount", val(s.triangleCount));
      solids.call<void>("push", so);
    }
    o.set("solids", solids);
    val warnings = val::array();
    for (const Status& w : mesh_.warnings) warnings.call<void>("push", statusToJs(w));
    o.set("warnings", warnings);
    if (hasTopology_) {
      val c = val::object();
      c.set("nEdges", val(topo_.nEdges));
      c.set("nBoundaryEdges", val(topo_.nBoundaryEdges));
      c.set("nNonManifoldEdges", val(topo_.nNonManifoldEdges));
      c.set("nInconsistentEdges", val(topo_.nInconsistentEdges));
      c.set("nNonManifoldVertices", val(topo_.nNonManifoldVertices));
      c.set("nDegenerate", val(topo_.nDegenerate));
      c.set("nShells", val(topo_.nShells));
      c.set("nUsedVertices", val(topo_.nUsedVertices));
      c.set("nHoles", val(topo_.nHoles));
      c.set("nSeams", val(topo_.nSeams));
      o.set("counts", c);
    } else {
      o.set("counts", val::null());
    }
    return o;
  }

  // The JSON report, byte for byte what the native CLI prints.
  std::string infoJson(const std::string& file) const {
    return stltopo::infoJson(file, mesh_, hasTopology_ ? &topo_ : nullptr);
  }

  // The native CLI's text report (src/cli.cpp printText), byte for byte: a
  // Uint8Array, since solid names may hold bytes that are not UTF-8.
  val infoText(const std::string& file) const { return bytesToJs(infoTextString(file)); }

  // The message of the last failed feed()/finish() as bytes (the native CLI
  // prints messages raw; a JS string would replace invalid UTF-8).
  val messageBytes() const { return bytesToJs(last_.message); }

  // A named result array (see withArray for the names); null for an unknown name.
  val array(const std::string& name, bool copy) {
    val out = val::null();
    withArray(name, [&](auto& a) { out = arrayToJs(a, copy); });
    return out;
  }

  // Allocates a named array of n elements and returns a writable view of it;
  // null on allocation failure or unknown name.
  val upload(const std::string& name, double n) {
    val out = val::null();
    withArray(name, [&](auto& a) {
      if (n >= 0 && a.resize(size_t(n))) out = val(typed_memory_view(a.size(), a.data()));
    });
    return out;
  }

  // For validate() on uploaded arrays: the counts that are not array lengths.
  void setCounts(double nHoles, double nSeams, double nUsedVertices) {
    topo_.nTriangles = mesh_.nTriangles();
    topo_.nVertices = mesh_.nVertices();
    topo_.nHoles = uint32_t(nHoles);
    topo_.nSeams = uint32_t(nSeams);
    topo_.nUsedVertices = uint32_t(nUsedVertices);
    hasTopology_ = true;
  }

  val validate() const {
    if (!hasTopology_) return statusToJs(makeStatus(Code::InvalidArgument, "the mesh has no topology (loaded with topology: false)"));
    return statusToJs(stltopo::validate(mesh_, topo_));
  }

 private:
  std::string infoTextString(const std::string& file) const;
  static val bytesToJs(const std::string& s) {
    return val(typed_memory_view(s.size(), reinterpret_cast<const uint8_t*>(s.data()))).call<val>("slice");
  }
  val remember(const Status& s) {
    if (!s.ok()) last_ = s;
    return statusToJs(s);
  }

  template <class F>
  void withArray(const std::string& n, F&& f) {
    stltopo::Mesh& m = mesh_;
    stltopo::Topology& t = topo_;
    if (n == "positions") f(m.positions);
    else if (n == "triangles") f(m.triangles);
    else if (n == "attributes") f(m.attributes);
    else if (n == "normals") f(m.normals);
    else if (n == "colors") f(m.colors);
    else if (n == "colorValid") f(m.colorValid);
    else if (n == "next") f(t.next);
    else if (n == "prev") f(t.prev);
    else if (n == "vert") f(t.vert);
    else if (n == "face") f(t.face);
    else if (n == "pairKind") f(t.pairKind);
    else if (n == "triangleHalfedge") f(t.triangleHalfedge);
    else if (n == "vertexHalfedge") f(t.vertexHalfedge);
    else if (n == "vertexWeld") f(t.vertexWeld);
    else if (n == "loopHalfedge") f(t.loopHalfedge);
    else if (n == "loopOffsets") f(t.loopOffsets);
    else if (n == "loopHalfedges") f(t.loopHalfedges);
    else if (n == "loopIsSeam") f(t.loopIsSeam);
    else if (n == "loopPerimeter") f(t.loopPerimeter);
    else if (n == "triangleDegenerate") f(t.triangleDegenerate);
    else if (n == "vertexNonManifold") f(t.vertexNonManifold);
  }

  stltopo::ReadOptions options_;
  stltopo::Reader* reader_ = nullptr;
  uint8_t* input_ = nullptr;
  size_t inputCap_ = 0;
  double bytesRead_ = 0;
  stltopo::Mesh mesh_;
  stltopo::Topology topo_;
  bool hasTopology_ = false;
  Status last_;
};

std::string Session::infoTextString(const std::string& file) const {
  return stltopo::infoText(file, mesh_, hasTopology_ ? &topo_ : nullptr);
}

// errorJson for a status made in JS (e.g. the npm CLI's "cannot open").
std::string errorJson(const std::string& file, const std::string& code, const std::string& message, double offset,
                      double line, double triangle) {
  Status s;
  s.code = Code::InvalidArgument;
  for (int c = 0; c <= int(Code::NameTruncated); ++c)
    if (code == stltopo::codeName(Code(c))) s.code = Code(c);
  s.message = message;
  s.offset = offset >= 0 ? uint64_t(offset) : stltopo::kNoOffset;
  s.line = line > 0 ? uint64_t(line) : 0;
  s.triangle = triangle >= 0 ? uint32_t(triangle) : stltopo::kInvalid;
  return stltopo::errorJson(file, s);
}

// The allocator's in-use bytes (dlmalloc mallinfo), for the heap-baseline tests.
double heapInUse() { return double(mallinfo().uordblks); }
double heapSize() { return double(emscripten_get_heap_size()); }
double heapMax() { return double(emscripten_get_heap_max()); }

// Test hook: occupy the heap so that at most about `leave` bytes stay allocatable,
// to prove that allocation failure becomes an out-of-memory status. Returns the
// number of bytes held. testRelease() gives them back.
void* gBallast[8192];
size_t gBallastSize[8192];
int gBallastCount = 0;
void testRelease() {
  for (int i = 0; i < gBallastCount; ++i) std::free(gBallast[i]);
  gBallastCount = 0;
}
double testFill(double leave) {
  testRelease();
  double held = 0;
  for (size_t size = size_t(1) << 28; size >= (size_t(1) << 16); size >>= 1) {
    while (gBallastCount < 8192) {
      void* p = std::malloc(size);
      if (!p) break;
      gBallast[gBallastCount] = p;
      gBallastSize[gBallastCount++] = size;
      held += double(size);
    }
  }
  // Free the smallest blocks until about `leave` bytes are available again.
  double freed = 0;
  while (gBallastCount > 0 && freed < leave) {
    --gBallastCount;
    std::free(gBallast[gBallastCount]);
    freed += double(gBallastSize[gBallastCount]);
    held -= double(gBallastSize[gBallastCount]);
  }
  return held;
}

// Test hook: a wasm abort (what a failed operator new would do), to prove that
// the JS layer drops the dead instance and the next load gets a fresh one.
void testAbort() { std::abort(); }

}  // namespace

EMSCRIPTEN_BINDINGS(stltopo) {
  using namespace emscripten;
  class_<Session>("_Session")
      .constructor<double, double, double, bool>()
      .function("buffer", &Session::buffer)
      .function("feed", &Session::feed)
      .function("finish", &Session::finish)
      .function("bytesRead", &Session::bytesRead)
      .function("meta", &Session::meta)
      .function("infoJson", &Session::infoJson)
      .function("infoText", &Session::infoText)
      .function("messageBytes", &Session::messageBytes)
      .function("array", &Session::array)
      .function("upload", &Session::upload)
      .function("setCounts", &Session::setCounts)
      .function("validate", &Session::validate);
  function("_errorJson", &errorJson);
  function("_heapInUse", &heapInUse);
  function("_heapSize", &heapSize);
  function("_heapMax", &heapMax);
  function("_testFill", &testFill);
  function("_testRelease", &testRelease);
  function("_testAbort", &testAbort);
}
