// stltopo, Node entry: the same API as index.js, plus loadStlFile(path).
// Node reads the .wasm with fs (the Emscripten 3.1.6 ES-module glue cannot
// locate it by itself under Node).
import { readFile, open } from 'node:fs/promises';
import createStltopoModule from './stltopo-wasm.js';
import { createStltopo, normalizeOptions, StlError, Mesh, kInvalid, EdgeKind } from './core.js';
import { createEditableMesh, kLoopFaceBit } from './edit.js';

const wasmUrl = new URL('./stltopo-wasm.wasm', import.meta.url);
let wasmBytes = null;

const api = createStltopo({
  instantiate: async (extra) => {
    wasmBytes ??= await readFile(wasmUrl);
    return createStltopoModule({ ...extra, wasmBinary: wasmBytes });
  },
  loadWorker: () => import('./worker.node.js'),
});

export const loadStl = api.loadStl;

/** Local edits on a copy of a mesh in wasm memory (edit.js, docs/EDITING.md). */
export const EditableMesh = createEditableMesh(api.internal.getModule);
export { kLoopFaceBit };

const FILE_CHUNK = 1 << 20;

/**
 * A source that streams a file from disk in 1 MiB reads (one buffer, reused:
 * the core copies each chunk before the next read).
 * @internal
 */
export async function fileSource(path) {
  const fh = await open(path instanceof URL ? path : String(path), 'r');
  let total = 0;
  try {
    const st = await fh.stat();
    if (st.isFile()) total = st.size;
  } catch {
    // no size hint
  }
  const buf = new Uint8Array(FILE_CHUNK);
  let closed = false;
  const close = () => {
    if (closed) return;
    closed = true;
    fh.close().catch(() => {});
  };
  return {
    total,
    async next() {
      if (closed) return null;
      let n;
      try {
        ({ bytesRead: n } = await fh.read(buf, 0, buf.length, null));
      } catch (e) {
        close();
        throw e;
      }
      if (n === 0) {
        close();
        return null;
      }
      return buf.subarray(0, n);
    },
    cancel: close,
  };
}

/** Node only: reads an STL file from disk, streaming it to the core. */
export async function loadStlFile(path, options) {
  if (options && options.worker) return (await import('./worker.node.js')).loadStlFile(path, { ...options, worker: false });
  const o = normalizeOptions(options);
  let source;
  try {
    source = await fileSource(path);
  } catch (e) {
    throw new StlError('invalid-argument', `invalid-argument: cannot open ${path}: ${e.message}`);
  }
  return api.loadFromSource(source, o);
}

export { StlError, Mesh, kInvalid, EdgeKind };
/** @internal test and CLI hooks */
export const _internal = api.internal;
