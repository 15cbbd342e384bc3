// stltopo/report.h: the report `stltopo info` prints (JSON and text).
#pragma once

#include <string>

#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"

namespace stltopo {

// The report: what `stltopo info --json` prints. Never fails on a Mesh and Topology from
// readStl/Reader and buildTopology (with either prevAndFace); the strings allocate, so
// natively an exhausted heap throws std::bad_alloc here and nowhere else in the core.

// JSON object (one line, no trailing newline) for a successfully read file. `topo` may be
// null: the mesh part only (no edge, hole, shell, genus, watertight or manifold keys).
// `genus` is null unless the topology is watertight and manifold; `weldedVertices` is
// present only for a tolerance weld (TopologyOptions::tolerance > 0). `file` is printed
// as given (invalid UTF-8 becomes U+FFFD).
std::string infoJson(const std::string& file, const Mesh& mesh, const Topology* topo);
// The CLI's human-readable report (several lines, each ending in a newline); `topo` may
// be null as for infoJson.
std::string infoText(const std::string& file, const Mesh& mesh, const Topology* topo);
// JSON object for a failed file: {"file":..,"error":{code,message,location}}.
std::string errorJson(const std::string& file, const Status& error);
// Escapes a string as a JSON string literal (with quotes); invalid UTF-8 becomes U+FFFD.
std::string jsonString(const std::string& s);

}  // namespace stltopo
