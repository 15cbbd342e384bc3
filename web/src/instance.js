// The wasm instance of this thread in browsers and workers: the functions behind the
// public entry (index.js) and the hooks that are not public (the worker thread, tests).
// The .wasm is fetched next to this file (new URL('./stltopo-wasm.wasm', import.meta.url)),
// which bundlers understand.
import createStltopoModule from './stltopo-wasm.js';
import { createStltopo } from './wasm.js';

export const api = createStltopo({
  instantiate: (extra) => createStltopoModule(extra),
  loadWorker: () => import('./worker.js'),
});
