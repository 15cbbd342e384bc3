// Threads (issue 24): when a load runs in the threaded wasm modules (stltopo-wasm-mt,
// stltopo-full-mt: pthreads, shared memory) and with how many threads. Those modules need
// SharedArrayBuffer, which browsers give only to cross-origin isolated pages (the server
// sends COOP `same-origin` and COEP `require-corp`); Node always has it. Everything else
// (and `threads: 1`) uses the single-threaded modules: the same API and the same results.
//
// The threaded module's worker pool is preallocated when the module is instantiated (a
// thread cannot start while the load's thread blocks in a fork-join): its size is the
// threads of the first threaded load, minus the calling thread. Later loads that ask for
// more threads run on that many (mesh.threads says how many were used).

/** The most threads a load uses (the core's kMaxThreads, src/parallel.h). */
export const MAX_THREADS = 64;

/** Whether this thread can run the threaded modules: shared memory, and in browsers isolation. */
export function threadsAllowed() {
  if (typeof SharedArrayBuffer !== 'function' || typeof Atomics !== 'object') return false;
  if (typeof process === 'object' && process.versions && process.versions.node) return true;
  return globalThis.crossOriginIsolated === true;
}

/** The machine's logical cores as this thread sees them (1 when unknown). */
export function machineCores() {
  const n = typeof navigator !== 'undefined' && navigator.hardwareConcurrency;
  return Number.isInteger(n) && n > 0 ? n : 1;
}

/**
 * The threads a load with options o runs on. o.threads: null = the default (`dflt()`:
 * in browsers what the page allows, in Node 1), 0 = the machine's cores, else that number;
 * capped at MAX_THREADS, and 1 when the threaded modules cannot run here.
 */
export function threadsFor(o, dflt, cores = machineCores) {
  if (!threadsAllowed()) return 1;
  let t = o && o.threads !== null && o.threads !== undefined ? o.threads : dflt();
  if (t === 0) t = cores();
  return Math.max(1, Math.min(MAX_THREADS, t));
}

/** The browser default: the cores when the page is cross-origin isolated, else 1. */
export const browserDefaultThreads = () => (threadsAllowed() ? machineCores() : 1);

/** The module file names of kind 'wasm' (the core) or 'full': { glue, wasm, worker }. */
export function threadedFiles(kind) {
  const base = `stltopo-${kind}-mt`;
  return { glue: `${base}.js`, wasm: `${base}.wasm`, worker: `${base}.worker.js` };
}

/**
 * The options of a threaded module's factory besides instantiateWasm: the pool size
 * (Module.stltopoPoolSize, read by the glue's PTHREAD_POOL_SIZE; at least 1), where its
 * worker script is (locateFile) and the URL of its glue, which each worker imports.
 */
export function threadedModuleOptions(pool, workerUrl, glueUrl) {
  return {
    stltopoPoolSize: Math.max(1, pool),
    locateFile: (path) => (path.endsWith('.worker.js') ? workerUrl : path),
    mainScriptUrlOrBlob: glueUrl,
  };
}
