// The tolerance weld: a representative per vertex, for the topology only.
#pragma once

#include "bit_cast.h"
#include "stltopo/mesh.h"
#include "stltopo/topology.h"

namespace stltopo::detail {

// Deterministic tolerance weld: vertices in id order; a vertex joins the lowest-id
// representative within `tol` (Euclidean, in double) found in its own or the 26
// neighbouring grid cells of size `tol`; otherwise it becomes a representative itself
// (rep[v] = v). Fills rep (one entry per mesh vertex) and returns the number of
// representatives, or kInvalid when an allocation failed (rep is then unspecified).
// tol > 0. Memory: about 8 bytes per vertex plus 32 per representative's cell slot.
uint32_t toleranceWeld(const Mesh& mesh, double tol, Array<uint32_t>& rep);

}  // namespace stltopo::detail
