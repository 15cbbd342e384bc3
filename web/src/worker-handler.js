// Worker-thread side of stltopo/worker (shared by the browser and Node threads).
import { bufferSource, streamSource } from './sources.js';
import { normalizeOptions } from './options.js';
import { createEditableMesh } from './edit.js';
import { init } from './wasm-load.js';
import { invalid } from './errors.js';
import {
  Msg, InputKind, EditOp, readyMessage, pullMessage, progressMessage, resultMessage, errorMessage, transferList,
  errorFromMessage, writtenMessage, repairedMessage, repairTransferList, editedMessage,
} from './protocol.js';

// Chunks pulled from the main thread one batch at a time (flow control).
function pulledSource(port, total) {
  let queue = [];
  let done = false;
  let waiting = null;
  const source = {
    total,
    async next() {
      for (;;) {
        if (queue.length) return queue.shift();
        if (done) return null;
        port.post(pullMessage());
        const msg = await new Promise((r) => { waiting = r; });
        if (msg.error) throw errorFromMessage(msg.error);
        queue = msg.chunks;
        done = msg.done;
      }
    },
    cancel() {},
    deliver(msg) {
      const w = waiting;
      waiting = null;
      if (w) w(msg);
    },
  };
  return source;
}

export function serve(port, internal, { fileSource = null } = {}) {
  let EditableMesh = null;
  let pulled = null;
  let writing = null; // the iterator of the write in progress
  const editables = new Map(); // id -> the EditableMesh of a WorkerEditableMesh, until its dispose

  // One call of a WorkerEditableMesh: [the edited message, its transfer list].
  async function editableCall(msg) {
    if (msg.op === EditOp.Open) {
      if (editables.has(msg.id)) throw invalid(`the editable mesh ${msg.id} exists already`);
      const em = await EditableMesh.from(msg.mesh, msg.options);
      editables.set(msg.id, em);
      return [editedMessage(null, em.undoableSteps), []];
    }
    const em = editables.get(msg.id);
    if (!em) throw invalid('the editable mesh was disposed');
    const answer = (value, transfer = []) => [editedMessage(value, em.undoableSteps), transfer];
    switch (msg.op) {
      case EditOp.Plan: {
        const plan = em.planRepair(msg.options);
        return answer(plan, repairTransferList(plan));
      }
      case EditOp.Apply: {
        const log = em.applyRepair(msg.plan);
        return answer(log, repairTransferList(log));
      }
      case EditOp.Undo: return answer(em.undo());
      case EditOp.Stats: return answer(em.stats);
      case EditOp.Validate: return answer(em.validate());
      case EditOp.ToStl: {
        const bytes = em.toStl(msg.options); // a copy out of wasm memory: its buffer can go
        return answer(bytes, [bytes.buffer]);
      }
      case EditOp.ToMesh: {
        // The mesh as it is, ids kept (repair leaves it compact): its vertices unwelded.
        const o = internal.normalizeIndexedOptions({ ...msg.options, weld: 'none', attributes: em.attributes });
        const raw = await internal.indexedRaw(em.positions, em.triangles, o, { validate: true });
        return answer(raw, transferList(raw));
      }
      case EditOp.Dispose:
        em.dispose();
        editables.delete(msg.id);
        return [editedMessage(null, 0), []];
      default:
        throw invalid(`unknown editable call ${String(msg.op)}`);
    }
  }

  port.onMessage(async (msg) => {
    if (msg.wasm) init(msg.wasm); // the page's init(), before this thread's instance starts
    if (msg.type === Msg.Chunks) {
      if (pulled) pulled.deliver(msg);
      return;
    }
    if (msg.type === Msg.Editable) {
      try {
        if (!EditableMesh) EditableMesh = createEditableMesh(internal.editModule, internal.wasmFailure);
        const [reply, transfer] = await editableCall(msg);
        port.post(reply, transfer);
      } catch (e) {
        // A failed call may still have applied some steps (applyRepair stops at a failed step).
        const em = editables.get(msg.id);
        port.post({ ...errorMessage(e), undoableSteps: em ? em.undoableSteps : 0 });
      }
      return;
    }
    if (msg.type === Msg.Write || msg.type === Msg.WritePull) {
      try {
        if (msg.type === Msg.Write) writing = internal.writeHere(msg.mesh, internal.normalizeWriteOptions(msg.options));
        const r = writing ? await writing.next() : { done: true };
        if (r.done) writing = null;
        port.post(writtenMessage(r.done ? null : r.value), r.done ? [] : [r.value.buffer]);
      } catch (e) {
        writing = null;
        port.post(errorMessage(e));
      }
      return;
    }
    if (msg.type === Msg.Repair) {
      let em = null;
      try {
        if (!EditableMesh) EditableMesh = createEditableMesh(internal.editModule, internal.wasmFailure);
        if (msg.mode === 'plan') {
          const plan = await EditableMesh.planRepairOf(msg.mesh, msg.options);
          port.post(repairedMessage({ plan }), repairTransferList(plan));
        } else {
          em = await EditableMesh.from(msg.mesh);
          const log = em.applyRepair(msg.plan);
          const bytes = em.toStl({ format: msg.mesh.format === 'ascii' ? 'ascii' : 'binary' });
          const raw = await internal.loadRaw(bufferSource(bytes), normalizeOptions(msg.loadOptions), { validate: true });
          port.post(repairedMessage({ raw, log }), [...transferList(raw), ...repairTransferList(log)]);
        }
      } catch (e) {
        port.post(errorMessage(e));
      } finally {
        if (em) em.dispose();
      }
      return;
    }
    if (msg.type === Msg.Indexed) {
      try {
        const o = internal.normalizeIndexedOptions(msg.options);
        const raw = await internal.indexedRaw(msg.positions, msg.triangles, o, { validate: true });
        port.post(resultMessage(raw), transferList(raw));
      } catch (e) {
        port.post(errorMessage(e));
      }
      return;
    }
    if (msg.type !== Msg.Load) return;
    try {
      const input = msg.input;
      let source;
      if (input.kind === InputKind.Bytes) source = bufferSource(input.bytes);
      else if (input.kind === InputKind.Blob) source = streamSource(input.blob.stream(), input.blob.size);
      else if (input.kind === InputKind.Stream) source = pulled = pulledSource(port, input.total);
      else if (input.kind === InputKind.Path && fileSource) source = await fileSource(input.path);
      else throw new Error(`stltopo worker: unknown input kind ${input.kind}`);
      const o = normalizeOptions(msg.options);
      o.onProgress = (fraction, bytesRead) => port.post(progressMessage(fraction, bytesRead));
      const raw = await internal.loadRaw(source, o, { validate: true });
      port.post(resultMessage(raw), transferList(raw));
    } catch (e) {
      port.post(errorMessage(e));
    } finally {
      pulled = null;
    }
  });
  port.post(readyMessage());
}
