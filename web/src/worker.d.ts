// Types for 'stltopo/worker': loadStl in a Web Worker (worker_threads in Node).
import type { StlInput, LoadOptions, WithTopology, WithoutTopology, Mesh } from './index.js';
export { StlError, Mesh, kInvalid, EdgeKind, init } from './index.js';
export type {
  StlInput, LoadOptions, WithTopology, WithoutTopology, IfTopology, InitOptions, Stats, Solid, Warning, BoundaryLoop,
  ValidateResult, ErrorCode, WarningCode,
} from './index.js';

/** Same as loadStl from 'stltopo', run in a worker; { view } is ignored (arrays are transferred). */
export declare function loadStl(input: StlInput, options?: WithTopology): Promise<Mesh<true>>;
export declare function loadStl(input: StlInput, options: WithoutTopology): Promise<Mesh<false>>;
export declare function loadStl(input: StlInput, options?: LoadOptions): Promise<Mesh>;
/** Node only: the worker reads the file itself. */
export declare function loadStlFile(path: string | URL, options?: WithTopology): Promise<Mesh<true>>;
export declare function loadStlFile(path: string | URL, options: WithoutTopology): Promise<Mesh<false>>;
export declare function loadStlFile(path: string | URL, options?: LoadOptions): Promise<Mesh>;
