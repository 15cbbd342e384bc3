// What every entry (index.js, node.js, worker.js, worker.node.js) exports alike: each
// re-exports this module, then adds its own loadStl, fromIndexed, writeStl, toStl (and
// loadStlFile, EditableMesh) for where it runs. index.d.ts and worker.d.ts type them.
export { init } from './wasm-load.js';
export { StlError } from './errors.js';
export { Mesh, kInvalid, EdgeKind, DEFECT_KINDS, GEOMETRY_DEFECT_KINDS } from './mesh.js';
export { extractShell } from './extract-shell.js';
export { REPAIR_STEPS, REPAIR_DEFAULTS } from './options.js';
