// stltopo editing: an EditableMesh holds a mesh and its half-edge topology in the same
// flat arrays as Mesh + Topology, and changes them by local operations (remove, add, flip,
// split, collapse, reverse, fill) that the caller asks for. The core still never repairs
// on its own.
//
// Ids. Vertices, triangles and half-edges are slots in growable arrays; an edit never
// moves a live element to another slot, except as noted below. Removed elements leave
// dead slots (holes in the numbering) until compact() renumbers everything densely, in
// the same order, and returns the old -> new maps.
//   - Vertex ids: stable until compact(). A vertex dies only in collapseEdge() and
//     mergeVertices(); a vertex
//     that no triangle uses stays alive (addTriangle can use it again) but compact() and
//     toMesh() drop it, as a file could not hold it.
//   - Triangle ids: stable until compact(). New triangles take new ids at the end; the
//     operations that replace triangles (flip, split, collapse, reverse) keep the ids of
//     the triangles they change and say which new ones they add.
//   - Half-edge ids: twin(e) = e ^ 1 as in Topology; pair k = e >> 1 holds the two
//     half-edges of one triangle side and its partner (another triangle's side, or a
//     boundary half-edge). A triangle side keeps its half-edge id as long as its edge keeps
//     the same partner for it. When an edge with three or more sides gains or loses a side,
//     its sides are paired again by the rule buildTopology uses (first unpaired with first
//     unpaired, opposite directions, in side order 3t + c), and the half-edges of the sides
//     whose partner changed move to other slots.
//   - Face ids, as in Topology: face(e) is the triangle id, or nTriangles() + h for a
//     half-edge of boundary loop h (nTriangles() counts the slots, dead ones included, so
//     the two never meet). Loop h is numbered as buildTopology would number it on the
//     compacted mesh: loops in order of their earliest triangle side, each listed in next
//     order from the twin of that side; the numbering is rebuilt (O(n)) when loops are read
//     after an edit changed the boundary (loops(), face(e), stats()). The stored face words
//     (faceWords()) keep a triangle id, or kLoopFaceBit | h for a boundary half-edge, so
//     that adding a triangle renumbers nothing; a changed boundary half-edge holds
//     kStaleLoopFace there until the loops are numbered again.
//
// After every edit, the topology is the one buildTopology gives for the current
// triangles: toMesh()/compact() produce a Mesh and Topology whose arrays equal
// buildTopology(mesh) array by array, and the counts (stats()) equal that build's.
//
// Costs. Every edit is O(local size): the triangles around the vertices it touches (plus
// the hole for fillHole, the shell for reverseShell). stats() and loops() are O(n) when
// read after an edit, O(1) otherwise; toMesh() and compact() are O(n).
//
// Refused edits. An edit that cannot be done returns Code::EditRefused (or
// InvalidArgument for a dead or out-of-range id, OutOfMemory when memory runs out) and
// changes nothing: every array and every attribute stays as it was.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "stltopo/array.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"

namespace stltopo {

inline constexpr uint32_t kLoopFaceBit = 0x80000000u;                   // stored face word of a boundary half-edge
inline constexpr uint32_t kStaleLoopFace = kLoopFaceBit | 0x7FFFFFFEu;  // loop not numbered yet

// ---------------------------------------------------------------------------
// Attributes: named arrays of numbers per vertex, per triangle or per edge (pair k =
// e >> 1; an edge cut into several pairs has a value per pair), each value `components`
// numbers of one type. Each attribute has two rules:
//   merge: two elements become one. collapseEdge merges its two vertices (weights 1 - t and
//     t) and, on each side of the edge, the two edges that become one (weights 1/2);
//     flipEdge gives each of its two new triangles the merge of the two it replaces (the
//     triangle's own value first).
//   split: one value is made from two for a new element between them, or one element is
//     cut in parts. splitEdge makes its vertex from the edge's two (weights 1 - t, t), cuts
//     the edge in two and each triangle on it in two (each part gets split(x, x, t)).
// Rules: KeepFirst (the first value: the triangle's own, the edge's origin vertex, the
// remaining vertex of a collapse), Average (weighted in double, rounded to nearest and
// clamped for integer types), Fail (the edit is refused unless the values are equal) and
// Custom (a callback; returning false refuses the edit). Elements made from nothing (added
// and filled triangles, new vertices, edges inside them) get the attribute's default.
enum class Element : uint8_t { Vertex, Triangle, Edge };
enum class ValueType : uint8_t { U8, I8, U16, I16, U32, I32, F32, F64 };
enum class Rule : uint8_t { KeepFirst, Average, Fail, Custom };
size_t valueTypeSize(ValueType t);

// Custom rule: writes `components` numbers to `out` from a and b (b's weight is t). false
// refuses the edit.
using RuleCallback = std::function<bool(const double* a, const double* b, double t, double* out, uint32_t components)>;

struct AttributeRules {
  Rule merge = Rule::KeepFirst;
  Rule split = Rule::KeepFirst;
  RuleCallback mergeFn, splitFn;  // for Rule::Custom
};

// What attribute() returns. `data` holds count * components values of `type`, indexed by
// element slot (dead slots hold leftovers). Valid until the next edit or addAttribute.
struct AttributeView {
  Element element = Element::Vertex;
  ValueType type = ValueType::F32;
  uint32_t components = 0;
  void* data = nullptr;
  size_t count = 0;
};

// The names of the attributes an EditableMesh creates from a Mesh.
inline constexpr const char* kAttrWord = "attribute";         // Triangle, U16 x1: the binary attribute word
inline constexpr const char* kAttrColor = "color";            // Triangle, U8 x3, if the mesh has colours
inline constexpr const char* kAttrColorValid = "colorValid";  // Triangle, U8 x1, with "color"
inline constexpr const char* kAttrNormal = "normal";          // Triangle, F32 x3, if the mesh kept normals

enum class FillMethod : uint8_t { Fan, Ear };

// Whole-mesh figures: the fields infoJson prints, as a fresh build of the compacted mesh
// gives them.
// Besides `triangles` and `vertices` (the vertices that triangles use), one member per count of
// stltopo/counts.h (edges, boundaryEdges, ..., shells, degenerate, usedVertices), and the
// figures TopologyCounts derives from them.
struct EditStats {
  uint32_t triangles = 0, vertices = 0;
#define STLTOPO_STATS_MEMBER(count, name, doc) uint32_t name = 0;
  STLTOPO_COUNTS(STLTOPO_STATS_MEMBER)
  STLTOPO_OTHER_COUNTS(STLTOPO_STATS_MEMBER)
#undef STLTOPO_STATS_MEMBER
  int64_t eulerCharacteristic = 0;
  bool watertight = false, manifold = true;
};

// Boundary loops in the current loop numbering, laid out as in Topology.
struct EditLoops {
  Array<uint32_t> loopHalfedge, loopOffsets, loopHalfedges;
  Array<uint8_t> loopIsSeam;
  Array<double> loopPerimeter;
  uint32_t nLoops() const { return uint32_t(loopHalfedge.size()); }
};

// Old -> new ids of compact() and toMesh(); kInvalid for dropped elements.
struct CompactMaps {
  Array<uint32_t> vertices, triangles, halfedges;
};

class EditableMesh {
 public:
  EditableMesh();
  ~EditableMesh();
  EditableMesh(const EditableMesh&) = delete;
  EditableMesh& operator=(const EditableMesh&) = delete;
  EditableMesh(EditableMesh&& o) noexcept;
  EditableMesh& operator=(EditableMesh&& o) noexcept;

  // Takes `mesh` and its topology (built by buildTopology with prevAndFace = true, from this
  // mesh). Half-edge and loop ids are the topology's. With a tolerance weld the triangles
  // use the representatives (vertexWeld); the other vertices stay, unused. The mesh's
  // attribute words, colours and kept normals become triangle attributes. O(n). Errors:
  // InvalidArgument (topology without prev/face, or of another mesh), OutOfMemory; `*this`
  // is then empty.
  Status init(const Mesh& mesh, const Topology& topo);
  // Builds the topology (prevAndFace forced on) and takes both.
  Status init(const Mesh& mesh, const TopologyOptions& options = {});

  // Slot counts: the lengths of the arrays, dead slots included.
  uint32_t nVertices() const;
  uint32_t nTriangles() const;
  uint32_t nHalfedges() const;
  uint32_t nLiveTriangles() const;
  uint32_t nLiveVertices() const;
  uint32_t nLiveHalfedges() const;

  bool vertexAlive(uint32_t v) const;
  bool triangleAlive(uint32_t t) const;
  bool halfedgeAlive(uint32_t e) const;
  bool isBoundary(uint32_t e) const;
  bool triangleDegenerate(uint32_t t) const;
  bool vertexNonManifold(uint32_t v) const;

  // The arrays, laid out as Mesh and Topology (dead triangles: kInvalid corners; dead
  // half-edges: kInvalid in every word; dead vertices: positions left as they were).
  const Array<float>& positions() const;
  const Array<uint32_t>& triangles() const;
  const Array<uint32_t>& next() const;
  const Array<uint32_t>& prev() const;
  const Array<uint32_t>& vert() const;
  // The stored face words: a triangle id, or kLoopFaceBit | h for a boundary half-edge of
  // loop h (kStaleLoopFace until loops() or face(e) renumbers the loops). face(e) gives the
  // face id.
  const Array<uint32_t>& faceWords() const;
  const Array<uint8_t>& pairKind() const;
  const Array<uint32_t>& triangleHalfedge() const;
  const Array<uint32_t>& vertexHalfedge() const;
  const Array<uint8_t>& triangleDegenerateFlags() const;
  const Array<uint8_t>& vertexNonManifoldFlags() const;

  // The face id of half-edge e, as Topology numbers faces: its triangle, or nTriangles() + h
  // for boundary loop h, with the loop numbering brought up to date (O(n) after an edit,
  // else O(1)). kInvalid for a dead half-edge, or when memory ran out numbering the loops.
  uint32_t face(uint32_t e);
  const EditLoops& loops();
  const EditStats& stats();
  // infoJson of the compacted mesh (O(n)); "" when memory runs out.
  std::string infoJson(const std::string& file);

  // Room for `vertices` more vertices and `triangles` more triangles (and their half-edges
  // and attributes) without reallocating: the arrays otherwise grow by doubling, which
  // makes the one edit that crosses a capacity O(n). OutOfMemory changes nothing.
  Status reserve(uint32_t vertices, uint32_t triangles);

  // --- Edits ---------------------------------------------------------------------------
  // A new vertex (unused until a triangle uses it). Vertex attributes get their default.
  Status addVertex(float x, float y, float z, uint32_t* out = nullptr);
  // Moves vertex v to (x, y, z): geometry only. The triangles, the topology, the ids and
  // every attribute stay as they are (a kept triangle normal is not recomputed, so it may
  // no longer match); the perimeters of the boundary loops through v follow the move.
  // Refused (InvalidArgument) for a dead or out-of-range vertex and for a non-finite
  // coordinate. O(corners at v + the loops through v).
  Status setPosition(uint32_t v, float x, float y, float z);
  // Removes triangle t. Its sides that had a partner become boundary sides: the hole grows,
  // appears, splits or joins another as the fan rule says. Its vertices stay.
  Status removeTriangle(uint32_t t);
  // Adds triangle (a, b, c), returning its id. Each side pairs with an opposite boundary
  // side on the same edge. Refused when two corners are the same vertex, and, unless
  // allowNonManifold, when a side would land on an edge that has two sides already
  // (non-manifold) or on a boundary side running the same way (inconsistent).
  Status addTriangle(uint32_t a, uint32_t b, uint32_t c, uint32_t* out = nullptr, bool allowNonManifold = false);
  // Flips the interior edge of e: triangles (a, b, c) = face(e) and (b, a, d) = face(twin e)
  // become (c, a, d) and (d, b, c), keeping their ids (the first is face(e)'s); the new
  // edge c-d takes the old edge's attribute values. Refused on a boundary, inconsistent or
  // non-manifold edge, when c == d or when the edge c-d exists already.
  Status flipEdge(uint32_t e);
  // Splits the edge of e = a -> b at (1 - t) a + t b, 0 < t < 1: every triangle side on
  // that edge (one on a boundary, two inside, more on a non-manifold edge) is cut, and
  // each of its triangles (a, b, c) becomes (a, m, c), keeping its id, and (m, b, c), a new
  // id. Returns m: 1 vertex, 2 + (sides) edges and (sides) triangles more.
  Status splitEdge(uint32_t e, double t = 0.5, uint32_t* newVertex = nullptr);
  // Collapses the edge of e = a -> b: b is merged into a, which moves to (1 - t) a + t b and
  // is returned; the triangles on the edge are removed (their ids die) and the others at b
  // now use a. Refused unless the edge is an interior or boundary edge whose two vertices
  // are manifold and have only interior and boundary edges; when the link condition fails
  // (a and b have a common neighbour other than the edge's opposite vertices, a triangle
  // a-c-d and b-c-d both exist, or both are boundary vertices joined by an interior edge);
  // when the result would lose a whole shell; and when a remaining triangle at a or b
  // would fold over (its normal turns by more than 90 degrees).
  Status collapseEdge(uint32_t e, double t = 0.5, uint32_t* remaining = nullptr);
  // Reverses the winding of triangle t (corners (a, b, c) -> (a, c, b)); a kept normal is
  // negated.
  Status reverseTriangle(uint32_t t);
  // Reverses the winding of the n triangles ids[0..n), as one edit: the same triangles,
  // topology, counts and attributes as n reverseTriangle calls (the half-edge slots may
  // differ, as after any edit). InvalidArgument, and nothing changes, for a dead or
  // out-of-range id or an id listed twice.
  Status reverseTriangles(const uint32_t* ids, uint32_t n);
  // Reverses every triangle of the shell of triangle t (triangles connected through shared
  // edges, as Topology::nShells counts them).
  Status reverseShell(uint32_t t);
  // Fills the boundary loop of the boundary half-edge e with new triangles, returned in
  // `out`: a fan from the loop's first vertex, or ear clipping in the loop's best-fitting
  // (Newell) plane. A loop that passes a vertex more than once is cut there into simple
  // loops, each filled on its own. Refused for seams (loops with cut sides), for a part of
  // two edges, and when a new inner edge would land on an existing edge.
  Status fillHole(uint32_t e, FillMethod method, Array<uint32_t>* out = nullptr);
  // Same for loop h of loops().
  Status fillLoop(uint32_t h, FillMethod method, Array<uint32_t>* out = nullptr);

  // --- Joining and splitting vertices (repair: stitch, split-nonmanifold) ---------------
  // Merges vertex gone[i] into keep[i] for every i < n, as one edit: the triangles at
  // gone[i] now use keep[i] (they keep their ids), and gone[i] dies. keep[i] stays where it
  // is (the triangles at gone[i] move by the distance between the two). The 2n ids must be
  // live and all different (InvalidArgument). Refused, and nothing changes, when:
  //   - a triangle would get a repeated corner (it uses both vertices of a pair);
  //   - an edge that gains sides from another edge would end with three or more sides or
  //     with two sides running the same way (only boundary sides that pair up may join:
  //     an edge that merely moves with its vertex keeps its kind, and so does one that ends
  //     with as many sides of the same kind as it had, such as a side handed from a split
  //     triangle to its new part);
  //   - the number of boundary, non-manifold or inconsistent edges would grow;
  //   - unless allowNonManifold, the number of non-manifold vertices would grow (a single
  //     pair of boundary vertices whose edges do not join pinches two fans together: that
  //     is refused; a run of pairs along two boundaries zips them into one surface);
  //   - a moved triangle would fold over (its normal turns by more than 90 degrees, as in
  //     collapseEdge) or become zero-area (exactly collinear corners) when it was not.
  // Attributes: each keep[i] gets merge(keep, gone, 1/2) of the vertex attributes (the two
  // are one point of the surface); triangles keep theirs; an edge that two edges join into
  // keeps the values of the one whose half-edges the pairing keeps.
  Status mergeVertices(const uint32_t* keep, const uint32_t* gone, uint32_t n, bool allowNonManifold = false);
  Status mergeVertices(uint32_t keep, uint32_t gone, bool allowNonManifold = false);
  // Closes a T-junction: splits the boundary edge of e = a -> b at the existing vertex v,
  // which lies on it or near it: the edge's triangle (a, b, c) becomes (a, v, c), keeping
  // its id, and (v, b, c), a new id. The same result as splitEdge(e, t) at v's projection
  // t followed by mergeVertices(v, m), without the dead vertex m. InvalidArgument unless e
  // is a boundary half-edge (or the twin of one) and v a live vertex; refused when v is a
  // corner of the triangle, when v's projection onto a-b is not strictly inside the edge,
  // and for every reason mergeVertices refuses (edges that cannot pair, more defective
  // edges or, unless allowNonManifold, non-manifold vertices, fold-over, zero area). Both
  // parts get split(x, x, t) of the triangle attributes; v keeps its values.
  Status splitEdgeAt(uint32_t e, uint32_t v, bool allowNonManifold = false);
  // Both at once, as one edit (a crack whose two sides have different vertices): the
  // T-junctions (boundary half-edge edges[i], vertex vertices[i]) split their edges first
  // (several vertices on one edge split it in order along it; two edges of one triangle
  // may not both be split), then gone[i] merges into keep[i] everywhere, the new parts
  // included. Refused as mergeVertices and splitEdgeAt are, judged on the whole change
  // (a pair that alone would pinch may close with the splits beside it).
  Status stitch(const uint32_t* keep, const uint32_t* gone, uint32_t n, const uint32_t* edges, const uint32_t* vertices,
                uint32_t nSplits, bool allowNonManifold = false);
  // Splits vertex v into one vertex per fan; the fans beyond the first (ordered by their
  // lowest triangle id) get new vertices at the same position, with v's vertex attribute
  // values, and their triangles use them (triangle ids kept). A fan: v's triangles
  // connected through the edges at v that have exactly two sides (interior or
  // inconsistent), and through the pairs of v's non-manifold edges (paired as
  // buildTopology pairs them: opposite directions) where joining the two fans keeps every
  // edge at v at two sides at most. So a non-manifold vertex splits into its fans, and a
  // non-manifold edge's pairs come apart into manifold edges once both ends are split
  // (what manifold-3d does on import: duplicated edges, then pinched vertices split).
  // Returns the first new vertex and the number of new vertices (they follow each other).
  // Refused when v has one fan (nothing to split).
  Status splitVertex(uint32_t v, uint32_t* firstNew = nullptr, uint32_t* newCount = nullptr);

  // --- Attributes -----------------------------------------------------------------------
  // Adds (or replaces) attribute `name`. `values`: count * components values of `type` for
  // the current slots (count = nVertices(), nTriangles() or nHalfedges() / 2), or null for
  // all defaults. `defaultValue`: `components` numbers, or null for zeros. InvalidArgument
  // for zero components or an empty name.
  Status addAttribute(const std::string& name, Element element, ValueType type, uint32_t components, const void* values,
                      const AttributeRules& rules = {}, const double* defaultValue = nullptr);
  // Null when there is no such attribute.
  const AttributeView* attribute(const std::string& name) const;
  bool removeAttribute(const std::string& name);
  std::vector<std::string> attributeNames() const;

  // --- Output ---------------------------------------------------------------------------
  // The live mesh renumbered densely in the same order (vertices that no live triangle
  // uses are dropped), with the attribute word, colours and normals from the triangle
  // attributes and the figures (area, volume, bbox, normal mismatches) computed as the
  // reader computes them, and, when `topo` is given, its topology, equal to
  // buildTopology(out) in every array (with `triangleShell`, Topology::triangleShell too,
  // as TopologyOptions::triangleShell builds it). Solids keep their triangles; triangles
  // added by edits belong to the last solid. O(n). OutOfMemory leaves `out` unspecified.
  // figures = false: area, volume and normalMismatches are left 0 (the arrays, solids and
  // bbox as always), for a caller that needs only the arrays: their sums are about half of
  // the plain mesh's time.
  Status toMesh(Mesh& out, Topology* topo = nullptr, CompactMaps* maps = nullptr, bool triangleShell = false,
                bool figures = true) const;
  // Renumbers this mesh densely (toMesh + init): ids become the compacted ones.
  Status compact(CompactMaps* maps = nullptr);

  // Checks the editable structure (corner lists, side half-edges, counts, pairing rule) and
  // then validate() on toMesh()'s output. O(n). Code::Invalid with the element.
  Status validate() const;

  struct Impl;  // the state and the edit machinery (src/edit/)

 private:
  // The state and the machinery (src/edit/impl.h). Null only after a move or when it could
  // not be allocated: the object then reads as empty and init() allocates it again.
  Impl* impl_;
};

}  // namespace stltopo
