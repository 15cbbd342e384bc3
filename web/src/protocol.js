// The message protocol between stltopo/worker's main-thread side (worker-client.js) and
// the worker thread (worker-handler.js). Every message is { type, ...fields }:
//   main -> worker
//     load    { input, options, wasm }  input: { kind: 'bytes', bytes } | { kind: 'blob', blob }
//                                  | { kind: 'stream', total } | { kind: 'path', path } (Node);
//                                  options: plainOptions() of the load; wasm: the page's
//                                  init() { wasmUrl, wasmBinary, fullWasmUrl, fullWasmBinary }
//                                  (absolute URLs, bytes or null)
//     chunks  { chunks, done, error? }  the answer to a pull: Uint8Arrays (transferred), done at
//                                  the end, error (errorToMessage) when the producer failed
//     indexed { positions, triangles, options, wasm }  fromIndexed() (arrays transferred
//                                  copies); options: the caller's, without worker/signal/onProgress
//     write   { mesh, options, wasm }  writeStl() of writeInput(mesh) data (copied); answered by
//                                  one written message per writePull
//     writePull {}                 asks for the next chunk of the write
//     repair  { mode, mesh, options, plan, loadOptions, wasm }  planRepair() ('plan': options)
//                                  or applyRepair() ('apply': plan, loadOptions) on an
//                                  EditableMesh made there from writeInput(mesh) data (copied)
//     editable { op, id, ... }     a WorkerEditableMesh's call on the EditableMesh the worker
//                                  holds under id (worker-client.js numbers them) between
//                                  messages: 'open' { mesh, options, wasm } makes it (mesh: an
//                                  EditableMesh.from() source, copied), then 'plan' { options },
//                                  'apply' { plan } (fingerprint and options), 'undo', 'stats',
//                                  'validate', 'toStl' { options }, 'toMesh' { options } and
//                                  'dispose' (frees it); answered by one edited or error message
//   worker -> main
//     ready   {}                   once, when the thread runs (before it, an error is a failed
//                                  start); the platform wrappers (worker.js, worker.node.js)
//                                  consume it, the loader never sees it
//     pull    {}                   asks for the next chunks of a 'stream' input
//     progress { fraction, bytesRead }
//     result  { raw }              the mesh's raw data, its arrays transferred (transferList)
//     written { chunk }            the next chunk of a write (transferred), null at the end
//     repaired { plan } | { raw, log }  the plan, or the repaired mesh's raw data (loaded there
//                                  with loadOptions) and the change log; id lists transferred
//     edited  { value, undoableSteps }  an editable call's result (a plan's or log's id lists,
//                                  toStl's bytes and toMesh's raw arrays transferred) and how
//                                  many repair steps the mesh can undo after it
//     error   { error, undoableSteps? }  errorToMessage() of the failure (undoableSteps: after
//                                  a failed editable call, which may have applied some steps)
import { StlError } from './errors.js';

export const Msg = Object.freeze({
  Load: 'load', Chunks: 'chunks', Ready: 'ready', Pull: 'pull', Progress: 'progress', Result: 'result', Error: 'error',
  Indexed: 'indexed', Write: 'write', WritePull: 'writePull', Written: 'written', Repair: 'repair', Repaired: 'repaired',
  Editable: 'editable', Edited: 'edited',
});
/** The calls of a WorkerEditableMesh (the op of an editable message). */
export const EditOp = Object.freeze({
  Open: 'open', Plan: 'plan', Apply: 'apply', Undo: 'undo', Stats: 'stats', Validate: 'validate', ToStl: 'toStl',
  ToMesh: 'toMesh', Dispose: 'dispose',
});
export const InputKind = Object.freeze({ Bytes: 'bytes', Blob: 'blob', Stream: 'stream', Path: 'path' });

export const loadMessage = (input, options, wasm) => ({ type: Msg.Load, input, options, wasm });
export const readyMessage = () => ({ type: Msg.Ready });
export const chunksMessage = (chunks, done, error) => (error ? { type: Msg.Chunks, chunks, done, error } : { type: Msg.Chunks, chunks, done });
export const pullMessage = () => ({ type: Msg.Pull });
export const progressMessage = (fraction, bytesRead) => ({ type: Msg.Progress, fraction, bytesRead });
export const resultMessage = (raw) => ({ type: Msg.Result, raw });
export const indexedMessage = (positions, triangles, options, wasm) => ({ type: Msg.Indexed, positions, triangles, options, wasm });
export const writeMessage = (mesh, options, wasm) => ({ type: Msg.Write, mesh, options, wasm });
export const writePullMessage = () => ({ type: Msg.WritePull });
export const writtenMessage = (chunk) => ({ type: Msg.Written, chunk });
export const repairMessage = (mode, mesh, options, plan, loadOptions, wasm) => ({ type: Msg.Repair, mode, mesh, options, plan, loadOptions, wasm });
export const repairedMessage = (fields) => ({ type: Msg.Repaired, ...fields });
export const editableMessage = (op, id, fields) => ({ type: Msg.Editable, op, id, ...fields });
export const editedMessage = (value, undoableSteps) => ({ type: Msg.Edited, value, undoableSteps });
export const errorMessage = (e) => ({ type: Msg.Error, error: errorToMessage(e) });

/** The ArrayBuffers of a raw result, for a postMessage transfer list. */
export function transferList(raw) {
  const set = new Set();
  for (const a of Object.values(raw.arrays)) if (a && a.buffer) set.add(a.buffer);
  for (const a of Object.values(raw.shellTable || {})) if (a && a.buffer) set.add(a.buffer);
  return [...set];
}

/** The Uint32Array buffers of a plan's items or a log's steps, for a transfer list. */
export function repairTransferList(x) {
  const set = new Set();
  for (const s of (x && x.steps) || []) {
    for (const v of Object.values(s)) if (v instanceof Uint32Array) set.add(v.buffer);
    for (const it of s.items || []) for (const v of Object.values(it)) if (v instanceof Uint32Array) set.add(v.buffer);
  }
  return [...set];
}

/** An error as cloneable data; errorFromMessage() turns it back into an (Stl)Error. */
export function errorToMessage(e) {
  if (e instanceof StlError) {
    return { stl: true, code: e.code, message: e.message, offset: e.offset, line: e.line, triangle: e.triangle };
  }
  return { stl: false, name: e && e.name, message: String(e && e.message !== undefined ? e.message : e) };
}

export function errorFromMessage(m) {
  if (m.stl) return new StlError(m.code, m.message, m);
  const e = new Error(m.message);
  if (m.name) e.name = m.name;
  return e;
}
