// stltopo, browser (and default) entry. The .wasm is fetched next to this file
// (new URL('./stltopo-wasm.wasm', import.meta.url)), which bundlers understand.
import createStltopoModule from './stltopo-wasm.js';
import { createStltopo, StlError, Mesh, kInvalid, EdgeKind } from './core.js';
import { createEditableMesh, kLoopFaceBit } from './edit.js';

const api = createStltopo({
  instantiate: (extra) => createStltopoModule(extra),
  loadWorker: () => import('./worker.js'),
});

/**
 * Reads an STL file into a welded mesh and its half-edge topology.
 * See index.d.ts and docs/JS-API.md.
 */
export const loadStl = api.loadStl;

/** Local edits on a copy of a mesh in wasm memory (edit.js, docs/EDITING.md). */
export const EditableMesh = createEditableMesh(api.internal.getModule);
export { kLoopFaceBit };

/** Node only: streams a file from disk. In browsers it rejects. */
export async function loadStlFile() {
  throw new StlError('invalid-argument', 'invalid-argument: loadStlFile() needs Node; use loadStl(file) with a File/Blob');
}

export { StlError, Mesh, kInvalid, EdgeKind };
/** @internal test and CLI hooks */
export const _internal = api.internal;
