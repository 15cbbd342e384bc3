// Where the wasm module and the worker script come from (init() and the defaults next to
// this package's files), and the one way the .wasm is fetched and compiled. Every failure
// to get or compile it is an StlError 'wasm-load' whose message names the URL and what
// came back: the HTTP status, the content type and the first bytes.
import { stlError } from './errors.js';

const settings = { wasmUrl: null, wasmBinary: null, workerUrl: null };

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
 * An option left out keeps its value; null restores the default.
 */
export function init(options = {}) {
  if (options === null || typeof options !== 'object') throw stlError('invalid-argument', 'init() takes an object');
  for (const key of Object.keys(options)) {
    if (!(key in settings)) throw stlError('invalid-argument', `init(): unknown option ${key}`);
  }
  const { wasmUrl, wasmBinary, workerUrl } = options;
  if (wasmUrl !== undefined && wasmUrl !== null && !isUrl(wasmUrl)) throw stlError('invalid-argument', 'init(): wasmUrl must be a string or a URL');
  if (workerUrl !== undefined && workerUrl !== null && !isUrl(workerUrl)) throw stlError('invalid-argument', 'init(): workerUrl must be a string or a URL');
  if (wasmBinary !== undefined && wasmBinary !== null && !(wasmBinary instanceof ArrayBuffer || ArrayBuffer.isView(wasmBinary))) {
    throw stlError('invalid-argument', 'init(): wasmBinary must be an ArrayBuffer or a Uint8Array');
  }
  if (wasmUrl !== undefined) settings.wasmUrl = absolute(wasmUrl);
  if (workerUrl !== undefined) settings.workerUrl = absolute(workerUrl);
  if (wasmBinary !== undefined) {
    settings.wasmBinary = wasmBinary === null ? null
      : ArrayBuffer.isView(wasmBinary) ? new Uint8Array(wasmBinary.buffer, wasmBinary.byteOffset, wasmBinary.byteLength) : new Uint8Array(wasmBinary);
  }
}

/** The current init() settings (the worker client hands the wasm ones to its workers). */
export const wasmSettings = () => ({ ...settings });

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
export function instantiateModule(createModule, source, extra) {
  let fail;
  const failed = new Promise((resolve, reject) => { fail = reject; });
  const where = source.binary ? 'wasmBinary' : String(source.url);
  const ready = createModule({
    ...extra,
    instantiateWasm(imports, receive) {
      const bytes = source.binary ? Promise.resolve(source.binary)
        : source.read ? source.read().catch((e) => { throw stlError('wasm-load', `cannot read the WebAssembly module ${where}: ${e && e.message}`); })
          : fetchWasm(source.url);
      bytes.then((b) => compile(b, imports, where)).then((r) => receive(r.instance, r.module), fail);
      return {};
    },
  });
  // The factory's own promise never settles when instantiateWasm fails: race it.
  return Promise.race([ready, failed]);
}
