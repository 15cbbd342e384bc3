// stltopo shells and defects: the per-shell report and every defect with its location.
//
// A shell is an edge-connected component of the non-degenerate triangles (every shared
// edge counts, cut or not). Shells are numbered in the order of their lowest triangle id;
// Topology::triangleShell[t] is the shell of triangle t, kInvalid for a degenerate one.
//
// Needs Topology::triangleShell (TopologyOptions::triangleShell = true), never prev or
// face: the report-only topology (TopologyOptions::prevAndFace = false) is enough.
#pragma once

#include "stltopo/array.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"

namespace stltopo {

// How a shell is wound, decided in this order:
enum class Orientation : uint8_t {
  Inconsistent,  // "inconsistent": it has an inconsistent edge (a flipped face)
  Open,          // "open": else, it has a boundary edge
  Outward,       // "outward": else, its signed volume is > 0 (also when only non-manifold
                 //            edges keep it from being closed); the exact sum's sign
                 //            (Shell::volumeSign), not the rounded Shell::volume's
  Inward,        // "inward": else, its signed volume is < 0
  Flat,          // "flat": else, its signed volume is exactly 0
};
const char* orientationName(Orientation o);

// Shell::solid when the shell's triangles come from more than one solid.
inline constexpr uint32_t kMixedSolid = kInvalid - 1;

// One shell. Counts use the topology's vertices (Topology::vertexWeld representatives);
// the figures (area, volume, bbox) use the triangles' own corners (Mesh::triangles), with
// the reader's formulas, summed in triangle order.
struct Shell {
  uint32_t firstTriangle = kInvalid;  // its lowest triangle id
  uint32_t triangles = 0;             // non-degenerate triangles
  uint32_t vertices = 0;              // vertices its triangles use; a vertex shared by several
                                      // shells (they touch there) counts in each of them
  // The surface counts of stltopo/counts.h (edges, boundaryEdges, nonManifoldEdges,
  // inconsistentEdges, nonManifoldVertices, holes, seams), in this shell: all the triangles of
  // an edge are in one shell, so every edge counts in exactly one shell, and so does every
  // boundary loop; nonManifoldVertices counts the vertices with more than one vnext cycle in
  // this shell.
#define STLTOPO_SHELL_MEMBER(count, name, doc) uint32_t name = 0;
  STLTOPO_SURFACE_COUNTS(STLTOPO_SHELL_MEMBER)
#undef STLTOPO_SHELL_MEMBER
  uint32_t solid = kInvalid;  // index into Mesh::solids of the solid holding all of its
                              // triangles, kMixedSolid if several do, kInvalid if none
  double area = 0;            // sum of triangle areas
  double volume = 0;          // signed volume: sum of the signed tetrahedra (origin, a, b, c)
  int volumeSign = 0;         // the exact sign of that sum (without rounding): 1, -1 or 0;
                              // orientation() reads it (a flat closed shell is "flat")
  float bboxMin[3] = {0, 0, 0}, bboxMax[3] = {0, 0, 0};  // of its triangles' corners

  int64_t eulerCharacteristic() const { return int64_t(vertices) - int64_t(edges) + int64_t(triangles); }
  // Watertight on its own: no boundary, non-manifold or inconsistent edge.
  bool closed() const { return boundaryEdges == 0 && nonManifoldEdges == 0 && inconsistentEdges == 0; }
  bool manifold() const { return nonManifoldEdges == 0 && nonManifoldVertices == 0; }
  bool consistent() const { return inconsistentEdges == 0; }
  // The genus is defined when the shell is closed and manifold: (2 - chi) / 2.
  bool hasGenus() const { return closed() && manifold(); }
  double genus() const { return double(2 - eulerCharacteristic()) / 2; }
  Orientation orientation() const;
};

// Every defect, with its location, as flat arrays (one entry per defect, no per-defect
// objects). Vertex ids are the topology's (Topology::vertexWeld representatives, which are
// mesh vertex ids); triangle ids are the file's. Holes and seams are the topology's loops
// (Topology::loop*); only their shells are added here.
struct Defects {
  // Non-manifold edges, ordered by (smaller vertex, larger vertex). Edge i joins vertices
  // nonManifoldEdgeVertices[2i] < nonManifoldEdgeVertices[2i + 1]; the triangles with a side
  // on it, ascending, are nonManifoldEdgeTriangles[nonManifoldEdgeOffsets[i] ..
  // nonManifoldEdgeOffsets[i + 1]) (nonManifoldEdgeOffsets has one entry more than edges).
  Array<uint32_t> nonManifoldEdgeVertices;
  Array<uint32_t> nonManifoldEdgeOffsets;
  Array<uint32_t> nonManifoldEdgeTriangles;
  // Inconsistent edges, in the same order: edge i joins inconsistentEdgeVertices[2i] <
  // [2i + 1]; its two triangles are inconsistentEdgeTriangles[2i] < [2i + 1].
  Array<uint32_t> inconsistentEdgeVertices;
  Array<uint32_t> inconsistentEdgeTriangles;
  // Non-manifold vertices, ascending, and the number of vnext cycles of each (>= 2).
  Array<uint32_t> nonManifoldVertices;
  Array<uint32_t> nonManifoldVertexCycles;
  // Degenerate triangles, ascending, and which of their corners weld together: bit 0
  // corners 0 and 1, bit 1 corners 1 and 2, bit 2 corners 2 and 0 (7: all three).
  Array<uint32_t> degenerateTriangles;
  Array<uint8_t> degenerateCorners;
  // Per boundary loop h (hole or seam): the shell it lies in.
  Array<uint32_t> loopShell;
};

// Builds the per-shell report and the defect lists of `mesh` and its topology `topo`,
// built from this mesh with TopologyOptions::triangleShell (prev and face are not needed).
// Returns Ok, InvalidArgument (no triangleShell, or a topology that is not this mesh's:
// sizes, or a triangleShell not numbered as above) or OutOfMemory; on failure `shells` and
// `defects` are left empty. Either output may be null when not wanted. Allocates only
// through Array (no throw); O(n) plus a sort of the cut sides, of the half-edges leaving
// non-manifold vertices and of the loops.
Status findShellsAndDefects(const Mesh& mesh, const Topology& topo, Array<Shell>* shells, Defects* defects);

// The mesh of one shell, as a file of its own would read: its triangles in file order
// (the degenerate ones belong to no shell), its vertices compacted and numbered by first
// appearance in corner order (as the reader numbers them: writing `out` and reading it back
// gives the same arrays), the attribute words, kept normals and colours of its triangles,
// the solids it has triangles in (names kept, counts of its triangles), and its figures
// (area, volume, bbox; normalMismatches when the mesh kept its normals, else 0)
// recomputed. format and colorConvention are the mesh's; no warnings. Needs
// Topology::triangleShell. Returns Ok, InvalidArgument (no triangleShell, or no shell
// `shell`) or OutOfMemory; `out` is reset first and holds a partial mesh on failure.
Status extractShell(const Mesh& mesh, const Topology& topo, uint32_t shell, Mesh& out);

// ---------------------------------------------------------------------------
// Report fragments, in the format of infoJson / infoText.

// One shell's object, as in "shellList" (`id` is its index).
std::string shellJson(const Shell& shell, uint32_t id);
// The line `stltopo split` prints for each file it writes: {"file":FILE,"shell":{...}}.
std::string splitLineJson(const std::string& file, const Shell& shell, uint32_t id);
// `"shellList":[{...},...]`: one object per shell, in shell order.
// With `nesting` (findShellNesting of these shells), each object also has "selfIntersects",
// "intersectsShells", "parent" and "depth", as with `info --intersections`.
struct ShellNesting;
std::string shellListJson(const Array<Shell>& shells, const ShellNesting* nesting = nullptr);
// The JSON array ("[{...},...]") of shells [first, first + count) of the list, each as
// shellListJson gives it (its id its index in `shells`): a list too long for one string
// (a triangle soup has a shell a triangle) in ranges. Empty ("[]") past the end.
std::string shellRangeJson(const Array<Shell>& shells, const ShellNesting* nesting, size_t first, size_t count);
// `"defects":{...}`: each kind with its count and its first `maxPerKind` items; a hole's or
// seam's vertex list (and a seam's cut-edge list) is cut at `maxPerKind` entries too, its
// full length being its "edges".
std::string defectsJson(const Mesh& mesh, const Topology& topo, const Defects& defects, uint32_t maxPerKind);
// Lines for a person: the first `maxPerKind` defects of each kind with their coordinates.
std::string defectsText(const Mesh& mesh, const Topology& topo, const Defects& defects, uint32_t maxPerKind);
// Lines for a person: one per shell.
std::string shellsText(const Array<Shell>& shells);

}  // namespace stltopo
