// A heap that cannot hold prev and face (issue 24): views and worker loads ask the core for the
// full topology, 8 bytes a half-edge more than copies, and when the wasm heap cannot hold it
// the bindings build the topology without prev and face, which JS then derives on first read,
// as it does for copies. This fills the heap to its top but one free block (`room` bytes) and
// loads a mesh into it at sizes that go from "fits" to "out of memory": in between the load
// must succeed with derived prev and face, the same arrays as ever, and validate() must say
// out-of-memory instead of running. (A 46M-triangle file is where this happens for real:
// `npm run bench:big`.) Runs in its own process (node --test), as the heap never shrinks.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { loadStl, StlError } from 'stltopo';
import { api } from '../../dist/instance.node.js';
import { Mesh } from '../../dist/mesh.js';
import { toSource } from '../../dist/sources.js';
import { normalizeOptions } from '../../dist/options.js';
import { gridStl } from './helpers.mjs';

const _internal = api.internal;
const STL = gridStl(200); // 80,000 triangles, one hole: prev and face are 1.9 MB
const KEYS = ['positions', 'triangles', 'triangleHalfedge', 'vertexHalfedge', 'vertexWeld'];
const HALF_EDGE_KEYS = ['next', 'prev', 'vert', 'face'];

function snapshot(m) {
  const s = { stats: JSON.stringify(m.stats) };
  for (const k of KEYS) s[k] = Buffer.from(m[k].slice().buffer).toString('base64');
  for (const k of HALF_EDGE_KEYS) s[k] = Buffer.from(m.halfedges[k].slice().buffer).toString('base64');
  s.holes = JSON.stringify(m.holes.map((h) => [Array.from(h.halfedges), Array.from(h.vertices)]));
  return s;
}

// Mallocs a block of `room` bytes, then everything else the heap can give up to its top, then
// frees the first block: the next load has that block and the crumbs. Returns the pointers.
function fillBut(M, room) {
  const hole = M._malloc(room) >>> 0;
  assert.notEqual(hole, 0, `a block of ${room} B`);
  const blocks = [];
  for (let n = 2 ** 30; n >= 16;) {
    const p = M._malloc(n) >>> 0;
    if (p === 0) n = Math.floor(n / 2);
    else blocks.push(p);
  }
  M._free(hole);
  return blocks;
}

// Whether a mesh's prev and face were derived in JS: validate() says so (it cannot run in
// wasm without them); otherwise they were in the heap (for a view, views into it).
const wasDerived = (validation) => validation.code === 'out-of-memory' && /prev and face/.test(validation.message);

// The load of STL with `room` bytes free: 'heap' (prev and face built in the heap), 'derived'
// (derived in JS) or 'oom', with its snapshot and validate().
async function attempt(M, room, load) {
  const blocks = fillBut(M, room);
  try {
    const m = await load();
    const validation = m.validate();
    const kind = wasDerived(validation) ? 'derived' : 'heap';
    if (m.view) assert.equal(m.halfedges.prev.buffer === m.halfedges.next.buffer, kind === 'heap', 'views into the heap');
    const r = { kind, snap: snapshot(m), validation };
    m.dispose();
    return r;
  } catch (e) {
    assert.ok(e instanceof StlError, String(e));
    assert.equal(e.code, 'out-of-memory', e.message);
    return { kind: 'oom' };
  } finally {
    for (const p of blocks) M._free(p);
  }
}

// The outcomes from the smallest room that holds the whole topology down to out-of-memory.
async function sweep(M, load) {
  let lo = 0, hi = 64 << 20; // oom at lo, 'heap' at hi
  assert.equal((await attempt(M, hi, load)).kind, 'heap', 'the load fits in 64 MB');
  while (hi - lo > 64 << 10) {
    const mid = Math.floor((lo + hi) / 2 / 16) * 16;
    if ((await attempt(M, mid, load)).kind === 'heap') hi = mid;
    else lo = mid;
  }
  const seen = [];
  for (let room = hi - (64 << 10); room > 0; room -= 128 << 10) {
    const r = await attempt(M, room, load);
    seen.push(r);
    if (r.kind === 'oom') break;
  }
  return seen;
}

test('a view whose heap cannot hold prev and face loads with them derived, the same arrays', async () => {
  const reference = await loadStl(STL);
  const expected = snapshot(reference);
  assert.deepEqual(reference.validate(), { ok: true });
  const { module: M } = await _internal.getModule();
  const seen = await sweep(M, () => loadStl(STL, { view: true }));
  const derived = seen.filter((r) => r.kind === 'derived');
  assert.ok(derived.length >= 3, `derived prev and face in ${derived.length} of ${seen.map((r) => r.kind)}`);
  assert.equal(seen.at(-1).kind, 'oom', 'the sweep ends out of memory');
  for (const r of seen.filter((x) => x.kind !== 'oom')) assert.deepEqual(r.snap, expected);
  // The module keeps working: a view with room has its prev and face in the heap again.
  const again = await loadStl(STL, { view: true });
  assert.equal(again.halfedges.prev.buffer, again.halfedges.next.buffer);
  assert.deepEqual(snapshot(again), expected);
  assert.deepEqual(again.validate(), { ok: true });
  again.dispose();
});

test("a worker's load (copies, validated in wasm) whose heap cannot hold prev and face", async () => {
  const expected = snapshot(await loadStl(STL));
  const { module: M } = await _internal.getModule();
  // What the worker thread runs (worker-handler.js), then what its client makes of the result.
  const load = async () => new Mesh(await _internal.loadRaw(toSource(STL), normalizeOptions({}), { validate: true }));
  const seen = await sweep(M, load);
  const derived = seen.filter((r) => r.kind === 'derived');
  assert.ok(derived.length >= 3, `derived prev and face in ${derived.length} of ${seen.map((r) => r.kind)}`);
  for (const r of seen.filter((x) => x.kind === 'heap')) assert.deepEqual(r.snap, expected);
});

test('the threaded module: a view on 2 threads whose heap cannot hold prev and face', async () => {
  const expected = snapshot(await loadStl(STL));
  const mt = await _internal.moduleFor('load', { threads: 2, topology: true });
  assert.ok(mt.module.wasmMemory.buffer instanceof SharedArrayBuffer, 'the threaded module');
  const seen = await sweep(mt.module, async () => {
    const m = await loadStl(STL, { threads: 2, view: true });
    assert.equal(m.threads, 2);
    return m;
  });
  const derived = seen.filter((r) => r.kind === 'derived');
  assert.ok(derived.length >= 3, `derived prev and face in ${derived.length} of ${seen.map((r) => r.kind)}`);
  for (const r of seen.filter((x) => x.kind !== 'oom')) assert.deepEqual(r.snap, expected);
});
