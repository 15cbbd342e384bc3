// The wasm instance of this thread in Node: the functions behind the public entry
// (node.js) and the hooks that are not public (the worker thread, the npm CLI, tests).
// Node reads the .wasm with fs (the Emscripten 3.1.6 ES-module glue cannot locate it by
// itself under Node).
import { readFile } from 'node:fs/promises';
import createStltopoModule from './stltopo-wasm.js';
import { createStltopo } from './wasm.js';

export { fileSource } from './file-source.js';

const wasmUrl = new URL('./stltopo-wasm.wasm', import.meta.url);
let wasmBytes = null;

export const api = createStltopo({
  instantiate: async (extra) => {
    wasmBytes ??= await readFile(wasmUrl);
    return createStltopoModule({ ...extra, wasmBinary: wasmBytes });
  },
  loadWorker: () => import('./worker.node.js'),
});
