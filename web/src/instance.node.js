// The wasm instance of this thread in Node: the functions behind the public entry
// (node.js) and the hooks that are not public (the worker thread, the npm CLI, tests).
// The glue is the browser one (it has no Node code); Node hands it the .wasm bytes, read
// with fs from init()'s wasmUrl (a file: URL or a path; http(s) URLs are fetched), else
// from next to this file, or init()'s wasmBinary; the same for stltopo-full.wasm (fullWasmUrl,
// fullWasmBinary). The two modules are used as in browsers (web/src/wasm.js).
import { readFile } from 'node:fs/promises';
import createStltopoModule from './stltopo-wasm.js';
import { createStltopo } from './wasm.js';
import createStltopoFullModule from './stltopo-full.js';
import { instantiateModule, moduleSettings } from './wasm-load.js';

export { fileSource } from './file-source.js';

const defaults = { wasm: new URL('./stltopo-wasm.wasm', import.meta.url), full: new URL('./stltopo-full.wasm', import.meta.url) };
const defaultBytes = {};

function wasmSource(module) {
  const { binary, url } = moduleSettings(module);
  if (binary) return { binary };
  if (url && /^https?:/.test(url)) return { url };
  if (url) return { url, read: () => readFile(url.startsWith('file:') ? new URL(url) : url) };
  return { url: defaults[module].href, read: async () => (defaultBytes[module] ??= await readFile(defaults[module])) };
}

export const api = createStltopo({
  instantiate: (extra) => instantiateModule(createStltopoModule, wasmSource('wasm'), extra),
  instantiateFull: (extra) => instantiateModule(createStltopoFullModule, wasmSource('full'), extra),
  loadWorker: () => import('./worker.node.js'),
});
