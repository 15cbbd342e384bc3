// The Embind session of a load (`_Session`), what both wasm modules share: bindings.cpp
// registers it, session.cpp holds its adapters, and each module adds its own part from one
// file that only that module compiles (bindings/CMakeLists.txt): core.cpp (nothing more) or
// full.cpp (shells, fromIndexed(), writing, the exact geometry). Nothing here throws; every
// failure comes back as a status object ({code, message, offset?, line?, triangle?,
// element?}) or null for success.
//
// Typed arrays leave wasm memory in one of two ways (js::array()):
//   copy = true : a view is taken and slice()d in the same expression, so the JS
//                 array owns its bytes and never detaches;
//   copy = false: a borrowed view into wasm memory. It detaches when memory grows
//                 (emscripten#6747) and dangles after the session is deleted.
#pragma once

#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <cstdint>
#include <string>

#include "arrays.h"
#include "js_values.h"
#include "stltopo/stltopo.h"

namespace stltopo::js {

// One load: a streaming reader, then the mesh and (optionally) its topology.
// Also used the other way round by validate() on JS-owned copies: upload()
// allocates the arrays, JS fills them, validate() checks them.
class Session {
 public:
  Session(double maxTriangles, double maxBytes, double sizeHint, bool keepNormals);
  virtual ~Session();

  // A writable view of n bytes of the input buffer; null when it cannot be
  // allocated. JS must fill it before its next call into wasm.
  emscripten::val buffer(size_t n);
  // Feeds the first n bytes of the input buffer.
  emscripten::val feed(size_t n);
  // Completes the read, frees the reader and builds the topology when asked
  // (prevAndFace false: without the prev and face arrays, see TopologyOptions), and with
  // `shells` also triangleShell, the shell list and the defect lists.
  emscripten::val finish(bool topology, double tolerance, bool prevAndFace, bool shells);
  double bytesRead() const;
  // Scalars and small lists of the result.
  emscripten::val meta() const;
  // The JSON report, byte for byte what the native CLI prints (with --shells, --defects
  // and --max-defects when `shells`, `defects`, `maxDefects`; those need a load with shells,
  // which only the full module makes).
  virtual std::string infoJson(const std::string& file, bool shells, bool defects, double maxDefects) const;
  // The native CLI's text report (tools/cli.cpp), byte for byte: a Uint8Array, since
  // solid names may hold bytes that are not UTF-8.
  virtual emscripten::val infoText(const std::string& file, bool shells, bool defects, double maxDefects) const;
  // The message of the last failed feed()/finish() as bytes (the native CLI
  // prints messages raw; a JS string would replace invalid UTF-8).
  emscripten::val messageBytes() const;
  // A named result array (a name of the module's array table); null for an unknown name.
  virtual emscripten::val array(const std::string& name, bool copy);
  // Allocates a named array of n elements and returns a writable view of it;
  // null on allocation failure or unknown name.
  virtual emscripten::val upload(const std::string& name, double n);
  // For validate() on uploaded arrays: the counts that are not array lengths, as meta()
  // gives them in `counts` (every STLTOPO_TOPOLOGY_COUNTS name, and the tolerance).
  void setCounts(const emscripten::val& c);
  // The scalars of a mesh whose arrays were upload()ed: its colour convention ("none",
  // "viscam", "magics") and solids ([{ name, firstTriangle, triangleCount }]).
  void setMeta(const std::string& colorConvention, emscripten::val solids);
  emscripten::val validate() const;

 protected:
  // The shell list and the defect lists of a topology built with triangleShell; the core
  // module has none (an invalid-argument status that says where they are).
  virtual Status findShells();
  // stltopo::buildTopology of mesh_ into topo_. The full module builds it with the loops that
  // run once over the mesh in chunks, which its first load runs in V8's optimized code
  // (src/topology.cpp, detail::buildTopologyInChunks); the core keeps the smaller one-call code.
  virtual Status topologyOf(const TopologyOptions& to);
  // The topology of mesh_ when asked (prevAndFace false: without prev and face, see
  // TopologyOptions), and with `shells` also triangleShell and findShells(); null or the
  // failure's status.
  emscripten::val buildTopology(bool topology, double tolerance, bool prevAndFace, bool shells);
  static emscripten::val bytesToJs(const std::string& s);
  static emscripten::val bytesToJs(const char* data, size_t n);
  // A JS copy (a typed array of its own) of the n elements at p.
  template <class T>
  static emscripten::val copyOf(const T* p, size_t n) {
    return emscripten::val(emscripten::typed_memory_view(n, p)).call<emscripten::val>("slice");
  }
  // upload()'s adapter: `a` resized to n elements, as a writable view; null when it fails.
  template <class T>
  static emscripten::val uploadTo(Array<T>& a, double n) {
    if (n >= 0 && a.resize(size_t(n))) return emscripten::val(emscripten::typed_memory_view(a.size(), a.data()));
    return emscripten::val::null();
  }
  emscripten::val remember(const Status& s);

  // The parts of the array table's rows.
  Mesh& part(Mesh*) { return mesh_; }
  Topology& part(Topology*) { return topo_; }
  Defects& part(Defects*) { return defects_; }
  Indexed& part(Indexed*) { return indexedArrays_; }

  ReadOptions options_;
  Reader* reader_ = nullptr;
  uint8_t* input_ = nullptr;
  size_t inputCap_ = 0;
  double bytesRead_ = 0;
  Mesh mesh_;
  Topology topo_;
  bool hasTopology_ = false;
  Defects defects_;
  bool hasShells_ = false;
  bool hasIntersections_ = false;
  bool indexed_ = false;
  Indexed indexedArrays_;
  Status last_;
};

// The threads of the loads that follow (`_setThreads(n)`): the `threads` of the read, the
// topology and the exact geometry. 1 in the single-threaded modules, whatever was set (the
// core compiles its threaded paths out there); in the threaded ones at most the worker pool
// plus the calling thread (web/src/instance*.js set it before each load).
void setThreads(double n);
unsigned threads();
// The module's session (a Session, or full.cpp's FullSession), which `new _Session()` makes.
Session* newSession(double maxTriangles, double maxBytes, double sizeHint, bool keepNormals);
// The module's own methods of _Session (bindings.cpp registers the shared ones first).
void registerModuleSession(const emscripten::class_<Session>& session);

// errorJson for a status made in JS (e.g. the npm CLI's "cannot open"). A code name that the
// core does not know gives an invalid-argument report that says so.
std::string errorJson(const std::string& file, const std::string& code, const std::string& message, double offset,
                      double line, double triangle);
// The table as JS objects: [{ name, group, key, element, width, when, copied, derived, type, doc }].
emscripten::val arrayLayout();
// The stable name of code c (0 <= c < codeCount()), for the tests.
std::string codeNameAt(int c);
int codeCount();

}  // namespace stltopo::js
