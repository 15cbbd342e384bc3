// The wasm instances of a browser thread (the page or a worker): the functions behind the
// public entry (index.js) and the worker thread (worker-thread.js). This module starts no
// worker and imports nothing dynamically itself, so the worker's bundle has no dynamic
// import (every bundler's default worker format, iife included, can build it).
// Two modules (bindings/CMakeLists.txt): the core stltopo-wasm, fetched on the first load,
// and stltopo-full, fetched on the first use of what only it has (shells and defects,
// fromIndexed, writing, EditableMesh). Each .wasm comes from init()'s URL or bytes, else
// from next to this file (new URL('./….wasm', import.meta.url), which bundlers understand).
import createStltopoModule from './stltopo-wasm.js';
import { createStltopo } from './wasm.js';
import { instantiateModule, browserSource, wasmSettings } from './wasm-load.js';
import { stlError } from './errors.js';
import { browserDefaultThreads, threadedFiles, threadedModuleOptions } from './threads.js';

// The threaded module of kind ('wasm', 'full') with a pool of `pool` workers, from
// init()'s threadsUrl, else next to this file. Its glue is imported at run time from that
// URL (bundlers leave it alone: a bundle that does not serve the files falls back to the
// single-threaded module, see wasm.js); each pool worker imports the same glue.
async function instantiateThreaded(kind, pool, extra) {
  const files = threadedFiles(kind);
  // (No new URL('./…', import.meta.url) literal here: bundlers would take it for an asset.)
  const base = wasmSettings().threadsUrl || import.meta.url;
  const glue = new URL(files.glue, base).href;
  let create;
  try {
    ({ default: create } = await import(/* webpackIgnore: true */ /* @vite-ignore */ glue));
  } catch (e) {
    throw stlError('wasm-load', `cannot import ${glue}, the glue of the threaded module: ${e && e.message}`);
  }
  const options = { ...extra, ...threadedModuleOptions(pool, new URL(files.worker, base).href, glue) };
  return instantiateModule(create, { url: new URL(files.wasm, base).href }, options, { threaded: true });
}

/**
 * A wasm instance pair for this thread. importFull() resolves to the full module's glue
 * (the page imports it when first needed; a worker, which must not import dynamically,
 * passes its static import). loadWorker (main thread only) imports stltopo/worker.
 */
export function createInstance({ importFull, loadWorker = null }) {
  return createStltopo({
    instantiate(extra) {
      const source = browserSource('wasm', () => new URL('./stltopo-wasm.wasm', import.meta.url).href);
      return instantiateModule(createStltopoModule, source, extra);
    },
    async instantiateFull(extra) {
      let create;
      try {
        ({ default: create } = await importFull());
      } catch (e) {
        throw stlError('wasm-load', `cannot import stltopo-full.js, the glue of the full module: ${e && e.message}`);
      }
      const source = browserSource('full', () => new URL('./stltopo-full.wasm', import.meta.url).href);
      return instantiateModule(create, source, extra);
    },
    loadWorker,
    instantiateThreaded,
    defaultThreads: browserDefaultThreads,
  });
}
