// Every error code comes back as a StlError with its location, and the module
// keeps working after any error.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { loadStl, loadStlFile, StlError } from 'stltopo';
import { api } from '../../dist/instance.node.js';
import { fixture, gridStl, chunkedStream } from './helpers.mjs';

const _internal = api.internal; // the test hooks (not public)

const enc = (s) => new TextEncoder().encode(s);
const cube = readFileSync(fixture('Cube.stl'));
const asciiFacet = (a, b, c) =>
  `facet normal 0 0 1\n outer loop\n  vertex ${a}\n  vertex ${b}\n  vertex ${c}\n endloop\nendfacet\n`;

async function rejects(promise, code) {
  try {
    await promise;
  } catch (e) {
    assert.ok(e instanceof StlError, `expected StlError, got ${e}`);
    assert.ok(e instanceof Error);
    assert.equal(e.name, 'StlError');
    assert.equal(e.code, code, e.message);
    assert.ok(e.message.startsWith(`${code}: `), e.message);
    return e;
  }
  assert.fail(`expected a rejection with ${code}`);
}

test('empty', async () => {
  await rejects(loadStl(new Uint8Array(0)), 'empty');
  await rejects(loadStl(chunkedStream(new Uint8Array(0), 1)), 'empty');
});

test('not-stl', async () => {
  await rejects(loadStl(enc('hello world, this is not an STL file at all')), 'not-stl');
});

test('truncated: carries the offset', async () => {
  const g = gridStl(4);
  const e = await rejects(loadStl(g.subarray(0, g.length - 30)), 'truncated');
  assert.equal(typeof e.offset, 'number');
});

test('unexpected-end and ascii-syntax carry the line', async () => {
  const e1 = await rejects(loadStl(enc('solid x\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n')), 'unexpected-end');
  assert.equal(typeof e1.line, 'number');
  const e2 = await rejects(loadStl(enc(`solid x\n${asciiFacet('0 0 0', '1 0 zero', '0 1 0')}endsolid x\n`)), 'ascii-syntax');
  assert.equal(e2.line, 5);
});

test('non-finite carries the triangle', async () => {
  const g = gridStl(3);
  new DataView(g.buffer).setFloat32(84 + 50 * 5 + 12, NaN, true);
  const e = await rejects(loadStl(g), 'non-finite');
  assert.equal(e.triangle, 5);
});

test('too-large: maxTriangles and maxBytes', async () => {
  await rejects(loadStl(gridStl(10), { maxTriangles: 100 }), 'too-large');
  await rejects(loadStl(gridStl(10), { maxBytes: 1000 }), 'too-large');
  const ok = await loadStl(gridStl(10), { maxTriangles: 200 });
  assert.equal(ok.nTriangles, 200);
});

test('invalid-argument: bad input and bad options', async () => {
  await rejects(loadStl(42), 'invalid-argument');
  await rejects(loadStl(null), 'invalid-argument');
  await rejects(loadStl('solid x'), 'invalid-argument');
  await rejects(loadStl(cube, { weld: 'loose' }), 'invalid-argument');
  await rejects(loadStl(cube, { weld: { tolerance: -1 } }), 'invalid-argument');
  await rejects(loadStl(cube, { maxTriangles: 1.5 }), 'invalid-argument');
  await rejects(loadStl(new Response('nope', { status: 404 })), 'invalid-argument');
  await rejects(loadStl(new ReadableStream({ start(c) { c.enqueue('text chunk'); c.close(); } })), 'invalid-argument');
  await rejects(loadStlFile('/nonexistent/file.stl'), 'invalid-argument');
  const locked = new ReadableStream();
  locked.getReader();
  await rejects(loadStl(locked), 'invalid-argument');
});

test('aborted: an already aborted signal, and an abort mid-stream', async () => {
  await rejects(loadStl(cube, { signal: AbortSignal.abort() }), 'aborted');
  const ac = new AbortController();
  let pulls = 0;
  const slow = new ReadableStream({
    async pull(c) {
      if (++pulls === 3) ac.abort();
      await new Promise((r) => setTimeout(r, 5));
      c.enqueue(cube.subarray(0, 10));
    },
  });
  await rejects(loadStl(slow, { signal: ac.signal }), 'aborted');
});

test('out-of-memory: an exhausted heap is an error, not an abort, and the module recovers', async () => {
  const { getModule } = _internal;
  const entry = await getModule();
  const M = entry.module;
  const big = gridStl(300); // 180k triangles: ~15 MB of arrays
  try {
    for (const leave of [0, 1 << 20, 4 << 20]) {
      M._testFill(leave); // grows the heap to its maximum and leaves ~`leave` bytes allocatable
      await rejects(loadStl(big), 'out-of-memory');
      await rejects(loadStl(big, { view: true }), 'out-of-memory');
      M._testRelease();
    }
  } finally {
    M._testRelease();
  }
  assert.equal(await getModule(), entry, 'a status, not a wasm abort: the same instance carries on');
  const m = await loadStl(big);
  assert.equal(m.nTriangles, 180000);
  assert.deepEqual(m.validate(), { ok: true });
});

test('a wasm abort (RuntimeError) drops the instance; the next load gets a fresh one', async () => {
  const entry = await _internal.getModule();
  assert.throws(() => entry.module._testAbort(), WebAssembly.RuntimeError);
  const m = await loadStl(cube);
  assert.equal(m.nTriangles, 12);
  assert.notEqual(await _internal.getModule(), entry);
});

test('operator new failing: the instance aborts with its reason, an out-of-memory StlError, then a fresh one', async () => {
  // A repair plan's vectors and strings (a soup of 2M triangles) fail in operator new, far
  // below the top of the heap when the block is large; the abort had no reason, and the API
  // gave the raw RuntimeError.
  const entry = await _internal.getModule();
  let raw = null;
  assert.throws(() => entry.module._testNewFails(), (e) => {
    raw = e;
    return e instanceof WebAssembly.RuntimeError;
  });
  assert.match(raw.message, /out of memory/);
  assert.equal(entry.dead, true);
  const err = _internal.wasmFailure(entry, raw);
  assert.ok(err instanceof StlError && err.code === 'out-of-memory', String(err));
  const m = await loadStl(cube);
  assert.equal(m.nTriangles, 12);
  assert.notEqual(await _internal.getModule(), entry);
});

test('1000 alternating bad and good loads: the good results stay right', async () => {
  const good = await loadStl(cube);
  const bads = [
    [new Uint8Array(0), 'empty'],
    [enc('not an stl'), 'not-stl'],
    [gridStl(2).subarray(0, 150), 'truncated'],
    [enc('solid a\nfacet normal 0 0 1\nouter loop\nvertex 1 2 3\n'), 'unexpected-end'],
    [enc(`solid a\n${asciiFacet('0 0 0', '1 0 0', 'x 1 0')}`), 'ascii-syntax'],
  ];
  for (let i = 0; i < 500; ++i) {
    const [bytes, code] = bads[i % bads.length];
    await rejects(loadStl(bytes), code);
    const m = await loadStl(cube);
    assert.deepEqual(m.positions, good.positions);
    assert.deepEqual(m.triangles, good.triangles);
    assert.deepEqual(m.stats, good.stats);
  }
});
