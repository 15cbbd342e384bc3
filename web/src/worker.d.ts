// Types for 'stltopo/worker': the API of 'stltopo' (index.d.ts, re-exported here) run in a
// Web Worker (worker_threads in Node), without EditableMesh. There, loadStl() ignores
// { view } (the arrays are transferred); loadStlFile() (Node only) reads the file in the
// worker; fromIndexed() sends copies of the arrays there; writeStl() writes the chunks
// there and transfers them back one at a time; toStl() is a Blob in browsers, a Uint8Array
// in Node.
export {
  loadStl, loadStlFile, fromIndexed, writeStl, toStl,
  StlError, Mesh, kInvalid, EdgeKind, init, DEFECT_KINDS, GEOMETRY_DEFECT_KINDS, extractShell, REPAIR_STEPS, REPAIR_DEFAULTS,
} from './index.js';
import type { Mesh as MeshT, LoadOptions as LoadOptionsT, RepairOptions as RepairOptionsT, RepairPlan as RepairPlanT,
  RepairLog as RepairLogT } from './index.js';
/** A repair plan for a Mesh, made in a worker (docs/REPAIR.md); changes nothing. */
export declare function planRepair(mesh: MeshT, options?: RepairOptionsT): Promise<RepairPlanT>;
/**
 * Carries a plan out in a worker on a copy of the mesh: the repaired Mesh (loaded with
 * loadOptions) and the change log. The input mesh is unchanged: keeping it is the undo.
 */
export declare function applyRepair(mesh: MeshT, plan: RepairPlanT, loadOptions?: LoadOptionsT): Promise<{ mesh: MeshT; log: RepairLogT }>;
export type {
  RepairOptions, RepairPlan, RepairLog, RepairStep, RepairFigures, RepairItem, RepairStepLog,
  StlInput, LoadOptions, WithTopology, WithoutTopology, IfTopology, InitOptions, IndexedOptions, WriteOptions, Stats, Solid,
  Warning, BoundaryLoop, ValidateResult, ErrorCode, WarningCode, Shell, Orientation, DefectKind, Defect, IndexedShell,
} from './index.js';
