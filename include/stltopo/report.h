// stltopo/report.h: the report `stltopo info` prints (JSON and text).
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "stltopo/geometry.h"
#include "stltopo/mesh.h"
#include "stltopo/shells.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"

namespace stltopo {

// The report: what `stltopo info --json` prints. Never fails on a Mesh and Topology from
// readStl/Reader and buildTopology (with either prevAndFace); the strings allocate, so
// natively an exhausted heap throws std::bad_alloc here and nowhere else in the core.

// JSON object (one line, no trailing newline) for a successfully read file. `topo` may be
// null: the mesh part only (no edge, hole, shell, genus, watertight, manifold,
// intersection or solid keys). "zeroAreaTriangles" and "duplicateTriangles" are always
// there (checkTriangles, run here; null only when its memory ran out); the intersection
// keys ("selfIntersections", "intersectionKinds", "intersectingTriangles",
// "intersectionsComplete", "solid") are null unless ReportExtras::intersections is given.
// `genus` is null unless the topology is watertight and manifold; `weldedVertices` is
// present only for a tolerance weld (TopologyOptions::tolerance > 0). `file` is printed
// as given (invalid UTF-8 becomes U+FFFD).
std::string infoJson(const std::string& file, const Mesh& mesh, const Topology* topo);
// The CLI's human-readable report (several lines, each ending in a newline); `topo` may
// be null as for infoJson.
std::string infoText(const std::string& file, const Mesh& mesh, const Topology* topo);
// What `info --shells` and `--defects` add to the report: the results of
// findShellsAndDefects on the same mesh and topology. A null member adds nothing.
struct ReportExtras {
  const Array<Shell>* shells = nullptr;  // JSON: "shellList"; text: a line per shell
  const Defects* defects = nullptr;      // JSON: "defects"; text: the first maxDefects of each kind
  uint32_t maxDefects = 1000;            // items per defect kind, and entries of each loop's
                                         // vertex and cut-edge lists (JSON)
  // The geometry (stltopo/geometry.h) of the same mesh and topology.
  const TriangleChecks* checks = nullptr;        // null: the report runs checkTriangles itself
  const Intersections* intersections = nullptr;  // the intersection keys, and the defects'
                                                 // "selfIntersections" (else null)
  const ShellNesting* nesting = nullptr;         // with shells: each shell's "selfIntersects",
                                                 // "intersectsShells", "parent" and "depth"
  bool solid = false;                            // "solid", when intersections is given
};
// infoJson with "shellList" and then "defects" as the last keys (`topo` must not be null
// when `extras` has a member). Keeps the guarantees of infoJson.
std::string infoJson(const std::string& file, const Mesh& mesh, const Topology* topo, const ReportExtras& extras);
// Where infoJson(sink, ...) hands its text: `size` bytes at `data`, valid during the call.
using ReportSink = std::function<void(const char* data, size_t size)>;
// The size of its pieces: each but the last holds at least this much, and at most this
// plus one list item (a shell, a defect: a few kB, or a loop's vertex list).
constexpr size_t kReportPiece = size_t(1) << 20;
// infoJson with extras, handed to `sink` in pieces as it is written: the pieces, in the order
// given, are infoJson's string. Never holds the whole report: `info --json --shells` of a
// triangle soup lists a shell per triangle, some 390 bytes each (770 MB for 2M triangles).
void infoJson(const ReportSink& sink, const std::string& file, const Mesh& mesh, const Topology* topo,
              const ReportExtras& extras);
// infoText with extras in pieces, likewise (a line a shell: some 150 bytes each).
void infoText(const ReportSink& sink, const std::string& file, const Mesh& mesh, const Topology* topo,
              const ReportExtras& extras);
// infoText with the shell lines and then the defect lines after the topology's.
std::string infoText(const std::string& file, const Mesh& mesh, const Topology* topo, const ReportExtras& extras);
// JSON object for a failed file: {"file":..,"error":{code,message,location}}.
std::string errorJson(const std::string& file, const Status& error);
// Escapes a string as a JSON string literal (with quotes); invalid UTF-8 becomes U+FFFD.
std::string jsonString(const std::string& s);

}  // namespace stltopo
