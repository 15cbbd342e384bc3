// Embind bindings for the wasm build. Raw, underscore-prefixed API only: the
// friendly JavaScript API lives in web/src (core.js). Nothing here throws; every
// failure comes back as a status object ({code, message, offset?, line?,
// triangle?, element?}) or null for success.
//
// The arrays that cross to JS are listed once, in STLTOPO_JS_ARRAYS below (those of the
// EditableMesh in its sibling table, STLTOPO_JS_EDIT_ARRAYS in edit_arrays.h); the JS layer
// (web/src/mesh.js, web/src/edit.js), index.d.ts and docs/JS-API.md follow those tables.
//
// Typed arrays leave wasm memory in one of two ways (see array()):
//   copy = true : a view is taken and slice()d in the same expression, so the JS
//                 array owns its bytes and never detaches;
//   copy = false: a borrowed view into wasm memory. It detaches when memory grows
//                 (emscripten#6747) and dangles after the session is deleted.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "js_values.h"
#include "stltopo.h"

using emscripten::typed_memory_view;
using emscripten::val;

namespace stltopo {
// What fromIndexed() returns besides the mesh (the third part of the array table).
struct Indexed {
  Array<uint32_t> inputVertexMap;
};
}  // namespace stltopo

namespace js = stltopo::js;

namespace {

using stltopo::Array;
using stltopo::Code;
using stltopo::Status;

// The topology's counts that are not array lengths: meta() hands them to JS as `counts`, and
// setCounts() takes them back for validate() on uploaded arrays. The counts of
// stltopo/counts.h, and the weld's.
#define STLTOPO_TOPOLOGY_COUNTS(X) \
  STLTOPO_COUNTS(X) STLTOPO_OTHER_COUNTS(X) X(nWeldedVertices, weldedVertices, "")

// The result arrays that cross to JS, one line each:
//   X(name, part, group, key, element, width, when, flags, doc)
//   name     the member of stltopo::Mesh or stltopo::Topology (`part`), and the name
//            session.array()/upload() take;
//   group    the mesh property that holds it in JS ("" = the mesh itself), key its name there;
//   element  what its entries are indexed by, width entries per element;
//   when     when it exists: "mesh" always, "normals" with { normals: true }, "colors" when the
//            file has colours, "topology" unless { topology: false }, "indexed" for meshes of
//            fromIndexed(); otherwise JS sets null;
//   flags    kCopied: copied out even for { view: true } meshes (small, so holes never dangle);
//            kDerived: not copied out of wasm for copies, rebuilt in JS on first read
//            (web/src/mesh.js deriveArray) and not built by the core for them (prevAndFace);
//   doc      one line for index.d.ts and docs/JS-API.md (scripts/gen-api-docs.mjs writes them).
// A new array is one line here, then `node scripts/gen-api-docs.mjs`.
// The exact geometry's arrays (mesh.intersections), in the full module only: the core module
// never computes them, and its table (a smaller download) leaves them out.
#if STLTOPO_WASM_CORE
#define STLTOPO_JS_GEOMETRY_ARRAYS(X)
#else
#define STLTOPO_JS_GEOMETRY_ARRAYS(X)                                                                              \
  X(zeroArea, TriangleChecks, "intersections", "zeroAreaTriangles", "zero-area triangle", 1, "intersections", kCopied, \
    "The zero-area triangles (three distinct, exactly collinear corners), ascending.")                               \
  X(duplicateOffsets, TriangleChecks, "intersections", "duplicateOffsets", "duplicate group+1", 1, "intersections",   \
    kCopied, "Duplicate group g is duplicateTriangles[offsets[g] .. offsets[g+1]).")                                  \
  X(duplicateTriangles, TriangleChecks, "intersections", "duplicateTriangles", "group entry", 1, "intersections",     \
    kCopied, "The members of every duplicate group, ascending; groups by lowest member.")                            \
  X(duplicateOrientation, TriangleChecks, "intersections", "duplicateOrientation", "duplicate group", 1,              \
    "intersections", kCopied, "Per group: 0 same, 1 opposite, 2 mixed (DuplicateOrientation).")                     \
  X(pairs, Intersections, "intersections", "pairs", "pair", 2, "intersections", kCopied,                              \
    "Intersecting pair i is triangles [2i] < [2i+1]; ordered by (i, j).")                                           \
  X(kinds, Intersections, "intersections", "kinds", "pair", 1, "intersections", kCopied,                              \
    "Per pair: 0 crossing, 1 touching, 2 coplanar (IntersectionKind).")                                              \
  X(points, Intersections, "intersections", "points", "pair", 3, "intersections", kCopied,                            \
    "Per pair: x,y,z of one point of the intersection (float64, for framing a camera).")                            \
  X(triangleIntersects, Intersections, "intersections", "triangleIntersects", "triangle", 1, "intersections",         \
    kCopied, "Per triangle: 1 when it is in an intersecting pair.")
#endif
#define STLTOPO_JS_ARRAYS(X)                                                                                        \
  X(positions, Mesh, "", "positions", "vertex", 3, "mesh", 0, "x,y,z of vertex v at 3v..3v+2.")                     \
  X(triangles, Mesh, "", "triangles", "triangle", 3, "mesh", 0, "Vertex ids of corner c of triangle t at 3t+c.")      \
  X(attributes, Mesh, "", "attributes", "triangle", 1, "mesh", 0, "Binary attribute word per triangle (0 for ASCII).") \
  X(colors, Mesh, "", "colors", "triangle", 3, "colors", 0, "sRGB bytes per triangle when colorConvention !== 'none'.") \
  X(colorValid, Mesh, "", "colorValid", "triangle", 1, "colors", 0, "1 per triangle that has a colour.")             \
  X(normals, Mesh, "", "normals", "triangle", 3, "normals", 0, "Stored facet normals, with { normals: true }.")      \
  X(next, Topology, "halfedges", "next", "halfedge", 1, "topology", 0, "Next half-edge around the same face.")        \
  X(prev, Topology, "halfedges", "prev", "halfedge", 1, "topology", kDerived, "Inverse of next.")                    \
  X(vert, Topology, "halfedges", "vert", "halfedge", 1, "topology", kDerived, "Origin vertex (org).")                 \
  X(face, Topology, "halfedges", "face", "halfedge", 1, "topology", kDerived,                                         \
    "Left face: the triangle id, or nTriangles + h for boundary loop h.")                                            \
  X(triangleHalfedge, Topology, "", "triangleHalfedge", "triangle", 1, "topology", 0,                                 \
    "Per triangle: half-edge of side corner0->corner1, kInvalid if degenerate.")                                     \
  X(vertexHalfedge, Topology, "", "vertexHalfedge", "vertex", 1, "topology", 0,                                       \
    "Per vertex: an outgoing half-edge, kInvalid if unused.")                                                        \
  X(loopHalfedge, Topology, "", "loopHalfedge", "loop", 1, "topology", 0, "Per boundary loop: its lowest-id half-edge.") \
  X(vertexWeld, Topology, "", "vertexWeld", "vertex", 1, "topology", 0,                                               \
    "Per vertex: the representative vertex the topology uses (identity for exact weld).")                            \
  X(loopOffsets, Topology, "loops", "offsets", "loop+1", 1, "topology", kCopied,                                      \
    "Loop h is halfedges[offsets[h] .. offsets[h+1]).")                                                              \
  X(loopHalfedges, Topology, "loops", "halfedges", "loop entry", 1, "topology", kCopied,                              \
    "The half-edges of every loop in next order, starting at loopHalfedge[h].")                                      \
  X(loopIsSeam, Topology, "loops", "isSeam", "loop", 1, "topology", kCopied,                                          \
    "1 when the loop contains a cut (inconsistent or non-manifold) side.")                                           \
  X(loopPerimeter, Topology, "loops", "perimeter", "loop", 1, "topology", kCopied, "Sum of the loop's edge lengths.")  \
  X(pairKind, Topology, "problems", "pairKind", "pair", 1, "topology", 0,                                             \
    "Per pair k = e >> 1: 0 interior, 1 boundary, 2 inconsistent, 3 non-manifold (EdgeKind).")                       \
  X(triangleDegenerate, Topology, "problems", "triangleDegenerate", "triangle", 1, "topology", 0,                     \
    "1 when two corners of the triangle weld together.")                                                             \
  X(vertexNonManifold, Topology, "problems", "vertexNonManifold", "vertex", 1, "topology", 0,                         \
    "1 when the vertex's outgoing half-edges form more than one vnext cycle.")                                       \
  X(triangleShell, Topology, "", "triangleShell", "triangle", 1, "shells", 0,                                         \
    "Per triangle: its shell (numbered by lowest triangle id), kInvalid if degenerate.")      \
  X(nonManifoldEdgeVertices, Defects, "defects", "nonManifoldEdgeVertices", "non-manifold edge", 2, "shells", kCopied, \
    "Non-manifold edge i joins vertices [2i] < [2i+1]; ordered by (smaller, larger) vertex.")                       \
  X(nonManifoldEdgeOffsets, Defects, "defects", "nonManifoldEdgeOffsets", "non-manifold edge+1", 1, "shells", kCopied, \
    "Non-manifold edge i's triangles are nonManifoldEdgeTriangles[offsets[i] .. offsets[i+1]).")                                  \
  X(nonManifoldEdgeTriangles, Defects, "defects", "nonManifoldEdgeTriangles", "edge entry", 1, "shells", kCopied,     \
    "Every triangle with a side on each non-manifold edge, ascending.")                                              \
  X(inconsistentEdgeVertices, Defects, "defects", "inconsistentEdgeVertices", "inconsistent edge", 2, "shells",       \
    kCopied, "Inconsistent edge i joins vertices [2i] < [2i+1]; ordered by (smaller, larger) vertex.")              \
  X(inconsistentEdgeTriangles, Defects, "defects", "inconsistentEdgeTriangles", "inconsistent edge", 2, "shells",     \
    kCopied, "The two triangles of inconsistent edge i, [2i] < [2i+1].")                                             \
  X(nonManifoldVertices, Defects, "defects", "nonManifoldVertices", "non-manifold vertex", 1, "shells", kCopied,       \
    "The non-manifold vertices, ascending.")                                                                         \
  X(nonManifoldVertexCycles, Defects, "defects", "nonManifoldVertexCycles", "non-manifold vertex", 1, "shells",       \
    kCopied, "The number of vnext cycles of each (>= 2).")                                                           \
  X(degenerateTriangles, Defects, "defects", "degenerateTriangles", "degenerate triangle", 1, "shells", kCopied,       \
    "The degenerate triangles, ascending.")                                                                          \
  X(degenerateCorners, Defects, "defects", "degenerateCorners", "degenerate triangle", 1, "shells", kCopied,          \
    "Corners that weld: bit 0 corners 0,1; bit 1 corners 1,2; bit 2 corners 2,0 (7: all three).")                    \
  X(loopShell, Defects, "defects", "loopShell", "loop", 1, "shells", kCopied, "Per boundary loop h: its shell.")                                          \
  STLTOPO_JS_GEOMETRY_ARRAYS(X)                                                                                       \
  X(inputVertexMap, Indexed, "", "inputVertexMap", "input vertex", 1, "indexed", kCopied,                             \
    "fromIndexed(): per vertex of the input, its vertex in the mesh (kInvalid when no triangle uses it).")

constexpr int kCopied = 1;
constexpr int kDerived = 2;

struct JsArray {
  const char *name, *group, *key, *element;
  int width;
  const char* when;
  int flags;
  const char *type, *doc;
};
// The core module (the smaller download) leaves out the doc lines: only
// scripts/gen-api-docs.mjs reads them, from the full module.
#if STLTOPO_WASM_CORE
#define STLTOPO_DOC(doc) ""
#else
#define STLTOPO_DOC(doc) doc
#endif
#define STLTOPO_ROW(name, part, group, key, element, width, when, flags, doc) \
  {#name, group, key, element, width, when, flags, js::JsType<decltype(stltopo::part::name)>::js, STLTOPO_DOC(doc)},
constexpr JsArray kJsArrays[] = {STLTOPO_JS_ARRAYS(STLTOPO_ROW)};
#undef STLTOPO_ROW

// The table as JS objects: [{ name, group, key, element, width, when, copied, derived, type, doc }].
val arrayLayout() {
  val list = val::array();
  for (const JsArray& a : kJsArrays) {
    val d = js::layoutRow(a.name, a.group, a.key, a.element, a.width, a.type, a.doc);
    d.set("when", val(a.when));
    d.set("copied", val((a.flags & kCopied) != 0));
    d.set("derived", val((a.flags & kDerived) != 0));
    list.call<void>("push", d);
  }
  return list;
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
#if !STLTOPO_WASM_CORE
    delete writer_;
#endif
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
    if (!reader_) return js::status(Status::error(Code::OutOfMemory, "could not allocate the reader"));
    if (n > inputCap_) return js::status(Status::error(Code::InvalidArgument, "feed() larger than buffer()"));
    return remember(reader_->feed(input_, n));
  }

  // Completes the read, frees the reader and builds the topology when asked
  // (prevAndFace false: without the prev and face arrays, see TopologyOptions), and with
  // `shells` also triangleShell, the shell list and the defect lists.
  val finish(bool topology, double tolerance, bool prevAndFace, bool shells) {
    if (!reader_) return js::status(Status::error(Code::OutOfMemory, "could not allocate the reader"));
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

  double bytesRead() const { return reader_ ? double(reader_->bytesRead()) : bytesRead_; }

  // Scalars and small lists of the result.
  val meta() const {
    val o = val::object();
    o.set("format", val(stltopo::formatName(mesh_.format)));
    o.set("colorConvention", val(stltopo::colorConventionName(mesh_.colorConvention)));
    o.set("nVertices", val(mesh_.nVertices()));
    o.set("nTriangles", val(mesh_.nTriangles()));
    o.set("hasTopology", val(hasTopology_));
    o.set("hasShells", val(hasShells_));
    o.set("hasIntersections", val(hasIntersections_));
    o.set("hasNormals", val(!mesh_.normals.empty() || (options_.keepNormals && mesh_.nTriangles() == 0)));
    o.set("indexed", val(indexed_));
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
    for (const Status& w : mesh_.warnings) warnings.call<void>("push", js::status(w));
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

  // The JSON report, byte for byte what the native CLI prints (with --shells, --defects
  // and --max-defects when `shells`, `defects`, `maxDefects`; those need a load with shells).
  std::string infoJson(const std::string& file, bool shells, bool defects, double maxDefects) const {
#if STLTOPO_WASM_CORE
    (void)shells, (void)defects, (void)maxDefects;  // no load of this module has shells
    return stltopo::infoJson(file, mesh_, hasTopology_ ? &topo_ : nullptr);
#else
    return stltopo::infoJson(file, mesh_, hasTopology_ ? &topo_ : nullptr, extras(shells, defects, maxDefects));
#endif
  }

  // The native CLI's text report (tools/cli.cpp), byte for byte: a Uint8Array, since
  // solid names may hold bytes that are not UTF-8.
  val infoText(const std::string& file, bool shells, bool defects, double maxDefects) const {
#if STLTOPO_WASM_CORE
    (void)shells, (void)defects, (void)maxDefects;
    return bytesToJs(stltopo::infoText(file, mesh_, hasTopology_ ? &topo_ : nullptr));
#else
    return bytesToJs(stltopo::infoText(file, mesh_, hasTopology_ ? &topo_ : nullptr, extras(shells, defects, maxDefects)));
#endif
  }

#if !STLTOPO_WASM_CORE
  // The shell list as JSON ("[{...},...]"), for mesh.shells; "null" without shells.
  std::string shellListJson() const {
    if (!hasShells_) return "null";
    std::string j = stltopo::shellListJson(shells_, hasIntersections_ ? &nesting_ : nullptr);
    return j.substr(j.find('['));
  }
#endif

  // The message of the last failed feed()/finish() as bytes (the native CLI
  // prints messages raw; a JS string would replace invalid UTF-8).
  val messageBytes() const { return bytesToJs(last_.message); }

  // A named result array (a name of STLTOPO_JS_ARRAYS); null for an unknown name.
  val array(const std::string& name, bool copy) {
    val out = val::null();
    withArray(name, [&](auto& a) { out = js::array(a, copy); });
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

  // For validate() on uploaded arrays: the counts that are not array lengths, as meta()
  // gives them in `counts` (every STLTOPO_TOPOLOGY_COUNTS name, and the tolerance).
  void setCounts(const val& c) {
    topo_.nTriangles = mesh_.nTriangles();
    topo_.nVertices = mesh_.nVertices();
#define STLTOPO_COUNT(count, name, doc) topo_.count = c[#count].as<uint32_t>();
    STLTOPO_TOPOLOGY_COUNTS(STLTOPO_COUNT)
#undef STLTOPO_COUNT
    topo_.tolerance = c["tolerance"].as<double>();
    hasTopology_ = true;
  }

  // The scalars of a mesh whose arrays were upload()ed: its colour convention ("none",
  // "viscam", "magics") and solids ([{ name, firstTriangle, triangleCount }]).
  void setMeta(const std::string& colorConvention, val solids) {
    mesh_.colorConvention = js::colorConvention(colorConvention);
    mesh_.solids.clear();
    const int n = solids.isArray() ? solids["length"].as<int>() : 0;
    for (int i = 0; i < n; ++i) {
      val so = solids[i];
      stltopo::Solid s;
      s.name = so["name"].isString() ? so["name"].as<std::string>() : std::string();
      double first = so["firstTriangle"].as<double>(), count = so["triangleCount"].as<double>();
      s.firstTriangle = first >= 0 && first <= 4294967295.0 ? uint32_t(first) : stltopo::kInvalid;
      s.triangleCount = count >= 0 && count <= 4294967295.0 ? uint32_t(count) : stltopo::kInvalid;
      mesh_.solids.push_back(std::move(s));
    }
  }

#if !STLTOPO_WASM_CORE
  // fromIndexed(): builds the mesh from the upload()ed positions, triangles and optional
  // attributes, colors and colorValid (an empty array = not given) and the solids of
  // setMeta() (stltopo::meshFromIndexed), then its topology as finish() does.
  val fromIndexed(bool weldNone, bool topology, double tolerance, bool prevAndFace, bool shells) {
    const size_t nt = mesh_.triangles.size() / 3;
    if ((!mesh_.attributes.empty() && mesh_.attributes.size() != nt) || (!mesh_.colors.empty() && mesh_.colors.size() != 3 * nt) ||
        (!mesh_.colorValid.empty() && mesh_.colorValid.size() != nt))
      return remember(Status::error(Code::InvalidArgument, "attributes, colors and colorValid must hold 1, 3 and 1 values per triangle"));
    stltopo::IndexedMesh in;
    in.positions = mesh_.positions.data();
    in.positionsLength = mesh_.positions.size();
    in.triangles = mesh_.triangles.data();
    in.trianglesLength = mesh_.triangles.size();
    in.attributes = mesh_.attributes.empty() ? nullptr : mesh_.attributes.data();
    in.colors = mesh_.colors.empty() ? nullptr : mesh_.colors.data();
    in.colorValid = mesh_.colorValid.empty() ? nullptr : mesh_.colorValid.data();
    in.solids = mesh_.solids.data();
    in.nSolids = mesh_.solids.size();
    stltopo::IndexedOptions io;
    io.weld = weldNone ? stltopo::Weld::None : stltopo::Weld::Exact;
    stltopo::Mesh m;
    Status s = stltopo::meshFromIndexed(in, m, &indexedArrays_.inputVertexMap, io);
    if (!s.ok()) return remember(s);
    mesh_ = std::move(m);
    indexed_ = true;
    return buildTopology(topology, tolerance, prevAndFace, shells);
  }

  // Starts writing the mesh as STL (stltopo::StlWriter): format "binary"/"ascii", colors
  // "as-mesh"/"none"/"viscam"/"magics", name a string or null (each solid's own).
  val writeBegin(const std::string& format, const std::string& colors, val name, bool storedNormals, double chunkBytes) {
    delete writer_;
    writer_ = new (std::nothrow) stltopo::StlWriter(*writing_, js::writeOptions(format, colors, name, storedNormals, chunkBytes));
    if (!writer_) return js::status(Status::error(Code::OutOfMemory, "could not allocate the writer"));
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
                   ? stltopo::extractShell(mesh_, topo_, uint32_t(k), part_)
                   : Status::error(Code::InvalidArgument, "no such shell (load with shells)");
    if (!s.ok()) return js::status(s);
    writing_ = &part_;
    return val::null();
  }

  // The line `split` prints for shell k written to `file` (stltopo::splitLineJson).
  std::string splitLine(const std::string& file, double k) const {
    if (!hasShells_ || !(k >= 0 && k < double(shells_.size()))) return "null";
    return stltopo::splitLineJson(file, shells_[size_t(k)], uint32_t(k));
  }

  // The exact geometry of a load with shells (stltopo::analyzeGeometry's steps): the
  // triangle checks, the intersections (work limit maxPairs), the shells' nesting and
  // `solid`; the report then has their keys. Null or the failure's status.
  val intersect(double maxPairs) {
    if (!hasShells_) return remember(Status::error(Code::InvalidArgument, "intersections need a load with shells"));
    stltopo::IntersectionOptions o;
    if (maxPairs >= 1 && maxPairs <= 1099511627776.0) o.maxPairs = uint64_t(maxPairs);
    Status s = stltopo::checkTriangles(mesh_, &topo_, checks_);
    if (s.ok()) s = stltopo::findIntersections(mesh_, topo_, checks_, intersections_, o);
    if (s.ok()) s = stltopo::findShellNesting(mesh_, topo_, shells_, intersections_, nesting_);
    if (!s.ok()) return remember(s);
    solid_ = stltopo::isSolid(topo_, checks_, intersections_, shells_, nesting_);
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
      return js::status(s);
    }
    return val(typed_memory_view(size, data));
  }
#endif  // !STLTOPO_WASM_CORE

  val validate() const {
    if (!hasTopology_) return js::status(Status::error(Code::InvalidArgument, "the mesh has no topology (loaded with topology: false)"));
    return js::status(stltopo::validate(mesh_, topo_));
  }

 private:
#if !STLTOPO_WASM_CORE
  stltopo::ReportExtras extras(bool shells, bool defects, double maxDefects) const {
    stltopo::ReportExtras e;
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
#endif
  // The topology of mesh_ when asked (prevAndFace false: without prev and face, see
  // TopologyOptions), and with `shells` also triangleShell, the shell list and the defect
  // lists; null or the failure's status.
  val buildTopology(bool topology, double tolerance, bool prevAndFace, bool shells) {
    if (!topology) return val::null();
    stltopo::TopologyOptions to;
    to.tolerance = tolerance > 0 ? tolerance : 0;
    to.prevAndFace = prevAndFace;
    to.triangleShell = shells;
    Status s = stltopo::buildTopology(mesh_, topo_, to);
    if (!s.ok()) return remember(s);
    hasTopology_ = true;
    if (shells) {
#if STLTOPO_WASM_CORE
      return remember(Status::error(Code::InvalidArgument, "shells and defects are in the full module (stltopo-full)"));
#else
      s = stltopo::findShellsAndDefects(mesh_, topo_, &shells_, &defects_);
      if (!s.ok()) return remember(s);
      hasShells_ = true;
#endif
    }
    return val::null();
  }
  static val bytesToJs(const std::string& s) {
    return val(typed_memory_view(s.size(), reinterpret_cast<const uint8_t*>(s.data()))).call<val>("slice");
  }
  val remember(const Status& s) {
    if (!s.ok()) last_ = s;
    return js::status(s);
  }

  stltopo::Mesh& part(stltopo::Mesh*) { return mesh_; }
  stltopo::Topology& part(stltopo::Topology*) { return topo_; }
  stltopo::Defects& part(stltopo::Defects*) { return defects_; }
  stltopo::Indexed& part(stltopo::Indexed*) { return indexedArrays_; }
  stltopo::TriangleChecks& part(stltopo::TriangleChecks*) { return checks_; }
  stltopo::Intersections& part(stltopo::Intersections*) { return intersections_; }

  template <class F>
  void withArray(const std::string& n, F&& f) {
#define STLTOPO_CASE(name, part_, ...) \
  if (n == #name) return f(part(static_cast<stltopo::part_*>(nullptr)).name);
    STLTOPO_JS_ARRAYS(STLTOPO_CASE)
#undef STLTOPO_CASE
  }

  stltopo::ReadOptions options_;
  stltopo::Reader* reader_ = nullptr;
  uint8_t* input_ = nullptr;
  size_t inputCap_ = 0;
  double bytesRead_ = 0;
  stltopo::Mesh mesh_;
  stltopo::Topology topo_;
  bool hasTopology_ = false;
  stltopo::Array<stltopo::Shell> shells_;
  stltopo::Defects defects_;
  bool hasShells_ = false;
  bool indexed_ = false;
  stltopo::Indexed indexedArrays_;
  stltopo::TriangleChecks checks_;
  stltopo::Intersections intersections_;
  stltopo::ShellNesting nesting_;
  bool solid_ = false;
  bool hasIntersections_ = false;
#if !STLTOPO_WASM_CORE
  stltopo::StlWriter* writer_ = nullptr;
  stltopo::Mesh part_;                  // the shell selectShell() extracted
  const stltopo::Mesh* writing_ = &mesh_;  // what writeBegin() writes
#endif
  Status last_;
};

// errorJson for a status made in JS (e.g. the npm CLI's "cannot open"). A code
// name that the core does not know gives an invalid-argument report that says so.
std::string errorJson(const std::string& file, const std::string& code, const std::string& message, double offset,
                      double line, double triangle) {
  Status s;
  if (!stltopo::codeFromName(code.c_str(), s.code)) {
    return stltopo::errorJson(file, Status::error(Code::InvalidArgument, "unknown error code '" + code + "' (message: " + message + ")"));
  }
  s.message = message;
  s.offset = offset >= 0 ? uint64_t(offset) : stltopo::kNoOffset;
  s.line = line > 0 ? uint64_t(line) : 0;
  s.triangle = triangle >= 0 ? uint32_t(triangle) : stltopo::kInvalid;
  return stltopo::errorJson(file, s);
}

// The stable name of code c (0 <= c < codeCount()), for the tests.
std::string codeNameAt(int c) { return stltopo::codeName(Code(c)); }
int codeCount() { return stltopo::kCodeCount; }


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
      .function("setMeta", &Session::setMeta)
#if !STLTOPO_WASM_CORE
      .function("shellListJson", &Session::shellListJson)
      .function("selectShell", &Session::selectShell)
      .function("splitLine", &Session::splitLine)
      .function("intersect", &Session::intersect)
      .function("fromIndexed", &Session::fromIndexed)
      .function("writeBegin", &Session::writeBegin)
      .function("writeNext", &Session::writeNext)
#endif
      .function("validate", &Session::validate);
  function("_arrayLayout", &arrayLayout);
  function("_errorJson", &errorJson);
  function("_codeName", &codeNameAt);
  function("_codeCount", &codeCount);
}
