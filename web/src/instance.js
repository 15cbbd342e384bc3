// The wasm instance of a browser thread (the page or a worker): the functions behind the
// public entry (index.js) and the worker thread (worker-thread.js). This module starts no
// worker itself, so the worker's bundle has no dynamic import (every bundler's default
// worker format, iife included, can build it). The .wasm is fetched from init()'s wasmUrl,
// else next to this file (new URL('./stltopo-wasm.wasm', import.meta.url), which bundlers
// understand), or taken from init()'s wasmBinary.
import createStltopoModule from './stltopo-wasm.js';
import { createStltopo } from './wasm.js';
import { instantiateModule, wasmSettings } from './wasm-load.js';

/** A wasm instance for this thread; loadWorker (main thread only) imports stltopo/worker. */
export function createInstance(loadWorker = null) {
  return createStltopo({
    instantiate(extra) {
      const { wasmBinary, wasmUrl } = wasmSettings();
      const source = wasmBinary ? { binary: wasmBinary } : { url: wasmUrl || new URL('./stltopo-wasm.wasm', import.meta.url).href };
      return instantiateModule(createStltopoModule, source, extra);
    },
    loadWorker,
  });
}
