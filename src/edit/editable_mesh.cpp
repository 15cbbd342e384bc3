// The public EditableMesh: it owns an Impl (impl.h) and forwards every call to it. An
// EditableMesh whose Impl is missing (moved from, or not allocated) reads as empty; the
// calls that change it allocate the Impl first and return out-of-memory when they cannot.
#include "edit/impl.h"

namespace stltopo {

using Impl = EditableMesh::Impl;

namespace {
const Impl& emptyImpl() {
  static const Impl empty;
  return empty;
}
Status noImpl() { return detail::oom(edit_detail::kEditArrays); }
// The Impl, allocated first when missing (null when it cannot be). One function, so that the
// allocation is not repeated in every forwarder.
Impl* ensure(Impl*& impl) {
  if (!impl) impl = detail::tryNew<Impl>();
  return impl;
}
}  // namespace

EditableMesh::EditableMesh() : impl_(detail::tryNew<Impl>()) {}
EditableMesh::~EditableMesh() { detail::tryDelete(impl_); }
EditableMesh::EditableMesh(EditableMesh&& o) noexcept : impl_(o.impl_) { o.impl_ = nullptr; }
EditableMesh& EditableMesh::operator=(EditableMesh&& o) noexcept {
  if (this != &o) {
    detail::tryDelete(impl_);
    impl_ = o.impl_;
    o.impl_ = nullptr;
  }
  return *this;
}

#define STLTOPO_READ (impl_ ? *impl_ : emptyImpl())
#define STLTOPO_WRITE(call, otherwise) return ensure(impl_) ? impl_->call : otherwise

Status EditableMesh::init(const Mesh& mesh, const Topology& topo) { STLTOPO_WRITE(init(mesh, topo), noImpl()); }
Status EditableMesh::init(const Mesh& mesh, const TopologyOptions& options) {
  STLTOPO_WRITE(init(mesh, options), noImpl());
}

uint32_t EditableMesh::nVertices() const { return STLTOPO_READ.nVertices(); }
uint32_t EditableMesh::nTriangles() const { return STLTOPO_READ.nTriangles(); }
uint32_t EditableMesh::nHalfedges() const { return STLTOPO_READ.nHalfedges(); }
uint32_t EditableMesh::nLiveTriangles() const { return STLTOPO_READ.nLiveTriangles_; }
uint32_t EditableMesh::nLiveVertices() const { return STLTOPO_READ.nLiveVertices_; }
uint32_t EditableMesh::nLiveHalfedges() const { return 2 * STLTOPO_READ.nLivePairs_; }
bool EditableMesh::vertexAlive(uint32_t v) const { return STLTOPO_READ.vertexAlive(v); }
bool EditableMesh::triangleAlive(uint32_t t) const { return STLTOPO_READ.triangleAlive(t); }
bool EditableMesh::halfedgeAlive(uint32_t e) const { return STLTOPO_READ.halfedgeAlive(e); }
bool EditableMesh::isBoundary(uint32_t e) const { return STLTOPO_READ.isBoundary(e); }
bool EditableMesh::triangleDegenerate(uint32_t t) const { return STLTOPO_READ.degenerate_[t] != 0; }
bool EditableMesh::vertexNonManifold(uint32_t v) const { return STLTOPO_READ.vertexNonManifold_[v] != 0; }

const Array<float>& EditableMesh::positions() const { return STLTOPO_READ.positions_; }
const Array<uint32_t>& EditableMesh::triangles() const { return STLTOPO_READ.triangles_; }
const Array<uint32_t>& EditableMesh::next() const { return STLTOPO_READ.next_; }
const Array<uint32_t>& EditableMesh::prev() const { return STLTOPO_READ.prev_; }
const Array<uint32_t>& EditableMesh::vert() const { return STLTOPO_READ.vert_; }
const Array<uint32_t>& EditableMesh::faceWords() const { return STLTOPO_READ.face_; }
const Array<uint8_t>& EditableMesh::pairKind() const { return STLTOPO_READ.pairKind_; }
const Array<uint32_t>& EditableMesh::triangleHalfedge() const { return STLTOPO_READ.triangleHalfedge_; }
const Array<uint32_t>& EditableMesh::vertexHalfedge() const { return STLTOPO_READ.vertexHalfedge_; }
const Array<uint8_t>& EditableMesh::triangleDegenerateFlags() const { return STLTOPO_READ.degenerate_; }
const Array<uint8_t>& EditableMesh::vertexNonManifoldFlags() const { return STLTOPO_READ.vertexNonManifold_; }

uint32_t EditableMesh::face(uint32_t e) { STLTOPO_WRITE(face(e), kInvalid); }
const EditLoops& EditableMesh::loops() {
  static const EditLoops none;
  STLTOPO_WRITE(loops(), none);
}
const EditStats& EditableMesh::stats() {
  static const EditStats none;
  STLTOPO_WRITE(stats(), none);
}
std::string EditableMesh::infoJson(const std::string& file) { STLTOPO_WRITE(infoJson(file), std::string()); }

Status EditableMesh::reserve(uint32_t vertices, uint32_t triangles) {
  STLTOPO_WRITE(reserve(vertices, triangles), noImpl());
}
Status EditableMesh::addVertex(float x, float y, float z, uint32_t* out) {
  STLTOPO_WRITE(addVertex(x, y, z, out), noImpl());
}
Status EditableMesh::setPosition(uint32_t v, float x, float y, float z) {
  STLTOPO_WRITE(setPosition(v, x, y, z), noImpl());
}
Status EditableMesh::removeTriangle(uint32_t t) { STLTOPO_WRITE(removeTriangle(t), noImpl()); }
Status EditableMesh::addTriangle(uint32_t a, uint32_t b, uint32_t c, uint32_t* out, bool allowNonManifold) {
  STLTOPO_WRITE(addTriangle(a, b, c, out, allowNonManifold), noImpl());
}
Status EditableMesh::flipEdge(uint32_t e) { STLTOPO_WRITE(flipEdge(e), noImpl()); }
Status EditableMesh::splitEdge(uint32_t e, double t, uint32_t* newVertex) {
  STLTOPO_WRITE(splitEdge(e, t, newVertex), noImpl());
}
Status EditableMesh::collapseEdge(uint32_t e, double t, uint32_t* remaining) {
  STLTOPO_WRITE(collapseEdge(e, t, remaining), noImpl());
}
Status EditableMesh::reverseTriangle(uint32_t t) { STLTOPO_WRITE(reverseTriangle(t), noImpl()); }
Status EditableMesh::reverseTriangles(const uint32_t* ids, uint32_t n) {
  STLTOPO_WRITE(reverseTriangles(ids, n), noImpl());
}
Status EditableMesh::reverseShell(uint32_t t) { STLTOPO_WRITE(reverseShell(t), noImpl()); }
Status EditableMesh::fillHole(uint32_t e, FillMethod method, Array<uint32_t>* out) {
  STLTOPO_WRITE(fillHole(e, method, out), noImpl());
}
Status EditableMesh::fillLoop(uint32_t h, FillMethod method, Array<uint32_t>* out) {
  STLTOPO_WRITE(fillLoop(h, method, out), noImpl());
}
Status EditableMesh::mergeVertices(const uint32_t* keep, const uint32_t* gone, uint32_t n, bool allowNonManifold) {
  STLTOPO_WRITE(mergeVertices(keep, gone, n, allowNonManifold), noImpl());
}
Status EditableMesh::mergeVertices(uint32_t keep, uint32_t gone, bool allowNonManifold) {
  STLTOPO_WRITE(mergeVertices(&keep, &gone, 1, allowNonManifold), noImpl());
}
Status EditableMesh::splitEdgeAt(uint32_t e, uint32_t v, bool allowNonManifold) {
  STLTOPO_WRITE(splitEdgeAt(e, v, allowNonManifold), noImpl());
}
Status EditableMesh::stitch(const uint32_t* keep, const uint32_t* gone, uint32_t n, const uint32_t* edges,
                            const uint32_t* vertices, uint32_t nSplits, bool allowNonManifold) {
  STLTOPO_WRITE(stitch(keep, gone, n, edges, vertices, nSplits, allowNonManifold), noImpl());
}
Status EditableMesh::splitVertex(uint32_t v, uint32_t* firstNew, uint32_t* newCount) {
  STLTOPO_WRITE(splitVertex(v, firstNew, newCount), noImpl());
}

Status EditableMesh::addAttribute(const std::string& name, Element element, ValueType type, uint32_t components,
                                  const void* values, const AttributeRules& rules, const double* defaultValue) {
  STLTOPO_WRITE(addAttribute(name, element, type, components, values, rules, defaultValue), noImpl());
}
const AttributeView* EditableMesh::attribute(const std::string& name) const { return STLTOPO_READ.attribute(name); }
bool EditableMesh::removeAttribute(const std::string& name) { return impl_ && impl_->removeAttribute(name); }
std::vector<std::string> EditableMesh::attributeNames() const { return STLTOPO_READ.attributeNames(); }

Status EditableMesh::toMesh(Mesh& out, Topology* topo, CompactMaps* maps, bool triangleShell, bool figures) const {
  return STLTOPO_READ.toMesh(out, topo, maps, triangleShell, figures);
}
Status EditableMesh::compact(CompactMaps* maps) { STLTOPO_WRITE(compact(maps), noImpl()); }
Status EditableMesh::validate() const { return STLTOPO_READ.validate(); }

#undef STLTOPO_READ
#undef STLTOPO_WRITE

}  // namespace stltopo
