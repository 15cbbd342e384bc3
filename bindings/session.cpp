// The adapters of the load's session (session.h) and of the free functions that bindings.cpp
// registers: JS numbers and objects in, statuses, typed arrays and JSON out.
#include "session.h"

#include <cstdlib>
#include <cstring>
#include <new>
#include <string>

using emscripten::typed_memory_view;
using emscripten::val;

namespace stltopo::js {

namespace {
unsigned gThreads = 1;

val utf8Decoder() {
  static val* decoder = new val(val::global("TextDecoder").new_(val("utf-8")));
  return *decoder;
}
}  // namespace

void setThreads(double n) {
#if defined(__EMSCRIPTEN_PTHREADS__)
  gThreads = n >= 1 && n <= 64 ? unsigned(n) : 1;
#else
  (void)n;
  gThreads = 1;
#endif
}

unsigned threads() { return gThreads; }

Session::Session(double maxTriangles, double maxBytes, double sizeHint, bool keepNormals) {
  options_.threads = gThreads;
  options_.maxTriangles =
      maxTriangles >= 0 && maxTriangles <= 4294967295.0 ? uint32_t(maxTriangles) : options_.maxTriangles;
  options_.maxBytes = !(maxBytes > 0) ? 0 : maxBytes >= 18446744073709551615.0 ? ~uint64_t(0) : uint64_t(maxBytes);
  options_.sizeHint = sizeHint > 0 ? uint64_t(sizeHint) : 0;
  options_.keepNormals = keepNormals;
  reader_ = new (std::nothrow) Reader(options_);
}

Session::~Session() {
  delete reader_;
  std::free(input_);
}

val Session::buffer(size_t n) {
  if (n > inputCap_) {
    void* p = std::realloc(input_, n);
    if (!p) return val::null();
    input_ = static_cast<uint8_t*>(p);
    inputCap_ = n;
  }
  return val(typed_memory_view(n, input_));
}

val Session::feed(size_t n) {
  if (!reader_) return status(Status::error(Code::OutOfMemory, "could not allocate the reader"));
  if (n > inputCap_) return status(Status::error(Code::InvalidArgument, "feed() larger than buffer()"));
  return remember(reader_->feed(input_, n));
}

val Session::finish(bool topology, double tolerance, bool prevAndFace, bool shells) {
  if (!reader_) return status(Status::error(Code::OutOfMemory, "could not allocate the reader"));
  std::free(input_);
  input_ = nullptr;
  inputCap_ = 0;
  Status s = reader_->finish(mesh_);
  bytesRead_ = double(reader_->bytesRead());
  delete reader_;
  reader_ = nullptr;
  if (!s.ok()) return remember(s);
  return buildTopology(topology, tolerance, prevAndFace, shells);
}

double Session::bytesRead() const { return reader_ ? double(reader_->bytesRead()) : bytesRead_; }

val Session::meta() const {
  val o = val::object();
  o.set("format", val(formatName(mesh_.format)));
  o.set("colorConvention", val(colorConventionName(mesh_.colorConvention)));
  o.set("nVertices", val(mesh_.nVertices()));
  o.set("nTriangles", val(mesh_.nTriangles()));
  o.set("hasTopology", val(hasTopology_));
  o.set("hasShells", val(hasShells_));
  o.set("hasIntersections", val(hasIntersections_));
  o.set("hasNormals", val(!mesh_.normals.empty() || (options_.keepNormals && mesh_.nTriangles() == 0)));
  o.set("indexed", val(indexed_));
  val solids = val::array();
  for (const Solid& s : mesh_.solids) {
    val so = val::object();
    // Decoded by TextDecoder (invalid UTF-8 becomes U+FFFD): Embind's std::string decoder
    // reads past the end of a short name that ends inside a multi-byte sequence, so such a
    // name came out as whatever bytes followed it in memory.
    so.set("name", utf8Decoder().call<val>("decode", bytesToJs(s.name)));
    so.set("firstTriangle", val(s.firstTriangle));
    so.set("triangleCount", val(s.triangleCount));
    solids.call<void>("push", so);
  }
  o.set("solids", solids);
  val warnings = val::array();
  for (const Status& w : mesh_.warnings) warnings.call<void>("push", status(w));
  o.set("warnings", warnings);
  if (hasTopology_) {
    val c = val::object();
#define STLTOPO_COUNT(count, name, doc) c.set(#count, val(topo_.count));
    STLTOPO_TOPOLOGY_COUNTS(STLTOPO_COUNT)
#undef STLTOPO_COUNT
    c.set("tolerance", val(topo_.tolerance));
    o.set("counts", c);
  } else {
    o.set("counts", val::null());
  }
  return o;
}

std::string Session::infoJson(const std::string& file, bool, bool, double) const {
  return stltopo::infoJson(file, mesh_, hasTopology_ ? &topo_ : nullptr);
}

val Session::infoText(const std::string& file, bool, bool, double) const {
  return bytesToJs(stltopo::infoText(file, mesh_, hasTopology_ ? &topo_ : nullptr));
}

val Session::messageBytes() const { return bytesToJs(last_.message); }

// The rows this session serves: the table without the full module's (STLTOPO_JS_SKIP).
val Session::array(const std::string& n, bool copy) {
#define STLTOPO_CASE(name, part_, ...) \
  if (n == #name) return js::array(part(static_cast<stltopo::part_*>(nullptr)).name, copy);
  STLTOPO_JS_ARRAYS(STLTOPO_CASE, STLTOPO_JS_SKIP)
#undef STLTOPO_CASE
  return val::null();
}

val Session::upload(const std::string& n, double size) {
#define STLTOPO_CASE(name, part_, ...) \
  if (n == #name) return uploadTo(part(static_cast<stltopo::part_*>(nullptr)).name, size);
  STLTOPO_JS_ARRAYS(STLTOPO_CASE, STLTOPO_JS_SKIP)
#undef STLTOPO_CASE
  return val::null();
}

void Session::setCounts(const val& c) {
  topo_.nTriangles = mesh_.nTriangles();
  topo_.nVertices = mesh_.nVertices();
#define STLTOPO_COUNT(count, name, doc) topo_.count = c[#count].as<uint32_t>();
  STLTOPO_TOPOLOGY_COUNTS(STLTOPO_COUNT)
#undef STLTOPO_COUNT
  topo_.tolerance = c["tolerance"].as<double>();
  hasTopology_ = true;
}

void Session::setMeta(const std::string& convention, val solids) {
  mesh_.colorConvention = colorConvention(convention);
  mesh_.solids.clear();
  const int n = solids.isArray() ? solids["length"].as<int>() : 0;
  for (int i = 0; i < n; ++i) {
    val so = solids[i];
    Solid s;
    s.name = so["name"].isString() ? so["name"].as<std::string>() : std::string();
    double first = so["firstTriangle"].as<double>(), count = so["triangleCount"].as<double>();
    s.firstTriangle = first >= 0 && first <= 4294967295.0 ? uint32_t(first) : kInvalid;
    s.triangleCount = count >= 0 && count <= 4294967295.0 ? uint32_t(count) : kInvalid;
    mesh_.solids.push_back(std::move(s));
  }
}

val Session::validate() const {
  if (!hasTopology_)
    return status(Status::error(Code::InvalidArgument, "the mesh has no topology (loaded with topology: false)"));
  return status(stltopo::validate(mesh_, topo_));
}

Status Session::findShells() {
  return Status::error(Code::InvalidArgument, "shells and defects are in the full module (stltopo-full)");
}

Status Session::topologyOf(const TopologyOptions& to) { return stltopo::buildTopology(mesh_, topo_, to); }

val Session::buildTopology(bool topology, double tolerance, bool prevAndFace, bool shells) {
  if (!topology) return val::null();
  TopologyOptions to;
  to.threads = gThreads;
  to.tolerance = tolerance > 0 ? tolerance : 0;
  to.prevAndFace = prevAndFace;
  to.triangleShell = shells;
  // prev and face (8 B a half-edge, 24 a triangle) are asked for views and validate(): when
  // the heap cannot hold them, the topology without them (JS derives them on first read).
  // The core goes on without them when they are what fails (prevAndFaceIfRoom), so that its
  // first passes do not run twice; a later allocation that fails with them held (the loops,
  // the vertex classes) builds the topology again without them.
  to.prevAndFaceIfRoom = true;
  Status s;
  while ((s = topologyOf(to)).code == Code::OutOfMemory && to.prevAndFace) to.prevAndFace = false;
  if (!s.ok()) return remember(s);
  hasTopology_ = true;
  if (shells) {
    s = findShells();
    if (!s.ok()) return remember(s);
    hasShells_ = true;
  }
  return val::null();
}

val Session::bytesToJs(const std::string& s) { return bytesToJs(s.data(), s.size()); }

val Session::bytesToJs(const char* data, size_t n) { return copyOf(reinterpret_cast<const uint8_t*>(data), n); }

val Session::remember(const Status& s) {
  if (!s.ok()) last_ = s;
  return status(s);
}

std::string errorJson(const std::string& file, const std::string& code, const std::string& message, double offset,
                      double line, double triangle) {
  Status s;
  if (!codeFromName(code.c_str(), s.code)) {
    return stltopo::errorJson(
        file, Status::error(Code::InvalidArgument, "unknown error code '" + code + "' (message: " + message + ")"));
  }
  s.message = message;
  s.offset = offset >= 0 ? uint64_t(offset) : kNoOffset;
  s.line = line > 0 ? uint64_t(line) : 0;
  s.triangle = triangle >= 0 ? uint32_t(triangle) : kInvalid;
  return stltopo::errorJson(file, s);
}

val arrayLayout() {
  val list = val::array();
  for (size_t i = 0; i < kJsArrayCount; ++i) {
    const JsArray& a = kJsArrays[i];
    val d = layoutRow(a.name, a.group, a.key, a.element, a.width, a.type, a.doc);
    d.set("when", val(a.when));
    d.set("copied", val((a.flags & kCopied) != 0));
    d.set("derived", val((a.flags & kDerived) != 0));
    list.call<void>("push", d);
  }
  return list;
}

std::string codeNameAt(int c) { return codeName(Code(c)); }
int codeCount() { return kCodeCount; }

}  // namespace stltopo::js
