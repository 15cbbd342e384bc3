// stltopo: read STL files into an indexed triangle mesh and libstl-style topology.
//
// The umbrella header: includes every public header of the library. Everything is plain
// data plus a few functions; the core never prints, never touches files and never starts
// threads. Allocation
// failure is reported as Code::OutOfMemory, never thrown across the API.
//
// Layout (all indices are uint32, kInvalid = ~0u means "none"):
//   positions[3*v + k]     coordinate k of vertex v            (Mesh)
//   triangles[3*t + c]     vertex of corner c of triangle t     (Mesh)
//   next[e], vert[e], face[e]  half-edge arrays                 (Topology)
//   twin(e) = e ^ 1;  vnext(e) = next[e ^ 1]
#pragma once

// clang-format off: each header after the ones it builds on (kept by hand)
#include "stltopo/array.h"
#include "stltopo/counts.h"
#include "stltopo/edit.h"
#include "stltopo/geometry.h"
#include "stltopo/indexed.h"
#include "stltopo/mesh.h"
#include "stltopo/read.h"
#include "stltopo/repair.h"
#include "stltopo/report.h"
#include "stltopo/shells.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"
#include "stltopo/write.h"
// clang-format on
