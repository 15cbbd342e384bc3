// stltopo/worker (browser): loadStl() in a Web Worker, so large files never
// freeze the page. Same signature as loadStl from 'stltopo'; progress and
// AbortSignal work across the thread, and the result arrays are transferred.
import { stlError } from './errors.js';
import { createWorkerLoader } from './worker-client.js';
import { createUnion } from './union.js';
import { describeUrl, wasmSettings } from './wasm-load.js';
import { Msg } from './protocol.js';

// A worker that fails before its first message did not start: its script was not served
// (a 404, an HTML page) or does not load. That is a 'wasm-load' error, which names the
// URL and what it returns when init() gave the URL (a bundled worker's URL is not known).
async function startError(url, event) {
  const why = event && event.message ? ` (${event.message})` : '';
  if (!url) {
    return stlError('wasm-load', `the worker did not start${why}: stltopo's worker-thread.js, as the bundler emitted it, `
      + 'was not served or did not load; see the bundler notes in the README, or give its URL with init({ workerUrl })');
  }
  return stlError('wasm-load', `the worker ${url} did not start${why}: ${await describeUrl(url)}`);
}

const loader = createWorkerLoader(() => {
  const { workerUrl } = wasmSettings();
  // The literal new Worker(new URL(...)) form is what bundlers recognise and bundle.
  const w = workerUrl ? new Worker(workerUrl, { type: 'module' })
    : new Worker(new URL('./worker-thread.js', import.meta.url), { type: 'module' });
  let started = false;
  let terminated = false;
  return {
    post: (msg, transfer) => w.postMessage(msg, transfer || []),
    listen(onMessage, onError) {
      w.onmessage = (e) => {
        started = true;
        if (onMessage && e.data.type !== Msg.Ready) onMessage(e.data);
      };
      w.onerror = onError ? (e) => {
        e.preventDefault();
        if (started) onError(new Error(`stltopo worker: ${e.message || 'an error in the worker'}`));
        else startError(workerUrl, e).then(onError);
      } : null;
      w.onmessageerror = onError ? () => onError(new Error('stltopo worker: message could not be deserialized')) : null;
    },
    terminate: () => {
      terminated = true;
      w.terminate();
    },
    alive: () => wasmSettings().workerUrl === workerUrl, // init() gave another script: start anew
    exited: () => terminated, // a Web Worker ends only when terminated (errors reach onerror)
    ref() {},
    unref() {},
  };
});

// The worker API (documented in worker.d.ts): loads, writes and repairs made in a worker, and
// WorkerEditableMesh (an EditableMesh held in a worker, for repair with step-by-step undo).
export const { loadStl, fromIndexed, writeStl, planRepair, applyRepair, WorkerEditableMesh } = loader;

/** planUnion() and unionShells() (union.js), with their intersection passes and the result's load in a worker. */
export const { planUnion, unionShells } = createUnion(loader.fromIndexed);

/** toStl() with the writing in a worker: a Blob (type model/stl). */
export async function toStl(mesh, options) {
  const chunks = [];
  for await (const c of loader.writeStl(mesh, options)) chunks.push(c);
  return new Blob(chunks, { type: 'model/stl' });
}
export * from './exports.js';
