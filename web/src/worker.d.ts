// Types for 'stltopo/worker': loadStl in a Web Worker (worker_threads in Node).
import type { StlInput, LoadOptions, Mesh } from './index.js';
export { StlError, Mesh, kInvalid, EdgeKind, DEFECT_KINDS, extractShell } from './index.js';
export type { StlInput, LoadOptions, Stats, Solid, Warning, BoundaryLoop, ValidateResult, ErrorCode, WarningCode, Shell,
  Orientation, DefectKind, Defect, IndexedShell } from './index.js';

/** Same as loadStl from 'stltopo', run in a worker; { view } is ignored (arrays are transferred). */
export declare function loadStl(input: StlInput, options?: LoadOptions): Promise<Mesh>;
/** Node only: the worker reads the file itself. */
export declare function loadStlFile(path: string | URL, options?: LoadOptions): Promise<Mesh>;
