// Types for 'stltopo/worker': the API of 'stltopo' (index.d.ts, re-exported here) run in a
// Web Worker (worker_threads in Node), without EditableMesh; WorkerEditableMesh holds one in
// a worker for repair with undo. There, loadStl() ignores { view } (the arrays are
// transferred); loadStlFile() (Node only) reads the file in the worker; fromIndexed() sends
// copies of the arrays there; writeStl() writes the chunks there and transfers them back one
// at a time; toStl() is a Blob in browsers, a Uint8Array in Node.
export {
  loadStl, loadStlFile, fromIndexed, writeStl, toStl,
  StlError, Mesh, kInvalid, EdgeKind, init, DEFECT_KINDS, GEOMETRY_DEFECT_KINDS, extractShell, REPAIR_STEPS, REPAIR_DEFAULTS,
  planUnion, unionShells,
} from './index.js';
import type { Mesh as MeshT, LoadOptions as LoadOptionsT, RepairOptions as RepairOptionsT, RepairPlan as RepairPlanT,
  RepairLog as RepairLogT, RepairStep as RepairStepT, EditableMesh as EditableMeshT, IndexedMeshInput as IndexedMeshInputT,
  IndexedOptions as IndexedOptionsT, WriteOptions as WriteOptionsT, Stats as StatsT, ValidateResult as ValidateResultT,
} from './index.js';
/**
 * A repair plan made in a worker (docs/REPAIR.md); changes nothing. A Mesh is copied there;
 * a WorkerEditableMesh is planned where it is held.
 */
export declare function planRepair(mesh: MeshT | WorkerEditableMesh, options?: RepairOptionsT): Promise<RepairPlanT>;
/**
 * Carries a plan out in a worker on a copy of the mesh: the repaired Mesh (loaded with
 * loadOptions) and the change log. The input mesh is unchanged: keeping it is the undo of the
 * whole repair; WorkerEditableMesh undoes step by step.
 */
export declare function applyRepair(mesh: MeshT, plan: RepairPlanT, loadOptions?: LoadOptionsT): Promise<{ mesh: MeshT; log: RepairLogT }>;
/**
 * An EditableMesh held in a worker between calls, for repair with step-by-step undo off the
 * main thread (docs/REPAIR.md). Each call is sent to the worker and answered there, one at a
 * time in the order made; it rejects with the StlError the main thread's EditableMesh throws
 * (a refused call changes nothing). Each mesh holds a worker of its own until dispose(); one
 * that is garbage-collected without dispose() is freed eventually.
 */
export declare class WorkerEditableMesh {
  /** A copy of the source in a worker (EditableMesh.from()'s sources and options). */
  static from(source: MeshT | IndexedMeshInputT, options?: { tolerance?: number }): Promise<WorkerEditableMesh>;
  readonly format: EditableMeshT['format'];
  readonly colorConvention: EditableMeshT['colorConvention'];
  /** EditableMesh.planRepair(), in the worker (the plan's id lists are transferred). */
  planRepair(options?: RepairOptionsT): Promise<RepairPlanT>;
  /** EditableMesh.applyRepair(), in the worker: the change log. */
  applyRepair(plan: RepairPlanT): Promise<RepairLogT>;
  /** Undoes the last repair step still applied: its name, or null when there is none. */
  undo(): Promise<RepairStepT | null>;
  /** How many repair steps undo() can still take back, as of the last call that settled. */
  readonly undoableSteps: number;
  /** The figures of `info --json` for the mesh (EditableMesh.stats). */
  stats(): Promise<StatsT<true>>;
  validate(): Promise<ValidateResultT>;
  /** The STL file of the mesh, whole (EditableMesh.toStl(); the bytes are transferred). */
  toStl(options?: WriteOptionsT): Promise<Uint8Array>;
  /**
   * The mesh as a Mesh with the editable mesh's ids: fromIndexed() of its positions,
   * triangles and attribute words without a weld, in the worker (the arrays are transferred).
   * Colours are the attribute words read as VisCAM's (a Magics file's: loadStl(await toStl())).
   */
  toMesh(options?: Omit<IndexedOptionsT, 'weld' | 'attributes' | 'colors' | 'colorValid' | 'solids'> & { topology?: true }): Promise<MeshT<true>>;
  toMesh(options: Omit<IndexedOptionsT, 'weld' | 'attributes' | 'colors' | 'colorValid' | 'solids'> & { topology: false }): Promise<MeshT<false>>;
  /** Frees the mesh in the worker after the calls already made; every later call is refused. */
  dispose(): Promise<void>;
}
export type {
  RepairOptions, RepairPlan, RepairLog, RepairStep, RepairFigures, RepairItem, RepairStepLog,
  StlInput, LoadOptions, WithTopology, WithoutTopology, IfTopology, InitOptions, IndexedOptions, WriteOptions, Stats, Solid,
  Warning, BoundaryLoop, ValidateResult, ErrorCode, WarningCode, Shell, Orientation, DefectKind, Defect, IndexedShell,
  UnionGroup, UnionOptions,
} from './index.js';
