// stltopo/worker (Node): the same API on worker_threads, plus loadStlFile(path)
// which reads the file inside the worker.
import { Worker } from 'node:worker_threads';
import { fileURLToPath } from 'node:url';
import { stlError } from './errors.js';
import { createWorkerLoader } from './worker-client.js';
import { createUnion } from './union.js';
import { Msg } from './protocol.js';
import { concatBytes } from './wasm.js';

const loader = createWorkerLoader(() => {
  const w = new Worker(new URL('./worker-thread.node.js', import.meta.url));
  let onMessage = null;
  let onError = null;
  let alive = true;
  w.on('message', (m) => m.type !== Msg.Ready && onMessage && onMessage(m));
  w.on('error', (e) => onError && onError(e));
  w.on('exit', (code) => {
    alive = false;
    if (onError) onError(new Error(`stltopo worker exited (${code})`));
  });
  return {
    post: (msg, transfer) => w.postMessage(msg, transfer || []),
    listen(m, e) {
      onMessage = m;
      onError = e;
    },
    terminate: () => {
      onMessage = onError = null;
      alive = false;
      w.terminate();
    },
    alive: () => alive,
    exited: () => !alive, // exited or terminated: a held mesh is gone with it
    ref: () => w.ref(),
    unref: () => w.unref(),
  };
});

// The worker API (documented in worker.d.ts): loads, writes and repairs made in a worker, and
// WorkerEditableMesh (an EditableMesh held in a worker, for repair with step-by-step undo).
export const { loadStl, fromIndexed, writeStl, planRepair, applyRepair, WorkerEditableMesh } = loader;

/** planUnion() and unionShells() (union.js), with their intersection passes and the result's load in a worker. */
export const { planUnion, unionShells } = createUnion(loader.fromIndexed);

/** toStl() with the writing in a worker: one Uint8Array. */
export async function toStl(mesh, options) {
  const chunks = [];
  for await (const c of loader.writeStl(mesh, options)) chunks.push(c);
  return concatBytes(...chunks);
}

/** Reads the file at `path` (a path, or a file: URL object) in the worker. */
export async function loadStlFile(path, options) {
  let p = String(path);
  if (path instanceof URL) {
    try {
      p = fileURLToPath(path);
    } catch (e) {
      throw stlError('invalid-argument', `cannot open ${path}: ${e.message}`);
    }
  }
  return loader.loadStlFile(p, options);
}
export * from './exports.js';
