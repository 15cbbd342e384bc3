// Main-thread side of stltopo/worker: runs loadStl in a worker (one per load
// in flight, idle ones reused), reports progress, cancels by terminating the
// worker, and receives the result arrays as transferred ArrayBuffers.
import { abortError, checkAbort, stlError } from './errors.js';
import { normalizeOptions, plainOptions } from './options.js';
import { toSource } from './sources.js';
import { Mesh, workerHome, writeInput } from './mesh.js';
import {
  Msg, InputKind, loadMessage, chunksMessage, errorFromMessage, indexedMessage, writeMessage, writePullMessage, repairMessage,
} from './protocol.js';
import { normalizeIndexedOptions, normalizeWriteOptions, normalizeRepairOptions } from './options.js';
import { wasmSettings } from './wasm-load.js';

// Where the worker's wasm comes from: the page's init() settings.
function wasmOf() {
  const { wasmUrl, wasmBinary, fullWasmUrl, fullWasmBinary } = wasmSettings();
  return { wasmUrl, wasmBinary, fullWasmUrl, fullWasmBinary };
}

const PUMP_BYTES = 1 << 20; // stream chunks posted per pull (as separate chunks, never joined)
const MAX_IDLE = 2;

export function createWorkerLoader(spawn) {
  const idle = [];

  function acquire() {
    let w;
    while ((w = idle.pop()) && !w.alive()) w.terminate();
    if (!w) w = spawn();
    w.ref();
    return w;
  }
  function release(w) {
    w.unref();
    if (idle.length < MAX_IDLE) idle.push(w);
    else w.terminate();
  }

  function run(request, transfer, o, pumpSource) {
    return new Promise((resolve, reject) => {
      const w = acquire();
      const signal = o.signal;
      let settled = false;
      const settle = (fn, value, reuse) => {
        if (settled) return;
        settled = true;
        if (signal) signal.removeEventListener('abort', onAbort);
        w.listen(null, null);
        if (reuse) release(w);
        else w.terminate();
        if (pumpSource) pumpSource.cancel(); // a no-op once the stream was read to its end
        fn(value);
      };
      const onAbort = () => settle(reject, abortError(), false);
      const pump = async () => {
        const chunks = [];
        const transferChunks = [];
        let bytes = 0;
        let done = false;
        try {
          while (bytes < PUMP_BYTES) {
            const c = await pumpSource.next();
            if (c === null) {
              done = true;
              break;
            }
            const copy = c.slice(); // the producer may reuse its buffer
            chunks.push(copy);
            transferChunks.push(copy.buffer);
            bytes += copy.length;
          }
        } catch (e) {
          if (!settled) w.post(chunksMessage([], true, e));
          return;
        }
        if (!settled) w.post(chunksMessage(chunks, done), transferChunks);
      };
      w.listen(
        (msg) => {
          if (settled) return;
          switch (msg.type) {
            case Msg.Progress:
              if (o.onProgress) {
                try {
                  o.onProgress(msg.fraction, msg.bytesRead);
                } catch (e) {
                  settle(reject, e, false);
                }
              }
              break;
            case Msg.Pull:
              pump();
              break;
            case Msg.Result: {
              const mesh = new Mesh(msg.raw);
              workerHome.set(mesh, () => self);
              settle(resolve, mesh, true);
              break;
            }
            case Msg.Repaired: {
              let value = msg.plan;
              if (msg.raw) {
                const mesh = new Mesh(msg.raw);
                workerHome.set(mesh, () => self);
                value = { mesh, log: msg.log };
              }
              settle(resolve, value, true);
              break;
            }
            case Msg.Error:
              settle(reject, errorFromMessage(msg.error), true);
              break;
            default:
              break;
          }
        },
        (err) => settle(reject, err instanceof Error ? err : new Error(String(err)), false),
      );
      if (signal) signal.addEventListener('abort', onAbort, { once: true });
      w.post(request, transfer);
    });
  }

  async function loadStl(input, options) {
    const o = normalizeOptions(options);
    checkAbort(o.signal);
    const opts = plainOptions(o);
    if (input instanceof ArrayBuffer || ArrayBuffer.isView(input) ||
        (typeof SharedArrayBuffer !== 'undefined' && input instanceof SharedArrayBuffer)) {
      const src = input instanceof ArrayBuffer || input instanceof (globalThis.SharedArrayBuffer || ArrayBuffer)
        ? new Uint8Array(input)
        : new Uint8Array(input.buffer, input.byteOffset, input.byteLength);
      const bytes = src.slice(); // the caller keeps its buffer; the copy is transferred
      return run(loadMessage({ kind: InputKind.Bytes, bytes }, opts, wasmOf()), [bytes.buffer], o, null);
    }
    if (input && typeof input.stream === 'function' && typeof input.size === 'number' && typeof input.getReader !== 'function') {
      return run(loadMessage({ kind: InputKind.Blob, blob: input }, opts, wasmOf()), [], o, null);
    }
    const source = toSource(input); // streams, Responses, async iterables: pumped from this thread
    return run(loadMessage({ kind: InputKind.Stream, total: source.total }, opts, wasmOf()), [], o, source);
  }

  // Node: the worker reads the file at `path` (a string) itself.
  async function loadStlFile(path, options) {
    const o = normalizeOptions(options);
    checkAbort(o.signal);
    return run(loadMessage({ kind: InputKind.Path, path }, plainOptions(o), wasmOf()), [], o, null);
  }

  // fromIndexed() in a worker: copies of the arrays are transferred there.
  async function fromIndexed(positions, triangles, options) {
    const o = normalizeIndexedOptions(options); // checks here, so errors come from the call
    const copy = (v, Type) => (v instanceof Type ? v.slice() : Type.from(v));
    const pos = copy(positions, Float32Array);
    const tri = copy(triangles, Uint32Array);
    const { worker, signal, onProgress, ...plain } = options || {};
    return run(indexedMessage(pos, tri, plain, wasmOf()), [pos.buffer, tri.buffer], o, null);
  }

  // writeStl() in a worker: the mesh's arrays are copied there, and each chunk comes back
  // (transferred) when the consumer asks for it.
  async function* writeStl(mesh, options) {
    normalizeWriteOptions(options);
    const { worker, ...plain } = options || {};
    const w = acquire();
    let finished = false;
    let pending = null;
    w.listen((msg) => {
      const p = pending;
      pending = null;
      if (p) p.resolve(msg);
    }, (err) => {
      const p = pending;
      pending = null;
      if (p) p.reject(err instanceof Error ? err : new Error(String(err)));
    });
    const ask = (msg) => new Promise((resolve, reject) => {
      pending = { resolve, reject };
      w.post(msg);
    });
    try {
      let msg = await ask(writeMessage(writeInput(mesh), plain, wasmOf()));
      for (;;) {
        if (msg.type === Msg.Error) throw errorFromMessage(msg.error);
        if (msg.chunk === null) break;
        yield msg.chunk;
        msg = await ask(writePullMessage());
      }
      finished = true;
    } finally {
      w.listen(null, null);
      if (finished) release(w);
      else w.terminate(); // stopped early or failed: the write in the worker is abandoned
    }
  }

  // The mesh as an EditableMesh source: writeInput()'s arrays (copies) and its format.
  const repairInput = (mesh) => ({ ...writeInput(mesh), format: mesh.format });

  // planRepair() in a worker: the plan comes back with its id lists transferred.
  async function planRepair(mesh, options) {
    normalizeRepairOptions(options); // checks here, so errors come from the call
    return run(repairMessage('plan', repairInput(mesh), { ...(options || {}) }, null, null, wasmOf()), [], {}, null);
  }

  // applyRepair() in a worker: the repaired mesh (loaded with loadOptions) and the log.
  async function applyRepair(mesh, plan, loadOptions) {
    if (!plan || typeof plan !== 'object' || !plan.options || typeof plan.fingerprint !== 'string') {
      throw stlError('invalid-argument', 'applyRepair() needs a plan from planRepair()');
    }
    const o = normalizeOptions(loadOptions);
    const { steps, before, after, remaining, fingerprint, options } = plan;
    const lean = { fingerprint, options, before, after, remaining, steps: steps.map((s) => ({ step: s.step })) };
    return run(repairMessage('apply', repairInput(mesh), null, lean, plainOptions(o), wasmOf()), [], o, null);
  }

  const self = { loadStl, loadStlFile, fromIndexed, writeStl, planRepair, applyRepair };
  return self;
}

