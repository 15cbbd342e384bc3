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
export type {
  StlInput, LoadOptions, WithTopology, WithoutTopology, IfTopology, InitOptions, IndexedOptions, WriteOptions, Stats, Solid,
  Warning, BoundaryLoop, ValidateResult, ErrorCode, WarningCode, Shell, Orientation, DefectKind, Defect, IndexedShell,
} from './index.js';
