// Types for 'stltopo/worker': loadStl in a Web Worker (worker_threads in Node).
import type { StlInput, LoadOptions, WithTopology, WithoutTopology, Mesh, IndexedOptions, WriteOptions } from './index.js';
export { StlError, Mesh, kInvalid, EdgeKind, init, DEFECT_KINDS, GEOMETRY_DEFECT_KINDS, extractShell } from './index.js';
export type {
  StlInput, LoadOptions, WithTopology, WithoutTopology, IfTopology, InitOptions, IndexedOptions, WriteOptions, Stats, Solid,
  Warning, BoundaryLoop, ValidateResult, ErrorCode, WarningCode, Shell, Orientation, DefectKind, Defect, IndexedShell,
} from './index.js';

/** Same as loadStl from 'stltopo', run in a worker; { view } is ignored (arrays are transferred). */
export declare function loadStl(input: StlInput, options?: WithTopology): Promise<Mesh<true>>;
export declare function loadStl(input: StlInput, options: WithoutTopology): Promise<Mesh<false>>;
export declare function loadStl(input: StlInput, options?: LoadOptions): Promise<Mesh>;
/** Node only: the worker reads the file itself. */
export declare function loadStlFile(path: string | URL, options?: WithTopology): Promise<Mesh<true>>;
export declare function loadStlFile(path: string | URL, options: WithoutTopology): Promise<Mesh<false>>;
export declare function loadStlFile(path: string | URL, options?: LoadOptions): Promise<Mesh>;
/** fromIndexed() in a worker (copies of the arrays go there). */
export declare function fromIndexed(
  positions: Float32Array | ArrayLike<number>,
  triangles: Uint32Array | ArrayLike<number>,
  options?: IndexedOptions & { topology?: true },
): Promise<Mesh<true>>;
export declare function fromIndexed(
  positions: Float32Array | ArrayLike<number>,
  triangles: Uint32Array | ArrayLike<number>,
  options: IndexedOptions & { topology: false },
): Promise<Mesh<false>>;
export declare function fromIndexed(
  positions: Float32Array | ArrayLike<number>,
  triangles: Uint32Array | ArrayLike<number>,
  options?: IndexedOptions,
): Promise<Mesh>;
/** writeStl() in a worker: the chunks are written there and transferred back one at a time. */
export declare function writeStl(mesh: Mesh, options?: WriteOptions): AsyncIterableIterator<Uint8Array>;
/** toStl() written in a worker: a Blob in browsers, a Uint8Array in Node. */
export declare function toStl(mesh: Mesh, options?: WriteOptions): Promise<Blob | Uint8Array>;
