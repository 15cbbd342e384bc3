// stltopo, browser (and default) entry. See index.d.ts and docs/JS-API.md.
import { createInstance } from './instance.js';
import { stlError } from './errors.js';
import { createEditableMesh, createPlanRepair } from './edit.js';
import { createUnion } from './union.js';

const api = createInstance({ importFull: () => import('./stltopo-full.js'), loadWorker: () => import('./worker.js') });

/** Reads an STL file into a welded mesh and its half-edge topology. */
export const loadStl = api.loadStl;

/** A Mesh (the same object loadStl() gives) from indexed positions and triangles. */
export const fromIndexed = api.fromIndexed;

/** The STL file of a mesh as an async iterator of Uint8Array chunks. */
export const writeStl = api.writeStl;

/** The STL file of a mesh as a Blob (type model/stl), assembled from writeStl()'s chunks. */
export async function toStl(mesh, options) {
  return api.stlBlob(mesh, options);
}

/** Local edits on a copy of a mesh in wasm memory (edit.js, docs/EDITING.md). */
export const EditableMesh = createEditableMesh(api.internal.editModule, api.internal.wasmFailure);

/** A repair plan for a Mesh or an EditableMesh (docs/REPAIR.md); changes nothing. */
export const planRepair = createPlanRepair(EditableMesh);

/** Overlapping closed shells and their boolean union through manifold-3d (union.js, README). */
export const { planUnion, unionShells } = createUnion(api.fromIndexed);

/** Node only: streams a file from disk. In browsers it rejects. */
export async function loadStlFile() {
  throw stlError('invalid-argument', 'loadStlFile() needs Node; use loadStl(file) with a File/Blob');
}

export * from './exports.js';
