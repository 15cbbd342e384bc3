// The repair steps' common frame (private). The runner (src/repair/repair.cpp) compacts the
// EditableMesh before each step, hands the step a StepContext, and turns what the step did
// into the step's plan entry and change log. A step:
//   1. finds its candidate items on ctx.em (ids dense: the mesh is compacted);
//   2. for each item in order: ctx.begin(...) it; when ctx.excluded() says the user left it
//      out, ctx.skip("left out"); otherwise it tries the edits (each edit is all or
//      nothing) and calls ctx.skip(reason) when a precondition fails or an edit is refused
//      (having undone nothing: a refused edit changed nothing, and a step must check
//      before it edits, or take back its own partial edits of that item with edits);
//   3. returns Ok, or an error (out of memory, an edit failing for a reason it did not
//      expect): the runner then restores the mesh as it was before the step.
// Steps never print and never allocate without checking (detail::oom for failures).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "stltopo/edit.h"
#include "stltopo/geometry.h"
#include "stltopo/repair.h"
#include "try_alloc.h"

namespace stltopo {
namespace repair_detail {

struct StepContext {
  EditableMesh& em;
  const RepairOptions& options;
  RepairStepPlan& plan;
  // The mesh as the step found it (compacted: its ids are em's at the start of the step),
  // with its topology; null when the caller (a test) gives none: snapshot() makes them.
  const Mesh* mesh = nullptr;
  const Topology* topo = nullptr;
  // Where the runner rebuilds the mesh after the step (em.toMesh(*next, nextTopo, maps));
  // null when the caller gives none. A step that needs that rebuild itself may make it
  // there (with triangleShell or not) and set `rebuilt` when it edits nothing after it: the
  // runner then takes it as its own (dropping triangleShell) instead of building it again.
  Mesh* next = nullptr;
  Topology* nextTopo = nullptr;
  CompactMaps* maps = nullptr;
  bool rebuilt = false;
  // Orient's reversals (reverseTriangles), each triangle at most once, for the runner's
  // change log: while `reversedListed`, every triangle the step changed is in `reversed` (in
  // any order), and the step changed nothing else. A step that does not keep the list, or
  // changes the mesh another way, leaves or sets reversedListed false.
  Array<uint32_t> reversed{};
  bool reversedListed = false;
  // The triangle checks of `mesh` (with `topo`), when the runner has them; null otherwise.
  const TriangleChecks* checks = nullptr;
  // Index the next item gets.
  uint32_t nextItem() const { return uint32_t(plan.items.size()); }
  // Starts item `action`, touching these elements (ids of em now); bbox from their
  // positions (a loop's bbox is its vertices'). Returns the item, to fill further.
  RepairItem& begin(std::string action, std::vector<uint32_t> triangles = {}, std::vector<uint32_t> vertices = {},
                    std::vector<uint32_t> loops = {});
  // True when the user left the current (last begun) item out; marks it skipped.
  bool excluded();
  void skip(std::string reason) {
    plan.items.back().skipped = true;
    plan.items.back().reason = std::move(reason);
  }
};

Status runDuplicates(StepContext& ctx);
Status runZeroArea(StepContext& ctx);
Status runStitch(StepContext& ctx);
Status runSplitNonManifold(StepContext& ctx);
Status runFillHoles(StepContext& ctx);
// Tests only: whether the fill step's cell grid screens the triangles before the query of the
// loops' boxes (fill_holes.cpp, CellGrid); the default, true, and false give the same plans.
void setFillCellGridForTesting(bool on);
Status runOrient(StepContext& ctx);
Status runSmallShells(StepContext& ctx);

// |p - q| of two stored positions, in double (a float's difference and square are exact
// there; the sum and the root round). For what the steps measure and order, not for the
// decisions the contract calls exact (those are src/predicates.h's).
inline double distance(const float* p, const float* q) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += (double(p[k]) - q[k]) * (double(p[k]) - q[k]);
  return std::sqrt(d2);
}

// printf into a std::string for the plan's texts (actions, reasons, notes). Unlike
// detail::format (for error messages, which it cuts rather than fail), it never cuts: when
// the string cannot be allocated it throws natively, and the runner's catch makes that the
// step's out-of-memory error (runStep); in the wasm build, as for every std container there,
// it aborts.
std::string text(const char* f, ...) __attribute__((format(printf, 1, 2)));

// The compacted mesh and topology of em (for steps that read Topology, shells, checks).
Status snapshot(const EditableMesh& em, Mesh& mesh, Topology& topo);

}  // namespace repair_detail
}  // namespace stltopo
