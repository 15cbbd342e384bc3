// Where the wasm module and the worker script come from (init() and the defaults next to
// this package's files), and the one way the .wasm is fetched and compiled. Every failure
// to get or compile it is an StlError 'wasm-load' whose message names the URL and what
// came back: the HTTP status, the content type and the first bytes.
import { stlError } from './errors.js';

const settings = { wasmUrl: null, wasmBinary: null, workerUrl: null, fullWasmUrl: null, fullWasmBinary: null, threadsUrl: null };

const isUrl = (v) => typeof v === 'string' || v instanceof URL;

// URLs are resolved against the page (or the worker script), so that workers get the same
// ones; in Node, where there is no page, a string that is no URL is a path.
function absolute(v) {
  if (v === null) return null;
  const base = typeof location !== 'undefined' ? location.href : undefined;
  try {
    return new URL(v, base).href;
  } catch {
    if (base === undefined) return String(v);
    throw stlError('invalid-argument', `init(): ${v} is not a URL`);
  }
}

/**
 * Sets where the wasm and the worker come from, for bundlers and servers that do not
 * serve them next to the package's files. Applies to the wasm instances and workers
 * started after the call (call it before the first load).
 *   wasmUrl     URL (or string, resolved against the page) of stltopo-wasm.wasm
 *   wasmBinary  the bytes of stltopo-wasm.wasm (ArrayBuffer or Uint8Array)
 *   workerUrl   URL of the worker script (stltopo's dist/worker-thread.js, served)
 *   fullWasmUrl, fullWasmBinary  the same for stltopo-full.wasm, the module of shells and
 *               defects, fromIndexed(), writing and EditableMesh (fetched on their first use)
 *   threadsUrl  URL of the directory that serves the threaded modules (stltopo-wasm-mt.js,
 *               .wasm, .worker.js and the same of stltopo-full-mt), for loads with threads
 * An option left out keeps its value; null restores the default.
 */
export function init(options = {}) {
  if (options === null || typeof options !== 'object') throw stlError('invalid-argument', 'init() takes an object');
  for (const key of Object.keys(options)) {
    if (!(key in settings)) throw stlError('invalid-argument', `init(): unknown option ${key}`);
  }
  const urls = ['wasmUrl', 'workerUrl', 'fullWasmUrl', 'threadsUrl'].filter((k) => options[k] !== undefined);
  const binaries = ['wasmBinary', 'fullWasmBinary'].filter((k) => options[k] !== undefined);
  for (const k of urls) {
    if (options[k] !== null && !isUrl(options[k])) throw stlError('invalid-argument', `init(): ${k} must be a string or a URL`);
  }
  for (const k of binaries) {
    const v = options[k];
    if (v !== null && !(v instanceof ArrayBuffer || ArrayBuffer.isView(v))) {
      throw stlError('invalid-argument', `init(): ${k} must be an ArrayBuffer or a Uint8Array`);
    }
  }
  const resolved = urls.map((k) => [k, absolute(options[k])]); // may throw: nothing is set then
  for (const [k, v] of resolved) settings[k] = v;
  for (const k of binaries) {
    const v = options[k];
    settings[k] = v === null ? null
      : ArrayBuffer.isView(v) ? new Uint8Array(v.buffer, v.byteOffset, v.byteLength) : new Uint8Array(v);
  }
}

/** The current init() settings (the worker client hands the wasm ones to its workers). */
export const wasmSettings = () => ({ ...settings });

/**
 * Where the wasm of a module comes from in browsers: { binary } from init(), else { url }
 * from init() or `fallback` (the default URL next to the package's files).
 * module: 'wasm' (stltopo-wasm, the core) or 'full' (stltopo-full).
 */
export function browserSource(module, fallback) {
  const { binary, url } = moduleSettings(module);
  return binary ? { binary } : { url: url || fallback() };
}

/** init()'s { url, binary } of a module ('wasm' or 'full'). */
export function moduleSettings(module) {
  return module === 'full' ? { url: settings.fullWasmUrl, binary: settings.fullWasmBinary }
    : { url: settings.wasmUrl, binary: settings.wasmBinary };
}

/**
 * One wasm instance at a time, created on first use and again after it aborted: the
 * getter resolves to an entry { module, dead, lastError } (plus what setup() adds).
 * instantiate(extra) returns the module's promise (instantiateModule).
 */
export function lazyModule(instantiate, setup = () => {}) {
  let current = null;
  const getModule = () => {
    if (!current || current.dead) {
      const entry = { module: null, dead: false, lastError: '' };
      entry.promise = instantiate({
        onAbort(what) { entry.dead = true; entry.lastError = String(what || ''); },
        printErr(text) { entry.lastError = String(text); },
        print() {},
      }).then(
        (m) => {
          entry.module = m;
          setup(entry, m);
          return entry;
        },
        (e) => {
          if (current === entry) current = null;
          throw e;
        },
      );
      current = entry;
    }
    return current.promise;
  };
  /** The entry made last (null before the first call), loaded or not. */
  getModule.current = () => current;
  /** Forgets an entry that died, so that the next getModule() makes a new one. */
  getModule.drop = (entry) => {
    if (current === entry) current = null;
  };
  return getModule;
}

const MAGIC = [0x00, 0x61, 0x73, 0x6d]; // "\0asm"

function firstBytes(bytes) {
  const head = bytes.subarray(0, 8);
  const hex = [...head].map((b) => b.toString(16).padStart(2, '0')).join(' ');
  const text = String.fromCharCode(...head).replace(/[^\x20-\x7e]/g, '.');
  return bytes.length ? `first bytes ${hex} "${text}"` : 'no bytes';
}

/** What a response held, for the messages: "HTTP 404 (text/html), first bytes ...". */
export function describeResponse(response, bytes) {
  const type = response.headers.get('content-type') || 'no content type';
  return `HTTP ${response.status} (${type}), ${bytes ? firstBytes(bytes) : 'no body read'}`;
}

/** Fetches a URL and describes what came back (a worker that failed to start). */
export async function describeUrl(url) {
  try {
    const response = await fetch(url);
    const bytes = new Uint8Array(await response.arrayBuffer());
    return describeResponse(response, bytes);
  } catch (e) {
    return `the request failed (${e && e.message})`;
  }
}

async function fetchWasm(url) {
  let response;
  try {
    response = await fetch(url, { credentials: 'same-origin' });
  } catch (e) {
    throw stlError('wasm-load', `cannot fetch the WebAssembly module ${url}: ${e && e.message}`);
  }
  let bytes;
  try {
    bytes = new Uint8Array(await response.arrayBuffer());
  } catch (e) {
    throw stlError('wasm-load', `cannot read the WebAssembly module ${url}: HTTP ${response.status} (${e && e.message})`);
  }
  if (!response.ok || !MAGIC.every((b, i) => bytes[i] === b)) {
    throw stlError('wasm-load', `${url} is not the WebAssembly module: ${describeResponse(response, bytes)}`);
  }
  return bytes;
}

async function compile(bytes, imports, where) {
  if (!MAGIC.every((b, i) => bytes[i] === b)) throw stlError('wasm-load', `${where} is not a WebAssembly module: ${firstBytes(bytes)}`);
  try {
    return await WebAssembly.instantiate(bytes, imports);
  } catch (e) {
    throw stlError('wasm-load', `cannot compile the WebAssembly module ${where}: ${e && e.message}`);
  }
}

/**
 * Instantiates the Emscripten factory with the wasm from `source`: { binary } (bytes),
 * { url } (fetched) or { read } (an async function that returns the bytes, Node's fs).
 * Resolves to the module, or rejects with StlError 'wasm-load'.
 */
export function instantiateModule(createModule, source, extra, { threaded = false, Worker: WorkerClass = null } = {}) {
  let fail;
  const failed = new Promise((resolve, reject) => { fail = reject; });
  const where = source.binary ? 'wasmBinary' : String(source.url);
  // A threaded module waits for its pool's workers, forever when one fails to start (its
  // script not served, or blocked: a worker script of an isolated page needs COEP itself).
  // The glue sees such an error only once the wasm is compiled, and reports it by printErr;
  // an error before that would be lost, so every pool worker gets a listener of its own.
  const workerFailed = (what) => fail(stlError('wasm-load', `a worker of the threaded module ${where} failed to start: ${what}`));
  const printErr = threaded ? (text) => {
    if (/^worker sent an error/.test(String(text))) workerFailed(text);
    if (extra && extra.printErr) extra.printErr(text);
  } : extra && extra.printErr;
  const Base = threaded ? WorkerClass || globalThis.Worker : null;
  const had = threaded ? Object.getOwnPropertyDescriptor(globalThis, 'Worker') : null;
  if (threaded) {
    if (typeof Base !== 'function') return Promise.reject(stlError('wasm-load', 'no Worker here: the threaded module needs one'));
    // The glue makes its pool while the factory runs (PTHREAD_POOL_SIZE), with the global Worker.
    globalThis.Worker = class PoolWorker extends Base {
      constructor(...args) {
        super(...args);
        this.addEventListener('error', (e) => workerFailed(e && e.message ? e.message : `the script ${args[0]} did not load`));
      }

      // The glue's error handler reports the error, then rethrows it: an uncaught exception
      // of the page. Reported is enough (the instantiation fails with wasm-load).
      get onerror() { return this.stltopoOnError ?? null; }

      set onerror(fn) {
        this.stltopoOnError = fn;
        super.onerror = typeof fn === 'function' ? (e) => {
          try {
            fn.call(this, e);
          } catch {
            // reported through printErr
          }
        } : fn;
      }
    };
  }
  let ready;
  try {
    ready = createModule({
      ...extra,
      ...(printErr ? { printErr } : {}),
      instantiateWasm(imports, receive) {
        const bytes = source.binary ? Promise.resolve(source.binary)
          : source.read ? source.read().catch((e) => { throw stlError('wasm-load', `cannot read the WebAssembly module ${where}: ${e && e.message}`); })
            : fetchWasm(source.url);
        bytes.then((b) => compile(b, imports, where)).then((r) => receive(r.instance, r.module), fail);
        return {};
      },
    });
  } finally {
    if (threaded) {
      if (had) Object.defineProperty(globalThis, 'Worker', had);
      else delete globalThis.Worker;
    }
  }
  // The factory's own promise never settles when instantiateWasm fails: race it.
  return Promise.race([ready, failed]);
}
