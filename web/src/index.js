// stltopo, browser (and default) entry. See index.d.ts and docs/JS-API.md.
import { api } from './instance.js';
import { stlError } from './errors.js';

/** Reads an STL file into a welded mesh and its half-edge topology. */
export const loadStl = api.loadStl;

/** Node only: streams a file from disk. In browsers it rejects. */
export async function loadStlFile() {
  throw stlError('invalid-argument', 'loadStlFile() needs Node; use loadStl(file) with a File/Blob');
}

export { StlError } from './errors.js';
export { Mesh, kInvalid, EdgeKind, DEFECT_KINDS } from './mesh.js';
export { extractShell } from './extract-shell.js';
