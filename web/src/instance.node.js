// The wasm instance of this thread in Node: the functions behind the public entry
// (node.js) and the hooks that are not public (the worker thread, the npm CLI, tests).
// The glue is the browser one (it has no Node code); Node hands it the .wasm bytes, read
// with fs from init()'s wasmUrl (a file: URL or a path; http(s) URLs are fetched), else
// from next to this file, or init()'s wasmBinary; the same for stltopo-full.wasm (fullWasmUrl,
// fullWasmBinary). The two modules are used as in browsers (web/src/wasm.js).
import { readFile } from 'node:fs/promises';
import { availableParallelism } from 'node:os';
import { pathToFileURL } from 'node:url';
import createStltopoModule from './stltopo-wasm.js';
import { createStltopo } from './wasm.js';
import createStltopoFullModule from './stltopo-full.js';
import { instantiateModule, moduleSettings, wasmSettings } from './wasm-load.js';
import { threadedFiles, threadedModuleOptions } from './threads.js';
import { stlError } from './errors.js';

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

// A Web Worker as the threaded glue uses one (new Worker(url), onmessage, onerror,
// postMessage, terminate), on worker_threads: pthread-node.js runs the glue's worker script.
// Unref'd once loaded, so that an idle pool never keeps Node running (a load blocks the main
// thread while the pool works, so nothing is cut short). NodeWorker is worker_threads' Worker,
// imported by the first threaded instantiation (a process without threads never loads it).
let NodeWorker = null;
class PoolWorker {
  constructor(url) {
    this.onmessage = null;
    this.onerror = null;
    this.errorListeners = [];
    this.worker = new NodeWorker(new URL('./pthread-node.js', import.meta.url), {
      workerData: { script: String(url) },
      execArgv: [], // not the process's (--input-type, --eval and the like fail in a worker)
    });
    this.worker.on('message', (data) => {
      if (data && data.cmd === 'loaded') this.worker.unref();
      if (this.onmessage) this.onmessage({ data });
    });
    this.worker.on('error', (e) => {
      for (const fn of this.errorListeners) fn(e);
      try {
        if (this.onerror) this.onerror(e); // the glue's handler reports it (printErr), then rethrows
      } catch {
        // reported: the instantiation fails with wasm-load (wasm-load.js)
      }
    });
  }
  addEventListener(type, fn) {
    if (type === 'error') this.errorListeners.push(fn);
  }
  postMessage(msg, transfer) { this.worker.postMessage(msg, transfer); }
  terminate() { this.worker.terminate(); }
}

// The directory of the threaded modules: init()'s threadsUrl (a file: URL or a path), else
// next to this file.
function threadsBase() {
  const { threadsUrl } = wasmSettings();
  if (!threadsUrl) return new URL('./', import.meta.url);
  const dir = threadsUrl.endsWith('/') ? threadsUrl : `${threadsUrl}/`;
  return /^[a-z][a-z0-9+.-]*:/i.test(dir) && !/^[a-z]:/i.test(dir) ? new URL(dir) : pathToFileURL(dir);
}

// The threaded module of kind ('wasm', 'full') with a pool of `pool` workers. The glue reads
// the global Worker while the factory runs (the pool is made then); Node has none, so
// PoolWorker is it for that call only (instantiateModule).
async function instantiateThreaded(kind, pool, extra) {
  const files = threadedFiles(kind);
  const base = threadsBase();
  const glue = new URL(files.glue, base);
  let create;
  try {
    ({ default: create } = await import(glue.href));
  } catch (e) {
    throw stlError('wasm-load', `cannot import ${glue.href}, the glue of the threaded module: ${e && e.message}`);
  }
  const wasm = new URL(files.wasm, base);
  const source = { url: wasm.href, read: () => readFile(wasm) };
  const options = { ...extra, ...threadedModuleOptions(pool, new URL(files.worker, base).href, glue.href) };
  NodeWorker ??= (await import('node:worker_threads')).Worker;
  return instantiateModule(create, source, options, { threaded: true, Worker: PoolWorker });
}

export const api = createStltopo({
  instantiate: (extra) => instantiateModule(createStltopoModule, wasmSource('wasm'), extra),
  instantiateFull: (extra) => instantiateModule(createStltopoFullModule, wasmSource('full'), extra),
  loadWorker: () => import('./worker.node.js'),
  instantiateThreaded,
  // Node: one thread unless asked (the pool's start, ~50-100 ms per worker, is paid by
  // the first threaded load; a CLI run of one file gains less than that).
  defaultThreads: () => 1,
  cores: () => availableParallelism(),
});
