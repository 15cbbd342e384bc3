// stltopo repair: opt-in steps, planned before anything changes, applied with a change log
// that undoes them exactly. The core never repairs on its own: this layer runs only when
// the caller asks, and changes only what the plan lists.
//
// The model.
//   - planRepair(mesh, options) changes nothing. It runs the chosen steps on a scratch copy
//     and returns the plan: per step, its items (what each will do, the elements it touches
//     and where they are), the items that are skipped with the reason, and the figures the
//     mesh will have after the step.
//   - applyRepair(editable, plan) runs the same steps on an EditableMesh of the same mesh
//     and returns the change log: per step, every removed, added and changed triangle and
//     vertex, the largest distance a surviving vertex moved, the area removed and added,
//     and the reports before and after (fresh builds). The steps are deterministic, so the
//     result equals the plan's prediction. When the plan kept its own run's result
//     (RepairPlan::result), applyRepair takes that instead of running the steps again: the
//     same mesh and the same log.
//   - undoRepair(editable, log) (or undoRepairStep, last step first) restores the mesh
//     exactly: every position, corner and attribute, in the same slots.
//
// Ids. Between steps the mesh is compacted (EditableMesh::compact): the ids a step lists
// are those of the mesh as that step found it, numbered densely. The first step sees the
// input's ids. In a step's log, removed and changed elements carry their ids before the
// step; added ones take the ids after the step, which follow the survivors (survivors keep
// their order, so old -> new ids follow from the removed lists).
//
// Failures. An item that cannot be done (a refused edit, a failed precondition) is listed
// as skipped with the reason, and nothing of it changes. A step that fails part-way (out of
// memory) leaves the mesh as it was before that step; applyRepair then stops and returns
// the error, with the log of the steps that completed.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "stltopo/array.h"
#include "stltopo/edit.h"
#include "stltopo/mesh.h"
#include "stltopo/status.h"
#include "stltopo/topology.h"

namespace stltopo {

// The steps, in the order they run.
enum class RepairStepKind : uint8_t {
  Duplicates,        // "duplicates": remove duplicate triangles (keep the lowest id)
  ZeroArea,          // "zero-area": flip the longest edge of a zero-area triangle, or collapse its shortest
  Stitch,            // "stitch": merge boundary vertices within a tolerance, close T-junctions
  Orient,            // "orient": consistent orientation per shell, closed shells outward
  SplitNonManifold,  // "split-nonmanifold": one vertex per fan at non-manifold vertices and edges
  FillHoles,         // "fill-holes": triangulate holes up to a size limit
  SmallShells,       // "small-shells": remove shells below a size (off by default)
};
inline constexpr int kRepairStepCount = 7;
// The stable name of a step ("zero-area"); "unknown" outside the enum.
const char* repairStepName(RepairStepKind k);
// The step named `name`; false when there is none.
bool repairStepFromName(const std::string& name, RepairStepKind& out);
inline constexpr uint32_t repairStepBit(RepairStepKind k) { return 1u << uint32_t(k); }
// The default steps: duplicates, zero-area, stitch, orient, fill-holes (README, *Repair*).
inline constexpr uint32_t kDefaultRepairSteps =
    repairStepBit(RepairStepKind::Duplicates) | repairStepBit(RepairStepKind::ZeroArea) |
    repairStepBit(RepairStepKind::Stitch) | repairStepBit(RepairStepKind::Orient) |
    repairStepBit(RepairStepKind::FillHoles);

struct RepairOptions {
  uint32_t steps = kDefaultRepairSteps;  // bits of repairStepBit
  // duplicates: also remove every member of a group whose members face both ways (a
  // zero-thickness wall); otherwise such groups are skipped.
  bool removeOppositeDuplicates = false;
  // stitch: boundary vertices at most this far apart (Euclidean, in file units; decided
  // exactly) are merged; 0 merges nothing by distance and closes only exact T-junctions.
  double stitchTolerance = 0;
  // fill-holes: holes over any of these limits are skipped (0 = no limit for area and
  // perimeter).
  uint32_t maxHoleEdges = 1000;
  double maxHoleArea = 0;
  double maxHolePerimeter = 0;
  bool fillRefine = false;  // insert vertices to the surrounding edge length
  bool fillFair = false;    // smooth the new interior vertices (with fillRefine)
  // small-shells: shells with fewer triangles, or less |volume| (0 = no volume limit).
  uint32_t minShellTriangles = 10;
  double minShellVolume = 0;
  // Run the exact intersection pass: orient then uses shell nesting (a cavity stays a
  // cavity), and the plan lists the self-intersections that remain. Without it, closed
  // shells are oriented by volume sign only.
  bool intersections = true;
  uint64_t maxPairs = 4000000;
  // Threads for the passes the plan and the runner make on the whole mesh (the rebuilt
  // topology, the triangle checks, the intersection pass; as ReadOptions::threads: 1 = one
  // thread, the default, 0 = the machine's hardware threads). Plans, logs and results are
  // the same for every value, so plans and logs do not record it.
  unsigned threads = 1;
  // Items to leave out: (step, index of the item in that step's list) of a plan made with
  // the same options and exclusions before this one.
  struct Exclusion {
    RepairStepKind step;
    uint32_t item;
  };
  std::vector<Exclusion> exclude;
  // Keep the plan's own result (RepairPlan::result) for applyRepair, which then takes it
  // instead of running the steps again. false: the plan holds no mesh, and applyRepair runs
  // the steps.
  bool keepResult = true;
  // Called as each step starts (done = false) and ends (done = true), for progress and
  // timing. Optional.
  void (*onStep)(void* user, RepairStepKind step, bool done) = nullptr;
  void* user = nullptr;
};

// One thing a step does (or would do).
struct RepairItem {
  std::string action;  // what it does, in words ("remove triangle 17, a copy of 12")
  bool skipped = false;
  std::string reason;                                // why it is skipped
  std::vector<uint32_t> triangles, vertices, loops;  // ids as the step finds the mesh
  float bbox[6] = {0, 0, 0, 0, 0, 0};                // min xyz, max xyz of the elements it touches
  double moved = 0;                                  // how far it moves geometry (a collapse: the merged vertex)
};

// The figures of a mesh: EditStats plus the geometry counts.
struct RepairFigures {
  EditStats stats;
  uint32_t zeroAreaTriangles = 0, duplicateTriangles = 0;
  // With RepairOptions::intersections (else kInvalid / false).
  uint32_t selfIntersections = kInvalid;
  bool solid = false;
};

struct RepairStepPlan {
  RepairStepKind kind = RepairStepKind::Duplicates;
  std::string note;  // e.g. "closed shells oriented by volume sign only"
  std::vector<RepairItem> items;
  RepairFigures after;  // the figures after this step
  uint32_t nDone() const;
  uint32_t nSkipped() const;
};

struct RepairResult;  // what a plan's own run of the steps left (see RepairPlan::result)

struct RepairPlan {
  RepairOptions options;
  uint64_t fingerprint = 0;  // of the input (positions and triangles)
  RepairFigures before;
  bool beforeKnown = false;  // planRepair computed `before` (apply then reuses it)
  // The predicted result: its fingerprint and its figures (= steps.back().after, or
  // `before` when no step runs). applyRepair takes the intersection pass's figures of its
  // result (selfIntersections, solid) from here instead of running the pass again when
  // its result has this fingerprint; every other figure it computes afresh.
  bool afterKnown = false;
  uint64_t fingerprintAfter = 0;
  RepairFigures after;
  std::vector<RepairStepPlan> steps;  // the chosen steps, in run order
  std::string remaining;              // what the steps leave (self-intersections: advice)
  std::string afterReport;            // infoJson("") of the predicted result
  // The plan runs the steps on a scratch copy of the mesh. With RepairOptions::keepResult,
  // it keeps what that run left: the repaired mesh (compacted; an EditableMesh, or, when the
  // last step changed the mesh, the Mesh and Topology one is made from when an applyRepair
  // into an EditableMesh takes it) and the change log. applyRepair takes them instead of running the steps again when
  // its mesh is the plan's input as the plan found it (the same positions, triangles, attribute words, colours,
  // normals, solids and warnings) and its plan's options are the ones the result was made with (onStep, user, threads
  // and keepResult aside). The steps are deterministic, so the mesh and the log are the ones a run gives (the tests
  // compare both ways). The first applyRepair of a plan, or of a copy of it, takes the result; later ones run the
  // steps. Memory: the repaired mesh with its topology and attributes, held until it is applied or the plan and its
  // copies are gone (reset() it to let go).
  std::shared_ptr<RepairResult> result;
  // Whether an applyRepair took `result` (false without one).
  bool resultTaken() const;
};

// What one step changed. Ids: see the header comment.
struct RepairStepLog {
  RepairStepKind kind = RepairStepKind::Duplicates;
  Status status;  // Ok, or why the step failed (the mesh is then as before it)
  uint32_t trianglesBefore = 0, verticesBefore = 0, trianglesAfter = 0, verticesAfter = 0;
  std::vector<Solid> solidsBefore;   // names and triangle ranges before
  Array<uint32_t> removedTriangles;  // ascending ids before
  Array<uint32_t> removedCorners;    // 3 per removed triangle (vertex ids before)
  Array<uint32_t> changedTriangles;  // ascending ids before
  Array<uint32_t> changedCorners;    // 3 per changed triangle: corners before
  uint32_t addedTriangles = 0;       // ids trianglesAfter - added .. trianglesAfter - 1
  Array<uint32_t> removedVertices;   // ascending ids before
  Array<float> removedPositions;     // 3 per removed vertex
  Array<uint32_t> changedVertices;   // ascending ids before: moved or attributes changed
  Array<float> changedPositions;     // 3 per changed vertex: position before
  uint32_t addedVertices = 0;
  // Attribute values before, per triangle/vertex attribute (in attributeNames() order):
  // for the removed then the changed elements, stride bytes each.
  std::vector<std::string> attributeNames;
  std::vector<Array<uint8_t>> attributeBefore;
  double maxMoved = 0;  // largest distance geometry moved (a surviving vertex,
                        // or a vertex merged into another)
  double areaRemoved = 0, areaAdded = 0;
  uint32_t itemsDone = 0, itemsSkipped = 0;
  uint64_t fingerprintAfter = 0;  // repairFingerprint of the mesh after the step
};

struct RepairLog {
  uint64_t fingerprintBefore = 0, fingerprintAfter = 0;
  std::string beforeReport, afterReport;  // infoJson("") before and after
  RepairFigures before, after;
  std::vector<RepairStepLog> steps;  // the steps that ran, in order
};

// A fingerprint of the live mesh in compacted order (positions, corners). O(n).
uint64_t repairFingerprint(const EditableMesh& em);

// Plans the repair of `mesh`. Changes nothing. Errors: InvalidArgument (bad options),
// OutOfMemory, Aborted.
Status planRepair(const Mesh& mesh, const RepairOptions& options, RepairPlan& out);
// The same with the topology an EditableMesh of this mesh is (or will be) made from
// (EditableMesh::init(mesh, topo)): a tolerance weld's representatives, for example. The
// plan then fits that EditableMesh.
Status planRepair(const Mesh& mesh, const Topology* topo, const RepairOptions& options, RepairPlan& out);
// The plan for what `em` holds (as compacted): applyRepair(em, plan) then fits.
Status planRepair(const EditableMesh& em, const RepairOptions& options, RepairPlan& out);

// Carries out `plan` on `em`, which must hold the mesh the plan was made for (same
// fingerprint; InvalidArgument otherwise, and nothing changes). The mesh is compacted first
// (ids of a mesh with dead slots change then, as compact() says). Edge attributes are not
// carried through repair: a mesh with any is refused (InvalidArgument). With the plan's
// result (RepairPlan::result) for this mesh, em takes the repaired mesh and `log` the
// change log from it (O(n) to check that em holds the plan's input; onStep is called for
// each step of the log); otherwise the steps run.
Status applyRepair(EditableMesh& em, const RepairPlan& plan, RepairLog& log);
// The same for the Mesh the plan was made from (planRepair(mesh, ...)): `em` becomes the
// repaired mesh. What em.init(mesh, topologyOptions) then applyRepair(em, plan, log) give,
// but when the plan kept its result (RepairOptions::keepResult), `mesh` is its input as the
// plan found it and topologyOptions has no tolerance weld, em takes that result without
// building the input first (O(n) to check the mesh); otherwise an EditableMesh is built
// from `mesh` and the steps run on it. em stays as it was when the options are bad or that
// build fails; when a step fails, em holds what the failed applyRepair left (the mesh
// before that step).
Status applyRepair(const Mesh& mesh, const RepairPlan& plan, EditableMesh& em, RepairLog& log,
                   const TopologyOptions& topologyOptions = {});
// The same, for a caller that wants the repaired mesh as a Mesh (the CLI, which writes it):
// `out` becomes what em.toMesh() gives of the EditableMesh the overload above makes. When it
// takes the plan's result, the plan's run has that mesh already, and no EditableMesh is
// made. `out` changes only on success (the log says which step failed otherwise).
Status applyRepair(const Mesh& mesh, const RepairPlan& plan, Mesh& out, RepairLog& log,
                   const TopologyOptions& topologyOptions = {});

// Undoes the last step of `log` on `em` (which must be in the state after it: same
// fingerprint as the step left) and removes it from the log. InvalidArgument when the
// log is empty or em does not match; nothing changes then.
Status undoRepairStep(EditableMesh& em, RepairLog& log);
// Undoes every step, last first.
Status undoRepair(EditableMesh& em, RepairLog& log);

// The plan and the log as JSON (one object, no newline), as the CLI prints them.
std::string repairPlanJson(const RepairPlan& plan);
std::string repairLogJson(const RepairLog& log);

}  // namespace stltopo
