// Embind bindings of the EditableMesh (raw, underscore-prefixed; the JS class is in
// web/src/edit.js). As in session.cpp nothing throws: a failed edit returns a status
// object {code, message, triangle?, element?} (js_values.h); a successful one returns null
// or its result.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "edit_arrays.h"
#include "js_values.h"
#include "stltopo/edit.h"
#include "stltopo/stltopo.h"

using emscripten::typed_memory_view;
using emscripten::val;

namespace js = stltopo::js;

namespace {

using stltopo::Array;
using stltopo::Code;
using stltopo::EditableMesh;
using stltopo::Status;

uint32_t u32(double x) { return x >= 0 && x <= 4294967295.0 ? uint32_t(x) : stltopo::kInvalid; }

// A JS function (a, b, t) -> array of `components` numbers, or null/false to refuse.
stltopo::RuleCallback jsRule(val fn) {
  if (fn.isNull() || fn.isUndefined()) return nullptr;
  return [fn](const double* a, const double* b, double t, double* out, uint32_t n) {
    val r =
        fn(val(typed_memory_view(n, a)).call<val>("slice"), val(typed_memory_view(n, b)).call<val>("slice"), val(t));
    if (r.isNull() || r.isUndefined() || (r.isFalse())) return false;
    if (r["length"].as<uint32_t>() < n) return false;
    for (uint32_t k = 0; k < n; ++k) out[k] = r[k].as<double>();
    return true;
  };
}

// The figures of the last plan made in this module, for applyRepair: JS hands back only a
// plan's fingerprint and options. A plan's figures are those of the meshes with its
// fingerprints (toMesh() equals a fresh build of the compacted mesh), so apply takes the
// input's figures and the intersection pass's figures of the result from here (RepairPlan::
// beforeKnown, afterKnown) when the fingerprint and the pass's options match, instead of
// running the pass twice more. Anything else is computed as without it.
struct PlannedFigures {
  bool valid = false;
  uint64_t fingerprint = 0, fingerprintAfter = 0;
  bool intersections = false;
  uint64_t maxPairs = 0;
  stltopo::RepairFigures before, after;
};
PlannedFigures lastPlanned;
// The last plan's own result (RepairPlan::result: the repaired mesh and the change log),
// for applyRepair, which takes it when its mesh and options are still the plan's: one at
// most in the module, let go when it is taken or as the next plan starts. Module-wide, as
// planRepair(mesh) of the JS API plans on a temporary EditableMesh and applies on another.
std::shared_ptr<stltopo::RepairResult> lastPlannedResult;

class EditSession {
 public:
  // Staging: JS fills the mesh arrays of the mesh to edit (STLTOPO_JS_EDIT_UPLOADS), then
  // init(). A writable view of n elements, or null (unknown name, out of memory).
  val upload(const std::string& name, double n) {
    val out = val::null();
    auto up = [&](auto& a) {
      if (a.resize(n >= 0 ? size_t(n) : 0)) out = val(typed_memory_view(a.size(), a.data()));
    };
#define STLTOPO_UPLOAD(member) \
  if (name == #member) up(staged_.member);
    STLTOPO_JS_EDIT_UPLOADS(STLTOPO_UPLOAD)
#undef STLTOPO_UPLOAD
    return out;
  }
  void addSolid(const std::string& name, double first, double count) {
    stltopo::Solid s;
    s.name = name;
    s.firstTriangle = u32(first);
    s.triangleCount = u32(count);
    staged_.solids.push_back(std::move(s));
  }
  void setFormat(const std::string& format, const std::string& colors) {
    staged_.format = format == "binary"  ? stltopo::Format::Binary
                     : format == "ascii" ? stltopo::Format::Ascii
                                         : stltopo::Format::Unknown;
    staged_.colorConvention = js::colorConvention(colors);
  }
  // The editor of the staged mesh. On failure the staged arrays stay (a deferred init,
  // below, may be tried again).
  val init(double tolerance) {
    Status s = checkStaged();
    if (s.ok()) {
      stltopo::TopologyOptions o;
      o.tolerance = tolerance > 0 ? tolerance : 0;
      s = em_.init(staged_, o);
    }
    if (s.ok()) {
      staged_ = stltopo::Mesh{};
      deferred_ = false;
    }
    return js::status(s);
  }
  // A deferred init (EditableMesh.from() without a tolerance): checks the staged arrays as
  // init() does and keeps them; JS calls init(0) before the first call that needs the
  // editor. planRepairStaged(opts, true) and applyRepairStaged() work on the staged mesh
  // itself, so that from() + planRepair() + applyRepair() never builds the editor of the
  // input (applyRepair takes the plan's result).
  val defer() {
    Status s = checkStaged();
    deferred_ = s.ok();
    return js::status(s);
  }
  bool deferred() const { return deferred_; }
  // planRepair of the staged mesh itself, instead of init() and planRepair(): the plan of
  // the EditableMesh init(0) would make (the same plan: tests/js/repair.test.mjs compares
  // both ways, and tests/test_repair.cpp the C++ calls under them), without building that
  // EditableMesh first. `keep`: the staged arrays stay (a deferred session); else the
  // session stays empty.
  val planRepairStaged(val opts, bool keep) {
    Status s = checkStaged();
    stltopo::RepairOptions o;
    if (s.ok()) s = repairOptions(opts, o);
    stltopo::RepairPlan p;
    if (s.ok()) {
      lastPlannedResult.reset();  // the last plan's result goes first: one at a time
      s = stltopo::planRepair(staged_, o, p);
    }
    if (!keep) staged_ = stltopo::Mesh{};
    return planned(s, p, o);
  }
  // applyRepair of a deferred session: stltopo::applyRepair(staged mesh, plan, em, log),
  // which takes the plan's result without an editor of the input when it can, and builds
  // one and runs the steps otherwise. When it carried out nothing (a refused plan, out of
  // memory before any step), the session stays deferred, as it was.
  val applyRepairStaged(val opts, const std::string& fingerprint) {
    if (!deferred_) return js::status(Status::error(Code::InvalidArgument, "the editable mesh is not deferred"));
    stltopo::RepairPlan p;
    Status s = repairPlanOf(opts, fingerprint, p);
    if (!s.ok()) return js::status(s);
    stltopo::RepairLog log;
    EditableMesh out;
    s = stltopo::applyRepair(staged_, p, out, log);
    if (p.resultTaken()) lastPlannedResult.reset();
    if (!s.ok() && log.steps.empty() && !p.resultTaken()) return js::status(s);
    em_ = std::move(out);
    staged_ = stltopo::Mesh{};
    deferred_ = false;
    return logged(s, std::move(log));
  }

  // Edits. Results: null (done), a number (new id), a Uint32Array (new triangles) or a status.
  val reserve(double vertices, double triangles) { return js::status(em_.reserve(u32(vertices), u32(triangles))); }
  val setPosition(double v, double x, double y, double z) {
    return js::status(em_.setPosition(u32(v), float(x), float(y), float(z)));
  }
  val removeTriangle(double t) { return js::status(em_.removeTriangle(u32(t))); }
  val addVertex(double x, double y, double z) {
    uint32_t v = 0;
    Status s = em_.addVertex(float(x), float(y), float(z), &v);
    return s.ok() ? val(v) : js::status(s);
  }
  val addTriangle(double a, double b, double c, bool nonManifold) {
    uint32_t t = 0;
    Status s = em_.addTriangle(u32(a), u32(b), u32(c), &t, nonManifold);
    return s.ok() ? val(t) : js::status(s);
  }
  val flipEdge(double e) { return js::status(em_.flipEdge(u32(e))); }
  val splitEdge(double e, double t) {
    uint32_t v = 0;
    Status s = em_.splitEdge(u32(e), t, &v);
    return s.ok() ? val(v) : js::status(s);
  }
  val collapseEdge(double e, double t) {
    uint32_t v = 0;
    Status s = em_.collapseEdge(u32(e), t, &v);
    return s.ok() ? val(v) : js::status(s);
  }
  // Vertex joins (stitch): id lists as JS arrays (web/src/edit.js checks them).
  static std::vector<uint32_t> ids(const val& list) {
    std::vector<uint32_t> out;
    const uint32_t n = list["length"].as<uint32_t>();
    out.reserve(n);
    for (uint32_t i = 0; i < n; ++i) out.push_back(u32(list[i].as<double>()));
    return out;
  }
  val mergeVertices(val keep, val gone, bool nonManifold) {
    std::vector<uint32_t> k = ids(keep), g = ids(gone);
    if (k.size() != g.size())
      return js::status(Status::error(Code::InvalidArgument, "keep and gone need the same length"));
    return js::status(em_.mergeVertices(k.data(), g.data(), uint32_t(k.size()), nonManifold));
  }
  val splitEdgeAt(double e, double v, bool nonManifold) {
    return js::status(em_.splitEdgeAt(u32(e), u32(v), nonManifold));
  }
  val stitch(val keep, val gone, val edges, val vertices, bool nonManifold) {
    std::vector<uint32_t> k = ids(keep), g = ids(gone), e = ids(edges), v = ids(vertices);
    if (k.size() != g.size() || e.size() != v.size())
      return js::status(Status::error(Code::InvalidArgument, "keep/gone and edges/vertices need the same lengths"));
    return js::status(
        em_.stitch(k.data(), g.data(), uint32_t(k.size()), e.data(), v.data(), uint32_t(e.size()), nonManifold));
  }
  val splitVertex(double v) {
    uint32_t first = 0, count = 0;
    Status s = em_.splitVertex(u32(v), &first, &count);
    if (!s.ok()) return js::status(s);
    val o = val::object();
    o.set("first", val(first));
    o.set("count", val(count));
    return o;
  }
  val reverseTriangle(double t) { return js::status(em_.reverseTriangle(u32(t))); }
  val reverseShell(double t) { return js::status(em_.reverseShell(u32(t))); }
  val fill(double id, bool byLoop, bool ear) {
    Array<uint32_t> out;
    stltopo::FillMethod m = ear ? stltopo::FillMethod::Ear : stltopo::FillMethod::Fan;
    Status s = byLoop ? em_.fillLoop(u32(id), m, &out) : em_.fillHole(u32(id), m, &out);
    return s.ok() ? js::array(out, true) : js::status(s);
  }
  val compact() {
    stltopo::CompactMaps maps;
    Status s = em_.compact(&maps);
    if (!s.ok()) return js::status(s);
    val o = val::object();
    o.set("vertices", js::array(maps.vertices, true));
    o.set("triangles", js::array(maps.triangles, true));
    o.set("halfedges", js::array(maps.halfedges, true));
    return o;
  }

  // Reading.
  val counts() const {
    val o = val::object();
    o.set("nVertices", val(em_.nVertices()));
    o.set("nTriangles", val(em_.nTriangles()));
    o.set("nHalfedges", val(em_.nHalfedges()));
    o.set("nLiveVertices", val(em_.nLiveVertices()));
    o.set("nLiveTriangles", val(em_.nLiveTriangles()));
    o.set("nLiveHalfedges", val(em_.nLiveHalfedges()));
    return o;
  }
  std::string infoJson(const std::string& file) { return em_.infoJson(file); }
  // A named array of STLTOPO_JS_EDIT_ARRAYS (a copy, or a borrowed view); null for an
  // unknown name.
  val array(const std::string& n, bool copy) {
#define STLTOPO_EDIT_ARRAY(name, source, ...) \
  if (n == #name) return js::array(this->source, copy);
    STLTOPO_JS_EDIT_ARRAYS(STLTOPO_EDIT_ARRAY)
#undef STLTOPO_EDIT_ARRAY
    return val::null();
  }
  // The face ids of the half-edges, as a Mesh numbers them: the triangle id, or nTriangles +
  // h for a half-edge of boundary loop h (EditableMesh::face); kInvalid for dead slots.
  const Array<uint32_t>& faceIds() {
    const uint32_t nh = em_.nHalfedges();
    if (!faceIds_.resize(nh)) {
      faceIds_ = Array<uint32_t>{};
      return faceIds_;
    }
    for (uint32_t e = 0; e < nh; ++e) faceIds_[e] = em_.halfedgeAlive(e) ? em_.face(e) : stltopo::kInvalid;
    return faceIds_;
  }
  val validate() const { return js::status(em_.validate()); }

  // The STL file of the compacted mesh (toMesh + writeStl), whole: a Uint8Array or a status.
  // format: "binary" | "ascii"; colors: "as-mesh" | "none" | "viscam" | "magics"; normals:
  // "stored" | "computed".
  val toStl(const std::string& format, const std::string& colors, const std::string& normals, val name) const {
    stltopo::Mesh m;
    Status s = em_.toMesh(m);
    if (!s.ok()) return js::status(s);
    const stltopo::WriteOptions o = js::writeOptions(format, colors, name, normals != "computed");
    Array<uint8_t> out;
    bool grown = true;
    auto sink = [](void* user, const uint8_t* data, size_t n) {
      auto* st = static_cast<std::pair<Array<uint8_t>*, bool*>*>(user);
      size_t at = st->first->size();
      if (!st->first->resize(at + n)) return *st->second = false;
      std::memcpy(st->first->data() + at, data, n);
      return true;
    };
    std::pair<Array<uint8_t>*, bool*> user{&out, &grown};
    s = stltopo::writeStl(m, sink, &user, o);
    if (!grown) return js::status(Status::error(Code::OutOfMemory, "could not allocate the STL bytes"));
    return s.ok() ? js::array(out, true) : js::status(s);
  }

  // Attributes. element: 0 vertex, 1 triangle, 2 edge; type: ValueType index; rules:
  // 0 keepFirst, 1 average, 2 fail, 3 custom (with mergeFn / splitFn).
  val addAttribute(const std::string& name, int element, int type, double components, int merge, int split, val mergeFn,
                   val splitFn) {
    if (element < 0 || element > 2 || type < 0 || type > 7 || merge < 0 || merge > 3 || split < 0 || split > 3)
      return js::status(Status::error(Code::InvalidArgument, "unknown attribute element, type or rule"));
    stltopo::AttributeRules r;
    r.merge = stltopo::Rule(merge);
    r.split = stltopo::Rule(split);
    r.mergeFn = jsRule(mergeFn);
    r.splitFn = jsRule(splitFn);
    return js::status(
        em_.addAttribute(name, stltopo::Element(element), stltopo::ValueType(type), u32(components), nullptr, r));
  }
  // The attribute's values: a view (copy = false, to fill right away) or a copy; null when
  // there is no such attribute.
  val attribute(const std::string& name, bool copy) const {
    const stltopo::AttributeView* a = em_.attribute(name);
    if (!a) return val::null();
    size_t n = a->count * a->components;
    val v = val::null();
    switch (a->type) {
      case stltopo::ValueType::U8: v = val(typed_memory_view(n, static_cast<uint8_t*>(a->data))); break;
      case stltopo::ValueType::I8: v = val(typed_memory_view(n, static_cast<int8_t*>(a->data))); break;
      case stltopo::ValueType::U16: v = val(typed_memory_view(n, static_cast<uint16_t*>(a->data))); break;
      case stltopo::ValueType::I16: v = val(typed_memory_view(n, static_cast<int16_t*>(a->data))); break;
      case stltopo::ValueType::U32: v = val(typed_memory_view(n, static_cast<uint32_t*>(a->data))); break;
      case stltopo::ValueType::I32: v = val(typed_memory_view(n, static_cast<int32_t*>(a->data))); break;
      case stltopo::ValueType::F32: v = val(typed_memory_view(n, static_cast<float*>(a->data))); break;
      case stltopo::ValueType::F64: v = val(typed_memory_view(n, static_cast<double*>(a->data))); break;
    }
    return copy ? v.call<val>("slice") : v;
  }
  val attributeInfo(const std::string& name) const {
    const stltopo::AttributeView* a = em_.attribute(name);
    if (!a) return val::null();
    val o = val::object();
    o.set("element", val(int(a->element)));
    o.set("type", val(int(a->type)));
    o.set("components", val(a->components));
    return o;
  }
  val attributeNames() const {
    val out = val::array();
    for (const std::string& n : em_.attributeNames()) out.call<void>("push", val(n));
    return out;
  }

  // Repair (include/stltopo/repair.h). opts, as web/src/edit.js normalizes them: { steps:
  // [names], removeOppositeDuplicates, stitchTolerance, maxHoleEdges, maxHoleArea,
  // maxHolePerimeter, fillRefine, fillFair, minShellTriangles, minShellVolume,
  // intersections, maxPairs, exclude: [{ step, item }] }. The plan and the change log come
  // back as the CLI's JSON; the logs stay here for undo.
  val planRepair(val opts) {
    stltopo::RepairOptions o;
    Status s = repairOptions(opts, o);
    if (!s.ok()) return js::status(s);
    stltopo::RepairPlan p;
    lastPlannedResult.reset();  // the last plan's result goes first: one at a time
    s = stltopo::planRepair(em_, o, p);
    return planned(s, p, o);
  }
  val applyRepair(val opts, const std::string& fingerprint) {
    stltopo::RepairPlan p;
    Status s = repairPlanOf(opts, fingerprint, p);
    if (!s.ok()) return js::status(s);
    stltopo::RepairLog log;
    s = stltopo::applyRepair(em_, p, log);
    if (p.resultTaken()) lastPlannedResult.reset();
    return logged(s, std::move(log));
  }
  // Undoes the last repair step (of the last repair that has one): its name, null when
  // there is none, or a status.
  val undoRepairStep() {
    while (!logs_.empty() && logs_.back().steps.empty()) logs_.pop_back();
    if (logs_.empty()) return val::null();
    std::string name = stltopo::repairStepName(logs_.back().steps.back().kind);
    Status s = stltopo::undoRepairStep(em_, logs_.back());
    if (!s.ok()) return js::status(s);
    if (logs_.back().steps.empty()) logs_.pop_back();
    return val(name);
  }
  double undoableRepairSteps() const {
    size_t n = 0;
    for (const stltopo::RepairLog& l : logs_) n += l.steps.size();
    return double(n);
  }

  EditableMesh& em() { return em_; }

 private:
  stltopo::Mesh staged_;
  EditableMesh em_;
  Array<uint32_t> faceIds_;               // faceIds()
  std::vector<stltopo::RepairLog> logs_;  // applyRepair's, for undo
  bool deferred_ = false;                 // defer(): the staged arrays wait for init(0)

  // The staged arrays as init() and planRepairStaged() take them: whole elements, every
  // corner a vertex.
  Status checkStaged() const {
    const uint32_t nv = staged_.nVertices();
    if (staged_.positions.size() % 3 != 0 || staged_.triangles.size() % 3 != 0)
      return Status::error(Code::InvalidArgument, "positions and triangles need 3 numbers per element");
    for (size_t i = 0; i < staged_.triangles.size(); ++i)
      if (staged_.triangles[i] >= nv) {
        Status s =
            Status::error(Code::InvalidArgument, "triangle " + std::to_string(i / 3) + " uses a vertex out of range");
        s.triangle = uint32_t(i / 3);
        return s;
      }
    return Status{};
  }
  // The plan JS hands back (its options and fingerprint), with what this module knows of it:
  // the figures and the result of the last plan made here.
  static Status repairPlanOf(val opts, const std::string& fingerprint, stltopo::RepairPlan& p) {
    Status s = repairOptions(opts, p.options);
    if (!s.ok()) return s;
    char* end = nullptr;
    p.fingerprint = std::strtoull(fingerprint.c_str(), &end, 16);
    if (fingerprint.size() != 16 || *end)
      return Status::error(Code::InvalidArgument, "the plan has no fingerprint");
    if (lastPlanned.valid && lastPlanned.fingerprint == p.fingerprint &&
        lastPlanned.intersections == p.options.intersections && lastPlanned.maxPairs == p.options.maxPairs) {
      p.beforeKnown = p.afterKnown = true;
      p.before = lastPlanned.before;
      p.after = lastPlanned.after;
      p.fingerprintAfter = lastPlanned.fingerprintAfter;
    }
    p.result = lastPlannedResult;
    return Status{};
  }
  // What applyRepair (status s, log) gives JS: the log's JSON or the error; the log is kept
  // for undo when it has a step.
  val logged(const Status& s, stltopo::RepairLog log) {
    std::string json = stltopo::repairLogJson(log);
    if (!log.steps.empty()) logs_.push_back(std::move(log));
    while (!logs_.empty() && logs_.back().steps.empty()) logs_.pop_back();
    return s.ok() ? val(json) : js::status(s);
  }
  // What planRepair (status s, plan p, options o) gives JS: the plan's JSON, its figures
  // and result kept for applyRepair (module-wide), or the error.
  static val planned(const Status& s, const stltopo::RepairPlan& p, const stltopo::RepairOptions& o) {
    if (!s.ok()) return js::status(s);
    if (p.beforeKnown && p.afterKnown)
      lastPlanned = PlannedFigures{true, p.fingerprint, p.fingerprintAfter, o.intersections, o.maxPairs, p.before, p.after};
    lastPlannedResult = p.result;
    return val(stltopo::repairPlanJson(p));
  }

  static Status repairOptions(val v, stltopo::RepairOptions& o) {
    auto bad = [](const std::string& m) { return Status::error(Code::InvalidArgument, "repair options: " + m); };
    o.steps = 0;
    val steps = v["steps"];
    const uint32_t n = steps["length"].as<uint32_t>();
    for (uint32_t i = 0; i < n; ++i) {
      stltopo::RepairStepKind k;
      std::string name = steps[i].as<std::string>();
      if (!stltopo::repairStepFromName(name, k)) return bad("unknown step " + name);
      o.steps |= stltopo::repairStepBit(k);
    }
    o.removeOppositeDuplicates = v["removeOppositeDuplicates"].as<bool>();
    o.stitchTolerance = v["stitchTolerance"].as<double>();
    o.maxHoleEdges = u32(v["maxHoleEdges"].as<double>());
    o.maxHoleArea = v["maxHoleArea"].as<double>();
    o.maxHolePerimeter = v["maxHolePerimeter"].as<double>();
    o.fillRefine = v["fillRefine"].as<bool>();
    o.fillFair = v["fillFair"].as<bool>();
    o.minShellTriangles = u32(v["minShellTriangles"].as<double>());
    o.minShellVolume = v["minShellVolume"].as<double>();
    o.intersections = v["intersections"].as<bool>();
    o.maxPairs = uint64_t(v["maxPairs"].as<double>());
    val ex = v["exclude"];
    const uint32_t m = ex["length"].as<uint32_t>();
    for (uint32_t i = 0; i < m; ++i) {
      stltopo::RepairStepKind k;
      std::string name = ex[i]["step"].as<std::string>();
      if (!stltopo::repairStepFromName(name, k)) return bad("unknown step " + name);
      o.exclude.push_back({k, u32(ex[i]["item"].as<double>())});
    }
    return Status{};
  }
};

// The table as JS objects, as _arrayLayout gives the mesh's: [{ name, group, key, element,
// width, type, doc }].
struct EditArray {
  const char *name, *group, *key, *element;
  int width;
  const char *type, *doc;
};
#define STLTOPO_EDIT_ROW(name, source, group, key, element, width, doc)                                \
  {#name,   group, key,                                                                                \
   element, width, js::JsType<std::remove_cvref_t<decltype(std::declval<EditSession&>().source)>>::js, \
   doc},
constexpr EditArray kEditArrays[] = {STLTOPO_JS_EDIT_ARRAYS(STLTOPO_EDIT_ROW)};
#undef STLTOPO_EDIT_ROW

val editArrayLayout() {
  val list = val::array();
  for (const EditArray& a : kEditArrays) {
    list.call<void>("push", js::layoutRow(a.name, a.group, a.key, a.element, a.width, a.type, a.doc));
  }
  return list;
}

}  // namespace

EMSCRIPTEN_BINDINGS(stltopo_edit) {
  using emscripten::class_;
  class_<EditSession>("_EditableMesh")
      .constructor<>()
      .function("upload", &EditSession::upload)
      .function("addSolid", &EditSession::addSolid)
      .function("setFormat", &EditSession::setFormat)
      .function("init", &EditSession::init)
      .function("defer", &EditSession::defer)
      .function("deferred", &EditSession::deferred)
      .function("applyRepairStaged", &EditSession::applyRepairStaged)
      .function("reserve", &EditSession::reserve)
      .function("setPosition", &EditSession::setPosition)
      .function("removeTriangle", &EditSession::removeTriangle)
      .function("addVertex", &EditSession::addVertex)
      .function("addTriangle", &EditSession::addTriangle)
      .function("flipEdge", &EditSession::flipEdge)
      .function("splitEdge", &EditSession::splitEdge)
      .function("collapseEdge", &EditSession::collapseEdge)
      .function("mergeVertices", &EditSession::mergeVertices)
      .function("splitEdgeAt", &EditSession::splitEdgeAt)
      .function("stitch", &EditSession::stitch)
      .function("splitVertex", &EditSession::splitVertex)
      .function("reverseTriangle", &EditSession::reverseTriangle)
      .function("reverseShell", &EditSession::reverseShell)
      .function("fill", &EditSession::fill)
      .function("compact", &EditSession::compact)
      .function("counts", &EditSession::counts)
      .function("infoJson", &EditSession::infoJson)
      .function("array", &EditSession::array)
      .function("validate", &EditSession::validate)
      .function("toStl", &EditSession::toStl)
      .function("addAttribute", &EditSession::addAttribute)
      .function("attribute", &EditSession::attribute)
      .function("attributeInfo", &EditSession::attributeInfo)
      .function("attributeNames", &EditSession::attributeNames)
      .function("planRepair", &EditSession::planRepair)
      .function("planRepairStaged", &EditSession::planRepairStaged)
      .function("applyRepair", &EditSession::applyRepair)
      .function("undoRepairStep", &EditSession::undoRepairStep)
      .function("undoableRepairSteps", &EditSession::undoableRepairSteps);
  emscripten::function("_editArrayLayout", &editArrayLayout);
}
