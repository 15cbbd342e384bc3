// stltopo/worker (worker_threads under Node): same results as inline, progress,
// transferred arrays, errors, and AbortSignal stopping a large parse promptly
// (inline and in the worker).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { loadStl, loadStlFile, StlError } from 'stltopo';
import * as worker from 'stltopo/worker';
import { fixture, gridStl, chunkedStream, meshArrays } from './helpers.mjs';

const bunnyPath = fixture('bunny.stl');
const bunny = new Uint8Array(readFileSync(bunnyPath));
// ~1.1M triangles, 55 MB: big enough that a full parse takes a while.
const BIG_N = 740;
const big = gridStl(BIG_N);

function assertSame(a, b) {
  assert.deepEqual(meshArrays(a), meshArrays(b));
  assert.deepEqual(a.stats, b.stats);
  assert.deepEqual(a.holes, b.holes);
}

test('worker results equal inline results (bytes, Blob, stream, file, options)', async () => {
  const inline = await loadStl(bunny);
  assertSame(await worker.loadStl(bunny), inline);
  assertSame(await worker.loadStl(new Blob([bunny])), inline);
  assertSame(await worker.loadStl(chunkedStream(bunny, 5000)), inline);
  assertSame(await worker.loadStlFile(bunnyPath), inline);
  assertSame(await loadStl(bunny, { worker: true }), inline);
  assertSame(await loadStlFile(bunnyPath, { worker: true }), inline);
  const opts = { topology: false, normals: true };
  assertSame(await worker.loadStl(bunny, opts), await loadStl(bunny, opts));
  assert.equal(bunny.length, readFileSync(bunnyPath).length, "the caller's buffer is not detached");
});

test('worker: arrays arrive as transferred, JS-owned buffers; validate() works', async () => {
  const m = await worker.loadStl(bunny);
  assert.equal(m.view, false);
  assert.ok(m.positions.buffer instanceof ArrayBuffer);
  assert.equal(m.positions.byteOffset, 0);
  assert.equal(m.positions.buffer.byteLength, m.positions.byteLength, 'one buffer per array (sliced)');
  assert.deepEqual(m.validate(), { ok: true });
  assert.equal([...m.faceHalfedges(m.triangleHalfedge[0])].length, 3);
});

test('worker: progress and errors', async () => {
  const calls = [];
  await worker.loadStl(new Blob([bunny]), { onProgress: (f, n) => calls.push([f, n]) });
  assert.deepEqual(calls.at(-1), [1, bunny.length]);
  await assert.rejects(worker.loadStl(bunny.subarray(0, 100)), (e) => e instanceof StlError && e.code === 'truncated' && e.offset === 100);
  await assert.rejects(worker.loadStl(new Uint8Array(0)), (e) => e instanceof StlError && e.code === 'empty');
  await assert.rejects(worker.loadStl(bunny, { maxTriangles: 10 }), (e) => e instanceof StlError && e.code === 'too-large');
  await assert.rejects(worker.loadStl(bunny, { weld: 7 }), (e) => e instanceof StlError && e.code === 'invalid-argument');
  assert.equal((await worker.loadStl(bunny)).nTriangles, (await loadStl(bunny)).nTriangles, 'the worker recovers');
});

async function timeAbort(load, afterMs) {
  const ac = new AbortController();
  const t0 = performance.now();
  let firedAt = NaN;
  setTimeout(() => {
    firedAt = performance.now();
    ac.abort();
  }, afterMs);
  let err = null;
  try {
    await load(ac.signal);
  } catch (e) {
    err = e;
  }
  const end = performance.now();
  // latency: from the abort to the promise's end. The timer itself can fire late when the load
  // keeps the thread busy before the parse starts (the worker's input is copied for its
  // message): that delay is the machine's, not the abort's (a CI run of 2026-12-08 took 386 ms
  // in all on the worker, against a 384 ms bound, with the abort itself prompt).
  return { err, ms: end - t0, latency: end - firedAt };
}

test('AbortSignal stops a large parse promptly (inline and worker)', async () => {
  const t0 = performance.now();
  const full = await loadStl(big);
  const fullMs = performance.now() - t0;
  assert.equal(full.nTriangles, 2 * BIG_N * BIG_N);
  const AFTER = 20;
  for (const [name, load] of [
    ['inline buffer', (signal) => loadStl(big, { signal })],
    ['inline stream', (signal) => loadStl(chunkedStream(big, 1 << 16), { signal })],
    ['worker', (signal) => worker.loadStl(big, { signal })],
  ]) {
    const { err, ms, latency } = await timeAbort(load, AFTER);
    assert.ok(err instanceof StlError, `${name}: ${err}`);
    assert.equal(err.code, 'aborted', name);
    // The inline reader checks the signal at least every ~16 ms of feeding (were it not to
    // yield, the timer would fire after the load and nothing would be aborted); the topology
    // pass cannot be interrupted, but the abort comes before it here; the worker is ended.
    assert.ok(latency < Math.max(250, fullMs / 2),
      `${name}: ended ${latency.toFixed(0)} ms after the abort, ${ms.toFixed(0)} ms in all (full parse ${fullMs.toFixed(0)} ms)`);
  }
  // Still works afterwards.
  assert.equal((await loadStl(bunny)).validate().ok, true);
  assert.equal((await worker.loadStl(bunny)).validate().ok, true);
});

test('loadStlFile: AbortSignal on a large file on disk', async () => {
  const dir = mkdtempSync(path.join(tmpdir(), 'stltopo-'));
  try {
    const f = path.join(dir, 'big.stl');
    writeFileSync(f, big);
    const { err, ms, latency } = await timeAbort((signal) => loadStlFile(f, { signal }), 15);
    assert.ok(err instanceof StlError && err.code === 'aborted', String(err));
    assert.ok(latency < 500, `ended ${latency} ms after the abort, ${ms} ms in all`);
    const m = await loadStlFile(f);
    assert.equal(m.nTriangles, 2 * BIG_N * BIG_N);
    assert.equal(m.holes.length, 1);
    assert.equal(m.holes[0].edgeCount, 4 * BIG_N);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});
