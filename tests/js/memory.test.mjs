// Ownership and memory: copies need no dispose and the wasm heap returns to its
// baseline; { view: true } views are borrowed until dispose(); and what memory
// growth does to views (emscripten#6747).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { loadStl, StlError } from 'stltopo';
import { api } from '../../dist/instance.node.js';
import { fixture, gridStl } from './helpers.mjs';

const _internal = api.internal; // the test hooks (not public)

const bunny = readFileSync(fixture('bunny.stl'));

test('200 loads (copies): the allocator returns to its baseline', async () => {
  await loadStl(bunny); // first load: lazily created statics settle
  const base = (await _internal.heap()).inUse;
  for (let i = 0; i < 200; ++i) {
    const m = await loadStl(bunny);
    assert.ok(m.nTriangles > 0);
    assert.equal((await _internal.heap()).inUse, base, `load ${i}`);
  }
});

test('200 loads with errors, streams and validate(): still the baseline', async () => {
  const broken = new Uint8Array(bunny.subarray(0, bunny.length - 7));
  // One of each first: the allocator starts blocks of 64 KiB and more on a cache line, and
  // the padding that takes goes to the block before, once (bindings/emmalloc/emmalloc.c).
  (await loadStl(new Blob([bunny]))).validate();
  await assert.rejects(loadStl(broken), StlError);
  const base = (await _internal.heap()).inUse;
  for (let i = 0; i < 200; ++i) {
    if (i % 2) await assert.rejects(loadStl(broken), StlError);
    else (await loadStl(new Blob([bunny]))).validate();
  }
  assert.equal((await _internal.heap()).inUse, base);
});

test('view: true gives wasm views that dispose() frees', async () => {
  const base = (await _internal.heap()).inUse;
  const copy = await loadStl(bunny);
  const m = await loadStl(bunny, { view: true });
  assert.equal(m.view, true);
  assert.equal(copy.view, false);
  assert.ok((await _internal.heap()).inUse > base + m.positions.byteLength);
  const { module: M } = await _internal.getModule();
  assert.equal(m.positions.buffer, M.HEAPU8.buffer, 'a view into wasm memory');
  assert.notEqual(copy.positions.buffer, M.HEAPU8.buffer, 'a JS-owned copy');
  assert.deepEqual(m.positions, copy.positions);
  assert.deepEqual(m.halfedges.next, copy.halfedges.next);
  assert.deepEqual(m.validate(), { ok: true });
  m.dispose();
  m.dispose(); // idempotent
  assert.equal((await _internal.heap()).inUse, base);
  assert.throws(() => m.positions, StlError);
  assert.throws(() => m.validate(), StlError);
  copy.dispose(); // a no-op for copies
  assert.equal(copy.positions.length, 3 * copy.nVertices);
});

test('memory growth (emscripten#6747): kept views detach, mesh properties and copies do not', async () => {
  const m = await loadStl(bunny, { view: true });
  const copy = await loadStl(bunny);
  const kept = m.positions; // a view held in a variable
  const keptNext = m.halfedges.next;
  const before = (await _internal.heap()).size;
  // Load something large enough to grow the heap.
  const big = await loadStl(gridStl(Math.ceil(Math.sqrt(before / 150))), { view: true });
  assert.ok((await _internal.heap()).size > before, 'the heap grew');
  assert.equal(kept.length, 0, 'a view taken before growth is detached');
  assert.equal(kept.buffer.byteLength, 0);
  assert.equal(keptNext.length, 0);
  // The mesh's own properties re-create their views; copies were never views.
  assert.deepEqual(m.positions, copy.positions);
  assert.deepEqual(m.halfedges.next, copy.halfedges.next);
  assert.equal(copy.positions.length, 3 * copy.nVertices);
  big.dispose();
  m.dispose();
});

test('a forgotten view mesh is freed by the FinalizationRegistry', { skip: typeof globalThis.gc !== 'function' && 'needs --expose-gc' }, async () => {
  const base = (await _internal.heap()).inUse;
  (await loadStl(bunny, { view: true })).nTriangles;
  for (let i = 0; i < 20 && (await _internal.heap()).inUse !== base; ++i) {
    globalThis.gc();
    await new Promise((r) => setTimeout(r, 10));
  }
  assert.equal((await _internal.heap()).inUse, base);
});
