// What only the full module (stltopo-full) compiles on top of the shared session: its array
// table (every row, with the doc lines scripts/gen-api-docs.mjs reads), the count list
// (_countLayout, for the same script), and FullSession: the session with shells and defects,
// the exact geometry, fromIndexed() and the STL writer, whose methods it adds to _Session.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <algorithm>
#include <new>
#include <string>
#include <vector>

#include "session.h"

using emscripten::typed_memory_view;
using emscripten::val;

// buildTopology with its once-over-the-mesh loops in chunks (src/topology.cpp): the same
// result, for the full module's loads (Session::topologyOf).
namespace stltopo::detail {
Status buildTopologyInChunks(const Mesh& mesh, Topology& out, const TopologyOptions& options);
// checkTriangles, likewise (src/triangle_checks.cpp).
Status checkTrianglesInChunks(const Mesh& mesh, const Topology* topo, TriangleChecks& out, unsigned threads);
}

namespace stltopo::js {

const JsArray kJsArrays[] = {STLTOPO_JS_ARRAYS(STLTOPO_JS_ROW, STLTOPO_JS_ROW)};
const size_t kJsArrayCount = sizeof(kJsArrays) / sizeof(kJsArrays[0]);

namespace {

class FullSession : public Session {
 public:
  using Session::Session;
  ~FullSession() override { delete writer_; }

  std::string infoJson(const std::string& file, bool shells, bool defects, double maxDefects) const override {
    return stltopo::infoJson(file, mesh_, hasTopology_ ? &topo_ : nullptr, extras(shells, defects, maxDefects));
  }
  val infoText(const std::string& file, bool shells, bool defects, double maxDefects) const override {
    return bytesToJs(
        stltopo::infoText(file, mesh_, hasTopology_ ? &topo_ : nullptr, extras(shells, defects, maxDefects)));
  }

  // The geometry's rows of the table, then the shared ones.
  val array(const std::string& n, bool copy) override {
#define STLTOPO_CASE(name, part_, ...) \
  if (n == #name) return js::array(part(static_cast<stltopo::part_*>(nullptr)).name, copy);
    STLTOPO_JS_GEOMETRY_ARRAYS(STLTOPO_CASE)
#undef STLTOPO_CASE
    return Session::array(n, copy);
  }
  val upload(const std::string& n, double size) override {
#define STLTOPO_CASE(name, part_, ...) \
  if (n == #name) return uploadTo(part(static_cast<stltopo::part_*>(nullptr)).name, size);
    STLTOPO_JS_GEOMETRY_ARRAYS(STLTOPO_CASE)
#undef STLTOPO_CASE
    return Session::upload(n, size);
  }

  // infoJson in pieces (stltopo::infoJson with a sink): an array of Uint8Array copies, each
  // of about a MiB, whose bytes joined are infoJson's: the npm CLI's report, which as one JS
  // string would stop at V8's string limit (512 MiB: a triangle soup of 1.4M triangles with
  // --shells), and which the heap then never holds whole. infoTextPieces: infoText's, likewise.
  val infoJsonPieces(const std::string& file, bool shells, bool defects, double maxDefects) const {
    return pieces(true, file, shells, defects, maxDefects);
  }
  val infoTextPieces(const std::string& file, bool shells, bool defects, double maxDefects) const {
    return pieces(false, file, shells, defects, maxDefects);
  }
  val pieces(bool json, const std::string& file, bool shells, bool defects, double maxDefects) const {
    val list = val::array();
    const ReportSink sink = [&list](const char* d, size_t n) {
      list.call<void>("push", bytesToJs(d, n));
    };
    const Topology* t = hasTopology_ ? &topo_ : nullptr;
    if (json)
      stltopo::infoJson(sink, file, mesh_, t, extras(shells, defects, maxDefects));
    else
      stltopo::infoText(sink, file, mesh_, t, extras(shells, defects, maxDefects));
    return list;
  }

  // The shell list as columns, for mesh.shells (JS builds each shell's object from them on
  // first read, with the keys and values of the shell list's JSON; web/src/mesh.js
  // buildShells); null without shells. Copies, 104 bytes a shell (more with the nesting): as
  // JSON, the shell list of the 500k-triangle soup took 5 s of its load here (each double's
  // %e and strtod round trips are long double arithmetic, 128-bit software floats in wasm)
  // and 2.5 s more to parse in JS.
  //   names: the columns of `counts`, in the JSON's order: triangles, vertices, the surface
  //          counts (STLTOPO_SURFACE_COUNTS)
  //   counts: Uint32Array, names.length + 3 a shell: those, then solid (an index, kMixedSolid
  //          or kInvalid), orientation (Orientation) and flags (1 closed, 2 manifold,
  //          4 consistent, 8 has a genus)
  //   reals: Float64Array, 4 a shell: eulerCharacteristic, genus (0 without one), area, volume
  //   box: Float32Array, 6 a shell: bbox min xyz, max xyz
  //   with the intersection pass: selfIntersects (Uint8Array), intersectsOffsets,
  //   intersectsShells, parent and depth (Uint32Arrays) of its ShellNesting
  val shellTable() const {
    if (!hasShells_) return val::null();
    const size_t n = shells_.size();
    val names = val::array();
#define STLTOPO_NAME(count, name, doc) names.call<void>("push", std::string(#name));
    names.call<void>("push", std::string("triangles"));
    names.call<void>("push", std::string("vertices"));
    STLTOPO_SURFACE_COUNTS(STLTOPO_NAME)
#undef STLTOPO_NAME
    const size_t k = names["length"].as<size_t>() + 3;
    std::vector<uint32_t> counts(n * k);
    std::vector<double> reals(n * 4);
    std::vector<float> box(n * 6);
    for (size_t i = 0; i < n; ++i) {
      const Shell& sh = shells_[i];
      uint32_t* c = counts.data() + i * k;
      *c++ = sh.triangles;
      *c++ = sh.vertices;
#define STLTOPO_COUNT(count, name, doc) *c++ = sh.name;
      STLTOPO_SURFACE_COUNTS(STLTOPO_COUNT)
#undef STLTOPO_COUNT
      *c++ = sh.solid;
      *c++ = uint32_t(sh.orientation());
      *c++ = (sh.closed() ? 1u : 0u) | (sh.manifold() ? 2u : 0u) | (sh.consistent() ? 4u : 0u) |
             (sh.hasGenus() ? 8u : 0u);
      double* r = reals.data() + i * 4;
      r[0] = double(sh.eulerCharacteristic());
      r[1] = sh.hasGenus() ? sh.genus() : 0;
      r[2] = sh.area;
      r[3] = sh.volume;
      std::copy(sh.bboxMin, sh.bboxMin + 3, box.data() + i * 6);
      std::copy(sh.bboxMax, sh.bboxMax + 3, box.data() + i * 6 + 3);
    }
    val t = val::object();
    t.set("names", names);
    t.set("counts", copyOf(counts.data(), counts.size()));
    t.set("reals", copyOf(reals.data(), reals.size()));
    t.set("box", copyOf(box.data(), box.size()));
    // As the JSON lists: the nesting only when it is of this list.
    if (hasIntersections_ && nesting_.isOf(n)) {
      t.set("selfIntersects", copyOf(nesting_.selfIntersects.data(), nesting_.selfIntersects.size()));
      t.set("intersectsOffsets", copyOf(nesting_.intersectsOffsets.data(), nesting_.intersectsOffsets.size()));
      t.set("intersectsShells", copyOf(nesting_.intersectsShells.data(), nesting_.intersectsShells.size()));
      t.set("parent", copyOf(nesting_.parent.data(), nesting_.parent.size()));
      t.set("depth", copyOf(nesting_.depth.data(), nesting_.depth.size()));
    }
    return t;
  }
  // The number of shells; -1 without shells.
  double shellCount() const { return hasShells_ ? double(shells_.size()) : -1; }

  // fromIndexed(): builds the mesh from the upload()ed positions, triangles and optional
  // attributes, colors and colorValid (an empty array = not given) and the solids of
  // setMeta() (stltopo::meshFromIndexed), then its topology as finish() does.
  val fromIndexed(bool weldNone, bool topology, double tolerance, bool prevAndFace, bool shells) {
    const size_t nt = mesh_.triangles.size() / 3;
    if ((!mesh_.attributes.empty() && mesh_.attributes.size() != nt) ||
        (!mesh_.colors.empty() && mesh_.colors.size() != 3 * nt) ||
        (!mesh_.colorValid.empty() && mesh_.colorValid.size() != nt))
      return remember(Status::error(Code::InvalidArgument,
                                    "attributes, colors and colorValid must hold 1, 3 and 1 values per triangle"));
    IndexedMesh in;
    in.positions = mesh_.positions.data();
    in.positionsLength = mesh_.positions.size();
    in.triangles = mesh_.triangles.data();
    in.trianglesLength = mesh_.triangles.size();
    in.attributes = mesh_.attributes.empty() ? nullptr : mesh_.attributes.data();
    in.colors = mesh_.colors.empty() ? nullptr : mesh_.colors.data();
    in.colorValid = mesh_.colorValid.empty() ? nullptr : mesh_.colorValid.data();
    in.solids = mesh_.solids.data();
    in.nSolids = mesh_.solids.size();
    IndexedOptions io;
    io.weld = weldNone ? Weld::None : Weld::Exact;
    Mesh m;
    Status s = meshFromIndexed(in, m, &indexedArrays_.inputVertexMap, io);
    if (!s.ok()) return remember(s);
    mesh_ = std::move(m);
    indexed_ = true;
    return buildTopology(topology, tolerance, prevAndFace, shells);
  }

  // Starts writing the mesh as STL (stltopo::StlWriter): format "binary"/"ascii", colors
  // "as-mesh"/"none"/"viscam"/"magics", name a string or null (each solid's own).
  val writeBegin(const std::string& format, const std::string& colors, val name, bool storedNormals,
                 double chunkBytes) {
    delete writer_;
    writer_ = new (std::nothrow) StlWriter(*writing_, writeOptions(format, colors, name, storedNormals, chunkBytes));
    if (!writer_) return status(Status::error(Code::OutOfMemory, "could not allocate the writer"));
    return val::null();
  }

  // For `split`: what writeBegin() writes next, shell k of a load with shells (extracted,
  // as stltopo::extractShell), or the mesh itself for k < 0. Null or the failure's status.
  val selectShell(double k) {
    delete writer_;
    writer_ = nullptr;
    writing_ = &mesh_;
    if (k < 0) return val::null();
    Status s = hasShells_ && k < double(shells_.size())
                   ? extractShell(mesh_, topo_, uint32_t(k), part_)
                   : Status::error(Code::InvalidArgument, "no such shell (load with shells)");
    if (!s.ok()) return status(s);
    writing_ = &part_;
    return val::null();
  }

  // The line `split` prints for shell k written to `file` (stltopo::splitLineJson).
  std::string splitLine(const std::string& file, double k) const {
    if (!hasShells_ || !(k >= 0 && k < double(shells_.size()))) return "null";
    return splitLineJson(file, shells_[size_t(k)], uint32_t(k));
  }

  // The exact geometry of a load with shells (stltopo::analyzeGeometry's steps): the
  // triangle checks, the intersections (work limit maxPairs), the shells' nesting and
  // `solid`; the report then has their keys. Null or the failure's status.
  val intersect(double maxPairs) {
    if (!hasShells_) return remember(Status::error(Code::InvalidArgument, "intersections need a load with shells"));
    IntersectionOptions o;
    o.threads = threads();
    if (maxPairs >= 1 && maxPairs <= 1099511627776.0) o.maxPairs = uint64_t(maxPairs);
    Status s = stltopo::detail::checkTrianglesInChunks(mesh_, &topo_, checks_, o.threads);
    if (s.ok()) s = findIntersections(mesh_, topo_, checks_, intersections_, o);
    if (s.ok()) s = findShellNesting(mesh_, topo_, shells_, intersections_, nesting_);
    if (!s.ok()) return remember(s);
    solid_ = isSolid(topo_, checks_, intersections_, shells_, nesting_);
    hasIntersections_ = true;
    return val::null();
  }

  // The next chunk of the file: a borrowed Uint8Array view (valid until the next call into
  // wasm), null at the end (the writer is freed), or a status object on error.
  val writeNext() {
    if (!writer_) return val::null();
    const uint8_t* data;
    size_t size;
    Status s = writer_->next(data, size);
    if (!s.ok() || size == 0) {
      delete writer_;
      writer_ = nullptr;
      return status(s);
    }
    return val(typed_memory_view(size, data));
  }

 protected:
  Status findShells() override { return findShellsAndDefects(mesh_, topo_, &shells_, &defects_); }
  Status topologyOf(const TopologyOptions& to) override {
    return stltopo::detail::buildTopologyInChunks(mesh_, topo_, to);
  }

 private:
  ReportExtras extras(bool shells, bool defects, double maxDefects) const {
    ReportExtras e;
    e.shells = shells && hasShells_ ? &shells_ : nullptr;
    e.defects = defects && hasShells_ ? &defects_ : nullptr;
    e.maxDefects = maxDefects >= 0 && maxDefects <= 4294967295.0 ? uint32_t(maxDefects) : 1000;
    if (hasIntersections_) {
      e.checks = &checks_;
      e.intersections = &intersections_;
      e.nesting = &nesting_;
      e.solid = solid_;
    }
    return e;
  }

  using Session::part;
  TriangleChecks& part(TriangleChecks*) { return checks_; }
  Intersections& part(Intersections*) { return intersections_; }

  Array<Shell> shells_;
  TriangleChecks checks_;
  Intersections intersections_;
  ShellNesting nesting_;
  bool solid_ = false;
  StlWriter* writer_ = nullptr;
  Mesh part_;                     // the shell selectShell() extracted
  const Mesh* writing_ = &mesh_;  // what writeBegin() writes
};

// A FullSession method as a function of the registered class (_Session is a Session whose
// objects this module makes as FullSessions).
template <auto M>
struct Full;
template <class R, class... A, R (FullSession::*M)(A...)>
struct Full<M> {
  static R call(Session& s, A... a) { return (static_cast<FullSession&>(s).*M)(a...); }
};
template <class R, class... A, R (FullSession::*M)(A...) const>
struct Full<M> {
  static R call(Session& s, A... a) { return (static_cast<const FullSession&>(s).*M)(a...); }
};

// The count list (include/stltopo/counts.h) as JS objects: [{ name, count, doc }], for
// scripts/gen-api-docs.mjs (index.d.ts's TopologyCounts).
val countLayout() {
  val list = val::array();
#define STLTOPO_COUNT_ROW(count, name, doc) \
  {                                         \
    val d = val::object();                  \
    d.set("name", val(#name));              \
    d.set("count", val(#count));            \
    d.set("doc", val(doc));                 \
    list.call<void>("push", d);             \
  }
  STLTOPO_COUNTS(STLTOPO_COUNT_ROW)
#undef STLTOPO_COUNT_ROW
  return list;
}

}  // namespace

Session* newSession(double maxTriangles, double maxBytes, double sizeHint, bool keepNormals) {
  return new FullSession(maxTriangles, maxBytes, sizeHint, keepNormals);
}

void registerModuleSession(const emscripten::class_<Session>& session) {
  session.function("infoJsonPieces", &Full<&FullSession::infoJsonPieces>::call)
      .function("infoTextPieces", &Full<&FullSession::infoTextPieces>::call)
      .function("shellTable", &Full<&FullSession::shellTable>::call)
      .function("shellCount", &Full<&FullSession::shellCount>::call)
      .function("selectShell", &Full<&FullSession::selectShell>::call)
      .function("splitLine", &Full<&FullSession::splitLine>::call)
      .function("intersect", &Full<&FullSession::intersect>::call)
      .function("fromIndexed", &Full<&FullSession::fromIndexed>::call)
      .function("writeBegin", &Full<&FullSession::writeBegin>::call)
      .function("writeNext", &Full<&FullSession::writeNext>::call);
}

}  // namespace stltopo::js

EMSCRIPTEN_BINDINGS(stltopo_full) { emscripten::function("_countLayout", &stltopo::js::countLayout); }
