// The wasm instance of this thread in Node: the functions behind the public entry
// (node.js) and the hooks that are not public (the worker thread, the npm CLI, tests).
// The glue is the browser one (it has no Node code); Node hands it the .wasm bytes, read
// with fs from init()'s wasmUrl (a file: URL or a path; http(s) URLs are fetched), else
// from next to this file, or init()'s wasmBinary.
import { readFile } from 'node:fs/promises';
import createStltopoModule from './stltopo-wasm.js';
import { createStltopo } from './wasm.js';
import { instantiateModule, wasmSettings } from './wasm-load.js';

export { fileSource } from './file-source.js';

const defaultWasm = new URL('./stltopo-wasm.wasm', import.meta.url);
let defaultBytes = null;

function wasmSource() {
  const { wasmBinary, wasmUrl } = wasmSettings();
  if (wasmBinary) return { binary: wasmBinary };
  if (wasmUrl && /^https?:/.test(wasmUrl)) return { url: wasmUrl };
  if (wasmUrl) return { url: wasmUrl, read: () => readFile(wasmUrl.startsWith('file:') ? new URL(wasmUrl) : wasmUrl) };
  return { url: defaultWasm.href, read: async () => (defaultBytes ??= await readFile(defaultWasm)) };
}

export const api = createStltopo({
  instantiate: (extra) => instantiateModule(createStltopoModule, wasmSource(), extra),
  loadWorker: () => import('./worker.node.js'),
});
