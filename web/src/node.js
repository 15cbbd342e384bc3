// stltopo, Node entry: the same API as index.js, plus loadStlFile(path).
import { api, fileSource } from './instance.node.js';
import { stlError } from './errors.js';
import { createEditableMesh, createPlanRepair } from './edit.js';
import { createUnion } from './union.js';
import { normalizeOptions } from './options.js';

export const loadStl = api.loadStl;
export const fromIndexed = api.fromIndexed;
export const writeStl = api.writeStl;

/** Node: the STL file of a mesh as one Uint8Array (writeStl() streams it instead). */
export async function toStl(mesh, options) {
  return api.stlBytes(mesh, options);
}

/** Local edits on a copy of a mesh in wasm memory (edit.js, docs/EDITING.md). */
export const EditableMesh = createEditableMesh(api.internal.editModule, api.internal.wasmFailure);

/** A repair plan for a Mesh or an EditableMesh (docs/REPAIR.md); changes nothing. */
export const planRepair = createPlanRepair(EditableMesh);

/** Overlapping closed shells and their boolean union through manifold-3d (union.js, README). */
export const { planUnion, unionShells } = createUnion(api.fromIndexed);

/** Node only: reads an STL file from disk, streaming it to the core. */
export async function loadStlFile(path, options) {
  if (options && options.worker) return (await import('./worker.node.js')).loadStlFile(path, { ...options, worker: false });
  const o = normalizeOptions(options);
  let source;
  try {
    source = await fileSource(path);
  } catch (e) {
    throw stlError('invalid-argument', `cannot open ${path}: ${e.message}`);
  }
  return api.loadFromSource(source, o);
}

export * from './exports.js';
