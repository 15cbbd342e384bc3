// stltopo/worker (browser): loadStl() in a Web Worker, so large files never
// freeze the page. Same signature as loadStl from 'stltopo'; progress and
// AbortSignal work across the thread, and the result arrays are transferred.
import { createWorkerLoader } from './worker-client.js';

const loader = createWorkerLoader(() => {
  const w = new Worker(new URL('./worker-thread.js', import.meta.url), { type: 'module' });
  return {
    post: (msg, transfer) => w.postMessage(msg, transfer || []),
    listen(onMessage, onError) {
      w.onmessage = onMessage ? (e) => onMessage(e.data) : null;
      w.onerror = onError ? (e) => { e.preventDefault(); onError(new Error(`stltopo worker: ${e.message || 'failed to start'}`)); } : null;
      w.onmessageerror = onError ? () => onError(new Error('stltopo worker: message could not be deserialized')) : null;
    },
    terminate: () => w.terminate(),
    alive: () => true,
    ref() {},
    unref() {},
  };
});

export const loadStl = loader.loadStl;
export const fromIndexed = loader.fromIndexed;
export const writeStl = loader.writeStl;

/** toStl() with the writing in a worker: a Blob (type model/stl). */
export async function toStl(mesh, options) {
  const chunks = [];
  for await (const c of loader.writeStl(mesh, options)) chunks.push(c);
  return new Blob(chunks, { type: 'model/stl' });
}
export { StlError } from './errors.js';
export { Mesh, kInvalid, EdgeKind, DEFECT_KINDS } from './mesh.js';
export { extractShell } from './extract-shell.js';
