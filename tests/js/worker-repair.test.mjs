// stltopo/worker's WorkerEditableMesh (issue 23: plan, apply and undo "the same in the
// worker"): an EditableMesh held in a worker between calls. Checked against the main
// thread's EditableMesh on the same plan: the same log, the same bytes after the apply and
// after every undo, back to the input byte for byte; refusals change nothing and keep the
// worker usable; a disposed handle refuses; a dropped one is freed by the finalizer.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { Worker } from 'node:worker_threads';
import { fromIndexed, toStl, planRepair, EditableMesh, loadStlFile } from 'stltopo';
import * as worker from 'stltopo/worker';
import { root, damagedTorus, meshArrays } from './helpers.mjs';
import path from 'node:path';

const { WorkerEditableMesh } = worker;
const ALL = ['duplicates', 'zero-area', 'stitch', 'orient', 'split-nonmanifold', 'fill-holes', 'small-shells'];

// Every message the main thread posts to a worker thread (the loader's workers are
// node:worker_threads Workers), so that a test can see what the handle asked for.
const posted = [];
const transfers = []; // transfers[i]: the transfer list of posted[i]
const postMessage = Worker.prototype.postMessage;
Worker.prototype.postMessage = function (msg, transfer) {
  posted.push(msg);
  transfers.push(transfer || []);
  return postMessage.call(this, msg, transfer);
};

const bytes = async (x) => new Uint8Array(await toStl(x));
const isDisposed = (e) => e.code === 'invalid-argument' && /the editable mesh was disposed/.test(e.message);

// The damaged torus with attribute words (some of them VisCAM colours), so that the bytes
// compared below carry the attributes too.
async function damagedMesh(n, m, seed) {
  const t = damagedTorus(n, m, seed);
  const attributes = new Uint16Array(t.triangles.length / 3).map((_, i) => (i % 3 === 0 ? 0x8000 | (i & 0x7fff) : i % 7));
  return fromIndexed(t.positions, t.triangles, { attributes });
}

// Applies `plan` on the main thread and in the worker, then undoes step by step on both,
// comparing everything each side gives at every stage.
async function applyAndUndoBoth(mesh, plan, options) {
  const input = await bytes(mesh);
  const em = await EditableMesh.from(mesh);
  const wem = await WorkerEditableMesh.from(mesh);
  try {
    assert.equal(wem.undoableSteps, 0);
    assert.equal(wem.format, em.format);
    assert.equal(wem.colorConvention, em.colorConvention);
    assert.deepEqual(await wem.toStl(), new Uint8Array(em.toStl()), 'the worker holds the same mesh');
    // The plan made in the worker is the main thread's.
    const wplan = await wem.planRepair(options);
    assert.deepEqual(wplan.steps, plan.steps);
    assert.deepEqual(wplan.after, plan.after);
    assert.deepEqual(wplan.options, plan.options);
    assert.equal(wplan.fingerprint, plan.fingerprint);
    for (const s of wplan.steps) for (const it of s.items) assert.ok(it.triangles instanceof Uint32Array);
    assert.deepEqual(await worker.planRepair(wem, options), wplan, 'planRepair(em) plans the held mesh');

    const log = em.applyRepair(plan);
    const wlog = await wem.applyRepair(plan); // the main thread's plan: its fingerprint is the mesh's
    assert.deepEqual(wlog, log, 'the same change log');
    assert.ok(wlog.steps.length > 0 && wlog.steps.every((s) => s.status === 'ok'));
    for (const s of wlog.steps) assert.ok(s.removedTriangles instanceof Uint32Array);
    assert.equal(wem.undoableSteps, em.undoableSteps);
    assert.equal(wem.undoableSteps, plan.steps.length);
    assert.deepEqual(await wem.stats(), em.stats);
    assert.deepEqual(await wem.validate(), { ok: true });
    assert.deepEqual(await wem.toStl(), new Uint8Array(em.toStl()));
    assert.deepEqual(await wem.toStl({ format: 'ascii' }), new Uint8Array(em.toStl({ format: 'ascii' })));
    // toMesh(): the held mesh with its ids, as fromIndexed() of its arrays without a weld.
    const m = await wem.toMesh({ shells: true });
    const here = await fromIndexed(em.positions, em.triangles, { weld: 'none', attributes: em.attributes, shells: true });
    assert.deepEqual(meshArrays(m), meshArrays(here));
    assert.deepEqual(m.stats, here.stats);
    assert.equal(m.shells.length, here.shells.length);
    assert.ok(m.positions.buffer.byteLength === m.positions.byteLength, 'transferred, one buffer per array');
    assert.deepEqual(await bytes(m), await bytes(here), 'a Mesh from toMesh() is written in the worker too');

    // Undo one step at a time: the same step and the same bytes as the main thread each time.
    const undone = [];
    for (;;) {
      const name = em.undo();
      assert.equal(await wem.undo(), name);
      assert.equal(wem.undoableSteps, em.undoableSteps);
      if (name === null) break;
      undone.push(name);
      assert.deepEqual(await wem.validate(), { ok: true });
      assert.deepEqual(await wem.toStl(), new Uint8Array(em.toStl()), `after undoing ${name}`);
    }
    assert.deepEqual(undone, plan.steps.map((s) => s.step).reverse());
    assert.deepEqual(await wem.toStl(), input, 'undone: the input, byte for byte');
    assert.equal(await wem.undo(), null, 'nothing left to undo');
    assert.equal(wem.undoableSteps, 0);
    return wlog;
  } finally {
    em.dispose();
    await wem.dispose();
  }
}

test('WorkerEditableMesh: apply, then undo step by step, as the main thread: same log, same bytes, back to the input', async () => {
  const mesh = await damagedMesh(30, 12, 5);
  const options = { steps: ['duplicates', 'zero-area', 'stitch', 'split-nonmanifold', 'fill-holes', 'orient'], fill: ['refine', 'fair'] };
  const plan = await planRepair(mesh, options);
  assert.ok(plan.before.duplicateTriangles > 0 && plan.before.inconsistentEdges > 0);
  const log = await applyAndUndoBoth(mesh, plan, options);
  assert.equal(log.after.duplicateTriangles, 0);
  assert.equal(log.after.inconsistentEdges, 0);
});

test('WorkerEditableMesh: every step on admesh\'s files (read from disk, ASCII and binary)', async () => {
  for (const f of ['block/nearby-bad.stl', 'conveyor/fill-holes-bad.stl', 'hourglass/normal-directions-bad.stl']) {
    const mesh = await loadStlFile(path.join(root, 'tests/judge/admesh', f));
    const options = { steps: ALL, stitchTolerance: 0.05 };
    const plan = await planRepair(mesh, options);
    const log = await applyAndUndoBoth(mesh, plan, options);
    assert.ok(log.steps.length === plan.steps.length, f);
  }
});

test('WorkerEditableMesh: refusals change nothing and keep the worker usable', async () => {
  const mesh = await damagedMesh(24, 10, 3);
  const other = await fromIndexed(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), new Uint32Array([0, 1, 2]));
  const wem = await WorkerEditableMesh.from(mesh);
  try {
    const input = await wem.toStl();
    const otherPlan = await planRepair(other);
    // Checked before anything is sent: the main thread's codes and messages.
    await assert.rejects(wem.planRepair({ steps: ['nope'] }), (e) => e.code === 'invalid-argument' && /unknown repair step nope/.test(e.message));
    await assert.rejects(wem.planRepair({ stitchTolerance: -1 }), (e) => e.code === 'invalid-argument');
    await assert.rejects(wem.applyRepair({}), (e) => e.code === 'invalid-argument' && /needs a plan from planRepair/.test(e.message));
    await assert.rejects(wem.applyRepair(null), (e) => e.code === 'invalid-argument');
    await assert.rejects(wem.toStl({ format: 'obj' }), (e) => e.code === 'invalid-argument');
    await assert.rejects(wem.toMesh({ weld: 'exact' }), (e) => e.code === 'invalid-argument' && /no weld option/.test(e.message));
    await assert.rejects(wem.toMesh({ maxPairs: 0 }), (e) => e.code === 'invalid-argument');
    await assert.rejects(worker.applyRepair(wem, otherPlan), (e) => e.code === 'invalid-argument' && /em\.applyRepair\(plan\)/.test(e.message));
    // Refused in the worker, by the held mesh (the main thread refuses it the same way).
    const em = await EditableMesh.from(mesh);
    let mainError;
    try {
      em.applyRepair(otherPlan);
    } catch (e) {
      mainError = e;
    } finally {
      em.dispose();
    }
    assert.ok(mainError && /another mesh/.test(mainError.message));
    await assert.rejects(wem.applyRepair(otherPlan), (e) => e.code === mainError.code && e.message === mainError.message);
    assert.equal(wem.undoableSteps, 0);
    assert.deepEqual(await wem.toStl(), input, 'the refused plan changed nothing');
    assert.equal(await wem.undo(), null);
    // The handle and its worker still work: a real repair, after the refusals.
    const plan = await wem.planRepair({ steps: ['duplicates', 'orient'] });
    const log = await wem.applyRepair(plan);
    assert.equal(log.steps.length, 2);
    assert.equal(wem.undoableSteps, 2);
    // A plan that no longer fits (the mesh changed) is refused, and the steps stay applied.
    await assert.rejects(wem.applyRepair(plan), (e) => e.code === 'invalid-argument' && /another mesh/.test(e.message));
    assert.equal(wem.undoableSteps, 2);
    assert.equal(await wem.undo(), 'orient');
    assert.equal(await wem.undo(), 'duplicates');
    assert.deepEqual(await wem.toStl(), input);
    // Bad sources.
    await assert.rejects(WorkerEditableMesh.from(null), (e) => e.code === 'invalid-argument' && /needs a Mesh/.test(e.message));
    await assert.rejects(WorkerEditableMesh.from({ positions: new Float32Array(3) }), (e) => e.code === 'invalid-argument');
    await assert.rejects(WorkerEditableMesh.from(mesh, null), (e) => e.code === 'invalid-argument');
    await assert.rejects(WorkerEditableMesh.from({ positions: new Float32Array([0, 0, 0]), triangles: new Uint32Array([0, 0, 7]) }),
      (e) => e instanceof Error && typeof e.code === 'string', 'a bad index is refused by the worker');
    assert.equal((await worker.loadStl(await bytes(mesh))).nTriangles, mesh.nTriangles, 'the workers still load');
  } finally {
    await wem.dispose();
  }
});

test('WorkerEditableMesh: an indexed source, calls made at once run in order, two meshes are independent', async () => {
  const t = damagedTorus(20, 8, 11);
  const a = await WorkerEditableMesh.from({ positions: t.positions, triangles: t.triangles });
  const b = await WorkerEditableMesh.from({ positions: Array.from(t.positions), triangles: Array.from(t.triangles) });
  try {
    assert.equal(t.positions.length > 0 && t.positions.buffer.byteLength > 0, true, "the caller's arrays are not detached");
    const input = await a.toStl();
    assert.deepEqual(await b.toStl(), input);
    const plan = await a.planRepair();
    // Not awaited one by one: the calls are queued and answered in the order they were made.
    const [log, first, second, third, after] = await Promise.all([a.applyRepair(plan), a.undo(), a.undo(), a.undo(), a.toStl()]);
    assert.ok(log.steps.length >= 2, JSON.stringify(log.steps.map((s) => s.step)));
    const names = log.steps.map((s) => s.step).reverse();
    assert.deepEqual([first, second, third], [names[0], names[1], names[2] ?? null]);
    assert.equal(a.undoableSteps, Math.max(0, log.steps.length - 3));
    assert.ok(after instanceof Uint8Array);
    assert.deepEqual(await b.toStl(), input, 'b is its own mesh');
    assert.equal(b.undoableSteps, 0);
    // The main thread's EditableMesh of the same source gives the same log.
    const em = await EditableMesh.from({ positions: t.positions, triangles: t.triangles });
    try {
      assert.deepEqual(em.applyRepair(plan), log);
    } finally {
      em.dispose();
    }
  } finally {
    await Promise.all([a.dispose(), b.dispose()]);
  }
});

test('WorkerEditableMesh: dispose() frees the worker side, then every call is refused', async () => {
  const mesh = await damagedMesh(16, 8, 2);
  const wem = await WorkerEditableMesh.from(mesh);
  const plan = await wem.planRepair();
  const applying = wem.applyRepair(plan); // made before dispose(): it runs first
  const disposing = wem.dispose();
  assert.equal(wem.dispose(), disposing, 'a second dispose() is the first');
  assert.ok((await applying).steps.length > 0);
  await disposing;
  const id = posted.findLast((m) => m.type === 'editable' && m.op === 'open').id;
  assert.ok(posted.some((m) => m.type === 'editable' && m.op === 'dispose' && m.id === id), 'the worker was told to free it');
  await assert.rejects(wem.planRepair(), isDisposed);
  await assert.rejects(wem.applyRepair(plan), isDisposed);
  await assert.rejects(wem.undo(), isDisposed);
  await assert.rejects(wem.stats(), isDisposed);
  await assert.rejects(wem.validate(), isDisposed);
  await assert.rejects(wem.toStl(), isDisposed);
  await assert.rejects(wem.toMesh(), isDisposed);
  await assert.rejects(worker.planRepair(wem), isDisposed);
  assert.throws(() => wem.undoableSteps, isDisposed);
  const n = posted.length;
  await assert.rejects(wem.undo(), isDisposed);
  assert.equal(posted.length, n, 'a refused call sends nothing');
  // The worker went back to the idle ones and serves the next handle.
  const again = await WorkerEditableMesh.from(mesh);
  assert.deepEqual(await again.toStl(), await bytes(mesh));
  await again.dispose();
});

test('WorkerEditableMesh: a handle dropped without dispose() is freed by the finalizer', { skip: typeof globalThis.gc !== 'function' && 'needs --expose-gc' }, async () => {
  const mesh = await damagedMesh(12, 6, 4);
  let id;
  await (async () => {
    const wem = await WorkerEditableMesh.from(mesh);
    id = posted.findLast((m) => m.type === 'editable' && m.op === 'open').id;
    await wem.applyRepair(await wem.planRepair());
  })();
  const freed = () => posted.some((m) => m.type === 'editable' && m.op === 'dispose' && m.id === id);
  assert.ok(!freed());
  for (let i = 0; i < 50 && !freed(); ++i) {
    globalThis.gc();
    await new Promise((r) => setTimeout(r, 20));
  }
  assert.ok(freed(), 'the finalizer told the worker to free the mesh');
});

test('WorkerEditableMesh: a worker that dies takes the mesh with it, and the handle says so', async () => {
  const mesh = await damagedMesh(12, 6, 8);
  const held = [];
  const outer = Worker.prototype.postMessage;
  // The worker of the next handle: the one its open message goes to.
  Worker.prototype.postMessage = function (msg, transfer) {
    if (msg && msg.type === 'editable' && msg.op === 'open') held.push(this);
    return outer.call(this, msg, transfer);
  };
  let wem;
  try {
    wem = await WorkerEditableMesh.from(mesh);
  } finally {
    Worker.prototype.postMessage = outer;
  }
  assert.equal(held.length, 1);
  await held[0].terminate();
  await assert.rejects(wem.undo(), (e) => /the editable mesh was lost with its worker/.test(e.message));
  await assert.rejects(wem.stats(), (e) => /lost with its worker/.test(e.message));
  await wem.dispose(); // resolves: there is nothing left to free
  await assert.rejects(wem.undo(), isDisposed);
  const fresh = await WorkerEditableMesh.from(mesh);
  assert.deepEqual(await fresh.toStl(), await bytes(mesh), 'a new handle gets a new worker');
  await fresh.dispose();
});

test('WorkerEditableMesh: keys the main thread ignores (callbacks, signals) are ignored, not sent', async () => {
  const mesh = await damagedMesh(10, 6, 6);
  const wem = await WorkerEditableMesh.from(mesh);
  const em = await EditableMesh.from(mesh);
  try {
    const extra = { extra: () => 1, signal: new AbortController().signal };
    const first = em.planRepair().steps.find((st) => st.items.length > 0);
    const exclude = [{ step: first.step, item: 0, note: () => 0 }];
    const plan = await wem.planRepair({ ...extra, exclude });
    assert.deepEqual(plan.steps, em.planRepair({ ...extra, exclude }).steps);
    const excluded = plan.steps.find((st) => st.step === first.step).items[0];
    assert.ok(excluded.skipped && /left out by the user/.test(excluded.reason), JSON.stringify(excluded));
    assert.deepEqual(await wem.toStl({ ...extra, format: 'ascii' }), new Uint8Array(em.toStl({ ...extra, format: 'ascii' })));
    const m = await wem.toMesh({ ...extra, onProgress: () => {}, worker: true, shells: true });
    assert.ok(m.shells.length > 0);
    assert.deepEqual(await wem.applyRepair(plan), em.applyRepair(plan));
    assert.equal(await wem.undo(), em.undo());
  } finally {
    em.dispose();
    await wem.dispose();
  }
});

// A { view: true } mesh's arrays are views into wasm memory. A structured clone of a view sends
// its whole buffer (all of wasm memory), so each call sends copies of the elements, and
// transfers them.
test('worker calls on a { view: true } mesh send copies of its arrays, not wasm memory', async () => {
  const { loadStl } = await import('stltopo');
  const source = await bytes(await damagedMesh(16, 12, 5));
  const view = await loadStl(source, { view: true });
  const copy = await loadStl(source);
  const from = posted.length;
  const plan = await worker.planRepair(view, { steps: ['orient', 'fill-holes'] });
  assert.deepEqual(plan.steps.map((s) => s.done), (await planRepair(copy, { steps: ['orient', 'fill-holes'] })).steps.map((s) => s.done));
  const { mesh } = await worker.applyRepair(view, plan);
  assert.equal(mesh.stats.holes, 0);
  assert.deepEqual(await worker.toStl(view), await bytes(copy));
  const em = await WorkerEditableMesh.from(view);
  await em.dispose();
  let arrays = 0;
  const visit = (v, i) => {
    if (ArrayBuffer.isView(v)) {
      ++arrays;
      assert.equal(v.buffer.byteLength, v.byteLength, `message ${i} sends a ${v.constructor.name} with a ${v.buffer.byteLength} B buffer`);
      assert.ok(transfers[i].includes(v.buffer), `message ${i}: its ${v.constructor.name} is transferred`);
    } else if (v && typeof v === 'object') {
      for (const x of Object.values(v)) visit(x, i);
    }
  };
  for (let i = from; i < posted.length; ++i) visit(posted[i], i);
  assert.ok(arrays >= 8, `the four calls sent ${arrays} arrays`);
  view.dispose();
});
