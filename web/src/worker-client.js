// Main-thread side of stltopo/worker: runs loadStl in a worker (one per load
// in flight, idle ones reused), reports progress, cancels by terminating the
// worker, and receives the result arrays as transferred ArrayBuffers.
import { abortError, checkAbort, stlError, invalid } from './errors.js';
import { normalizeOptions, plainOptions } from './options.js';
import { toSource } from './sources.js';
import { Mesh, workerHome, writeInput, trackRelease, untrackSession } from './mesh.js';
import {
  Msg, InputKind, EditOp, loadMessage, chunksMessage, errorFromMessage, indexedMessage, writeMessage, writePullMessage,
  repairMessage, editableMessage,
} from './protocol.js';
import { normalizeIndexedOptions, normalizeWriteOptions, normalizeRepairOptions, REPAIR_DEFAULTS } from './options.js';
import { wasmSettings } from './wasm-load.js';

// Where the worker's wasm comes from: the page's init() settings.
function wasmOf() {
  const { wasmUrl, wasmBinary, fullWasmUrl, fullWasmBinary, threadsUrl } = wasmSettings();
  return { wasmUrl, wasmBinary, fullWasmUrl, fullWasmBinary, threadsUrl };
}

// Replaces the typed arrays of `data` by copies and returns the copies' buffers, to be
// transferred: the caller keeps its own arrays, and a view into wasm memory sends its
// elements only (a structured clone of a view sends its whole buffer: all of wasm memory).
function ownCopies(data) {
  const transfer = [];
  for (const [k, v] of Object.entries(data)) {
    if (!ArrayBuffer.isView(v)) continue;
    data[k] = v.slice();
    transfer.push(data[k].buffer);
  }
  return transfer;
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
    const ask = (msg, transfer) => new Promise((resolve, reject) => {
      pending = { resolve, reject };
      w.post(msg, transfer);
    });
    try {
      const input = writeInput(mesh);
      let msg = await ask(writeMessage(input, plain, wasmOf()), ownCopies(input));
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

  // The mesh as an EditableMesh source: writeInput()'s arrays and its format.
  const repairInput = (mesh) => ({ ...writeInput(mesh), format: mesh.format });

  // planRepair() in a worker: the plan comes back with its id lists transferred. A
  // WorkerEditableMesh is planned where it is held (as planRepair(em) on the main thread).
  async function planRepair(mesh, options) {
    if (mesh instanceof WorkerEditableMesh) return mesh.planRepair(options);
    normalizeRepairOptions(options); // checks here, so errors come from the call
    const input = repairInput(mesh);
    const transfer = ownCopies(input);
    return run(repairMessage('plan', input, { ...(options || {}) }, null, null, wasmOf()), transfer, {}, null);
  }

  const checkPlan = (plan) => {
    if (!plan || typeof plan !== 'object' || !plan.options || typeof plan.fingerprint !== 'string') {
      throw stlError('invalid-argument', 'applyRepair() needs a plan from planRepair()');
    }
  };

  // applyRepair() in a worker: the repaired mesh (loaded with loadOptions) and the log.
  async function applyRepair(mesh, plan, loadOptions) {
    if (mesh instanceof WorkerEditableMesh) {
      throw invalid('applyRepair(mesh, plan) repairs a copy of a Mesh; a WorkerEditableMesh repairs itself: em.applyRepair(plan)');
    }
    checkPlan(plan);
    const o = normalizeOptions(loadOptions);
    const { steps, before, after, remaining, fingerprint, options } = plan;
    const lean = { fingerprint, options, before, after, remaining, steps: steps.map((s) => ({ step: s.step })) };
    const input = repairInput(mesh);
    const transfer = ownCopies(input);
    return run(repairMessage('apply', input, null, lean, plainOptions(o), wasmOf()), transfer, o, null);
  }

  // ---------------------------------------------------------------------------------------
  // WorkerEditableMesh: an EditableMesh held in a worker between calls (worker-handler.js
  // keeps it under an id), for repair with undo off the main thread. Each one has a worker
  // of its own (taken from the idle ones) until dispose(), which frees the mesh there and
  // gives the worker back; its calls run one at a time, in the order they were made. The
  // state below is all a call needs; it never refers to the handle, so that the finalizer
  // (mesh.js, trackRelease) can free the worker's mesh once the handle is dropped.
  let lastId = 0;

  // One call on the worker's mesh after those queued before it: resolves to the edited
  // message's value. A worker that fails (exits, crashes) takes the mesh with it: that call
  // rejects with the failure, the later ones with `st.lost`.
  function editCall(st, op, fields = {}, transfer = []) {
    const p = st.queue.then(() => new Promise((resolve, reject) => {
      const w = st.w;
      if (!st.lost && w.exited()) st.lost = new Error('stltopo worker: the editable mesh was lost with its worker (it exited)');
      if (st.lost) {
        reject(st.lost);
        return;
      }
      const finish = (fn, value) => {
        w.listen(null, null);
        w.unref(); // an idle handle does not keep Node running
        fn(value);
      };
      w.ref();
      w.listen((msg) => {
        if (msg.type === Msg.Edited) {
          st.undoableSteps = msg.undoableSteps;
          finish(resolve, msg.value);
        } else if (msg.type === Msg.Error) {
          if (msg.undoableSteps !== undefined) st.undoableSteps = msg.undoableSteps;
          finish(reject, errorFromMessage(msg.error)); // refused: the mesh is still there
        }
      }, (err) => {
        const e = err instanceof Error ? err : new Error(String(err));
        st.lost = new Error(`stltopo worker: the editable mesh was lost with its worker (${e.message})`);
        st.undoableSteps = 0;
        w.listen(null, null);
        w.terminate();
        reject(e);
      });
      try {
        w.post(editableMessage(op, st.id, fields), transfer);
      } catch (e) {
        finish(reject, e); // not sent (a value that cannot be cloned): nothing happened there
      }
    }));
    st.queue = p.catch(() => {});
    return p;
  }

  // Frees the worker's mesh (after the calls queued before) and gives the worker back.
  function freeEditable(st) {
    st.disposed = true;
    st.freed ??= editCall(st, EditOp.Dispose).then(() => release(st.w), () => {}); // a lost worker is gone already
    return st.freed;
  }

  // The options a call sends: the keys its main-thread twin reads, so that anything else (a
  // callback, a signal) is ignored as there, not refused by the message's clone.
  const sendable = (options, keys) => {
    const o = options || {};
    const out = {};
    for (const k of keys) if (o[k] !== undefined) out[k] = o[k];
    return out;
  };
  const REPAIR_KEYS = [...Object.keys(REPAIR_DEFAULTS), 'exclude'];
  const WRITE_KEYS = ['format', 'colors', 'normals', 'name', 'chunkBytes'];
  const MESH_KEYS = ['topology', 'shells', 'intersections', 'maxPairs', 'validate'];

  // The finalizer's release of a dropped handle, made outside the class so that it cannot
  // hold the handle.
  const releaserOf = (st) => () => freeEditable(st);

  class WorkerEditableMesh {
    #st;

    constructor(st, source) {
      this.#st = st;
      /** As the source mesh's (EditableMesh's). */
      this.format = source.format || 'unknown';
      this.colorConvention = source.colors && source.colorValid ? source.colorConvention || 'none' : 'none';
      trackRelease(this, releaserOf(st));
    }

    /**
     * An EditableMesh in a worker, of a copy of a Mesh or of an indexed mesh { positions,
     * triangles, attributes?, colors?, colorValid?, colorConvention?, normals?, solids?,
     * format? } (EditableMesh.from()'s sources and options). Resolves when it is built there.
     */
    static async from(source, options = {}) {
      if (!source || !source.positions || !source.triangles) {
        throw invalid('WorkerEditableMesh.from() needs a Mesh or { positions, triangles }');
      }
      if (options === null || typeof options !== 'object') throw invalid('options must be an object');
      let data;
      if (source instanceof Mesh) {
        data = repairInput(source);
      } else {
        const keys = ['positions', 'triangles', 'attributes', 'colors', 'colorValid', 'colorConvention', 'normals', 'format'];
        data = Object.fromEntries(keys.filter((k) => source[k] != null).map((k) => [k, source[k]]));
        if (source.solids) data.solids = source.solids.map((so) => ({ ...so }));
      }
      const transfer = ownCopies(data);
      const st = { id: ++lastId, w: acquire(), queue: Promise.resolve(), undoableSteps: 0, lost: null, disposed: false, freed: null };
      const { tolerance } = options;
      try {
        await editCall(st, EditOp.Open, { mesh: data, options: tolerance === undefined ? {} : { tolerance }, wasm: wasmOf() }, transfer);
      } catch (e) {
        if (!st.lost) release(st.w); // refused there (bad input): the worker is fine
        throw e;
      }
      return new WorkerEditableMesh(st, source);
    }

    // A call on a mesh that is still there: refused at once after dispose().
    #call(op, fields, transfer) {
      if (this.#st.disposed) return Promise.reject(invalid('the editable mesh was disposed'));
      return editCall(this.#st, op, fields, transfer);
    }

    /** Plans a repair of this mesh (EditableMesh.planRepair): changes nothing. */
    async planRepair(options = {}) {
      normalizeRepairOptions(options); // checks here, so errors come from the call
      const o = sendable(options, REPAIR_KEYS);
      if (o.exclude) o.exclude = o.exclude.map(({ step, item }) => ({ step, item }));
      return this.#call(EditOp.Plan, { options: o });
    }
    /** Carries out a plan made for this mesh; resolves to the change log (EditableMesh.applyRepair). */
    async applyRepair(plan) {
      checkPlan(plan);
      return this.#call(EditOp.Apply, { plan: { fingerprint: plan.fingerprint, options: plan.options } });
    }
    /** Undoes the last repair step still applied: its name, or null when there is none. */
    async undo() { return this.#call(EditOp.Undo); }
    /** How many repair steps undo() can still take back, as of the last call that settled. */
    get undoableSteps() {
      if (this.#st.disposed) throw invalid('the editable mesh was disposed');
      return this.#st.undoableSteps;
    }
    /** The figures of `info --json` for the mesh (EditableMesh.stats). */
    async stats() { return this.#call(EditOp.Stats); }
    /** { ok: true } or { ok: false, code, message, element } (EditableMesh.validate). */
    async validate() { return this.#call(EditOp.Validate); }
    /** The STL file of the mesh as bytes (EditableMesh.toStl; the bytes are transferred). */
    async toStl(options = {}) {
      normalizeWriteOptions(options);
      return this.#call(EditOp.ToStl, { options: sendable(options, WRITE_KEYS) });
    }
    /**
     * The mesh as a Mesh with the editable mesh's ids (fromIndexed() of its positions,
     * triangles and attribute words without a weld, built in the worker; the arrays are
     * transferred). options: fromIndexed()'s, such as { shells, intersections }. Colours are
     * the attribute words read as VisCAM's (a Magics file's: loadStl() of toStl()'s bytes).
     */
    async toMesh(options = {}) {
      if (options === null || typeof options !== 'object') throw invalid('options must be an object');
      for (const k of ['weld', 'attributes', 'colors', 'colorValid', 'solids']) {
        if (options[k] !== undefined) throw invalid(`toMesh() takes the editable mesh's own vertices and attributes: no ${k} option`);
      }
      normalizeIndexedOptions({ ...options, weld: 'none' }); // checks here, so errors come from the call
      const raw = await this.#call(EditOp.ToMesh, { options: sendable(options, MESH_KEYS) });
      const mesh = new Mesh(raw);
      workerHome.set(mesh, () => self);
      return mesh;
    }
    /**
     * Frees the mesh in the worker, after the calls already made; the object refuses every
     * call from now on. Resolves when the worker has freed it.
     */
    dispose() {
      untrackSession(this);
      return freeEditable(this.#st);
    }
  }

  const self = { loadStl, loadStlFile, fromIndexed, writeStl, planRepair, applyRepair, WorkerEditableMesh };
  return self;
}

