// The 4 GB heap (issue 24): the modules are built with MAXIMUM_MEMORY=4GB, so wasm
// addresses pass 2^31, where a signed pointer in the glue, the bindings or the core would
// break; and the allocator must say "no" at the top of the heap instead of handing out a
// block that runs past 2^32 (Emscripten 3.1.6's emmalloc did: bindings/emmalloc/README.md).
// A ballast malloc'ed in the module pushes every array of a load above 2 GB (pages that are
// never written cost no memory), so this runs in seconds; `npm run bench:big` loads real
// 40M-triangle files. Runs in its own process (node --test), as the heap never shrinks.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { loadStl, fromIndexed, toStl, EditableMesh, StlError, planRepair } from 'stltopo';
import { api } from '../../dist/instance.node.js';
import { fixtures, gridStl, soupStl } from './helpers.mjs';

const _internal = api.internal; // the test hooks (not public)
const TWO_GB = 2 ** 31;
const HALF_EDGE_KEYS = ['next', 'prev', 'vert', 'face'];

// What a load gives, as plain data: the report, every array, validate().
function snapshot(m) {
  const s = { stats: JSON.stringify(m.stats), validation: JSON.stringify(m.validate()) };
  for (const k of ['positions', 'triangles', 'attributes', 'triangleHalfedge', 'vertexHalfedge']) {
    if (m[k]) s[k] = Buffer.from(m[k].buffer, m[k].byteOffset, m[k].byteLength).toString('base64');
  }
  if (m.halfedges) for (const k of HALF_EDGE_KEYS) s[k] = Buffer.from(m.halfedges[k].slice().buffer).toString('base64');
  s.holes = JSON.stringify(m.holes.map((h) => Array.from(h.vertices)));
  return s;
}

// Mallocs `bytes` in the module (in blocks of at most 1 GB), then every free block left
// below 2 GB (what earlier loads freed there: whether the allocator reuses such a hole for a
// small array depends on the exact layout, which a 16-byte allocation anywhere changes);
// returns the pointers.
function ballast(M, bytes) {
  const blocks = [];
  for (let left = bytes; left > 0;) {
    const n = Math.min(left, 2 ** 30);
    const p = M._malloc(n);
    assert.notEqual(p, 0, `the ballast (${bytes} B) fits in the heap`);
    blocks.push(p);
    left -= n;
  }
  for (let n = 1 << 20; n >= 8; n >>= 2) {
    for (;;) {
      const p = M._malloc(n) >>> 0;
      if (p === 0) break;
      blocks.push(p);
      if (p >= TWO_GB) break; // no hole of n bytes left below 2 GB
    }
  }
  return blocks;
}
const freeAll = (M, blocks) => { for (const p of blocks) M._free(p); };

const files = fixtures().filter((f) => readFileSync(f).length < 4 << 20).slice(0, 24);

// A load's snapshot, or its error's code and message (some fixtures are broken on purpose).
async function loadSnapshot(bytes, options) {
  let m;
  try {
    m = await loadStl(bytes, options);
  } catch (e) {
    assert.ok(e instanceof StlError, String(e));
    return { error: `${e.code}: ${e.message}` };
  }
  const s = snapshot(m);
  if (options && options.view) {
    s.aboveTwoGB = m.positions.length === 0 || m.positions.byteOffset >= TWO_GB;
    m.dispose();
  }
  return s;
}

test('every array of a load lives above 2 GB and is the same as below it', async () => {
  const entry = await _internal.getModule();
  assert.ok(entry.heapMax > 4 * 2 ** 30 - 2 ** 20, `the heap may grow to 4 GB (max ${entry.heapMax})`);
  const below = new Map();
  for (const f of files) below.set(f, await loadSnapshot(readFileSync(f)));
  const blocks = ballast(entry.module, TWO_GB + (64 << 20));
  try {
    let above = 0;
    for (const f of files) {
      const bytes = readFileSync(f);
      const { aboveTwoGB, ...view } = await loadSnapshot(bytes, { view: true });
      assert.deepEqual(view, below.get(f), `${f} (view)`);
      if (!view.error) {
        assert.equal(aboveTwoGB, true, `${f}: the arrays lie above 2 GB`);
        above += 1;
      }
      assert.deepEqual(await loadSnapshot(bytes), below.get(f), `${f} (copies)`);
    }
    assert.ok(above > 10, 'most fixtures were checked above 2 GB');
  } finally {
    freeAll(entry.module, blocks);
  }
});

test('the threaded module: a load on 2 threads above 2 GB is the same as on one thread below it', async () => {
  const stl = gridStl(200); // 80,000 triangles: split over the threads at the stages' own grain
  const below = await loadSnapshot(stl, { threads: 1 });
  const mt = await _internal.moduleFor('load', { threads: 2, topology: true });
  assert.ok(mt.module.wasmMemory.buffer instanceof SharedArrayBuffer, 'the threaded module');
  const blocks = ballast(mt.module, TWO_GB + (64 << 20));
  try {
    const m = await loadStl(stl, { threads: 2, view: true });
    assert.equal(m.threads, 2);
    assert.ok(m.positions.byteOffset >= TWO_GB, `positions at ${m.positions.byteOffset}`);
    const view = snapshot(m);
    m.dispose();
    assert.deepEqual(view, below);
    assert.deepEqual(await loadSnapshot(stl, { threads: 2 }), below);
  } finally {
    freeAll(mt.module, blocks);
  }
});

test('fromIndexed, writing and EditableMesh above 2 GB (the full module)', async () => {
  const stl = gridStl(40);
  const before = await loadStl(stl);
  const work = async () => {
    const m = await fromIndexed(before.positions, before.triangles, { view: true });
    const out = { stats: JSON.stringify(m.stats), stl: Buffer.from(await toStl(m)).toString('base64') };
    const em = await EditableMesh.from(m);
    em.reverseTriangle(0);
    for (const t of [1, 2, 3]) em.removeTriangle(t);
    em.splitEdge(em.nHalfedges - 2);
    em.compact();
    out.edited = Buffer.from(em.toStl()).toString('base64');
    out.editedStats = JSON.stringify(em.stats);
    out.valid = JSON.stringify(em.validate());
    em.dispose();
    m.dispose();
    return out;
  };
  const expected = await work();
  const full = await _internal.getFull();
  const blocks = ballast(full.module, TWO_GB + (64 << 20));
  try {
    const m = await fromIndexed(before.positions, before.triangles, { view: true });
    assert.ok(m.positions.byteOffset >= TWO_GB, `positions at ${m.positions.byteOffset}`);
    m.dispose();
    assert.deepEqual(await work(), expected);
  } finally {
    freeAll(full.module, blocks);
  }
});

test('at the top of the 4 GB heap a load fails with out-of-memory, and the module keeps working', async () => {
  const entry = await _internal.getModule();
  const M = entry.module;
  const stl = gridStl(300); // 180,000 triangles: some 15 MB of wasm memory
  const expected = snapshot(await loadStl(stl));
  // Fill the heap to within a few MB of its top, in blocks that get smaller.
  const blocks = [];
  for (let n = 2 ** 30; n >= 1 << 20; n /= 2) {
    for (let p = M._malloc(n) >>> 0; p !== 0; p = M._malloc(n) >>> 0) {
      blocks.push(p);
      // The allocator's contract: a block lies inside memory (3.1.6's emmalloc wrapped past 2^32).
      assert.ok(p + n <= M.HEAPU8.length, `malloc(${n}) gave [${p}, ${p + n}), past the heap's end ${M.HEAPU8.length}`);
    }
  }
  assert.ok(M.HEAPU8.length > 4 * 2 ** 30 - (256 << 20), `the heap grew to ${M.HEAPU8.length} B`);
  try {
    await assert.rejects(loadStl(stl), (e) => e instanceof StlError && e.code === 'out-of-memory');
    assert.equal(await _internal.getModule(), entry, 'the instance did not abort (no trap)');
    assert.equal(entry.dead, false);
  } finally {
    freeAll(M, blocks);
  }
  assert.deepEqual(snapshot(await loadStl(stl)), expected);
  assert.equal(await _internal.getModule(), entry);
});

test('a repair plan past the top of the 4 GB heap: out-of-memory, then the module works again', async () => {
  // A soup's default plan has an item a triangle (its hole filled). Planned with the heap
  // full, it runs out: here at the editor's topology, which the core checks (a status); at
  // an allocation it does not check (a vector or string of the plan: the npm CLI's `repair`
  // of a 2M-triangle soup) the instance aborts, which edit.test.mjs covers.
  const mesh = await loadStl(soupStl(20000));
  const expected = JSON.stringify(await planRepair(mesh));
  const entry = await _internal.getFull();
  const M = entry.module;
  const em = await EditableMesh.from(mesh);
  const other = await EditableMesh.from(mesh);
  const blocks = [];
  for (let n = 2 ** 30; n >= 4096; n /= 2) {
    for (let p = M._malloc(n) >>> 0; p !== 0; p = M._malloc(n) >>> 0) blocks.push(p);
  }
  try {
    assert.throws(() => em.planRepair(), (e) => e instanceof StlError && e.code === 'out-of-memory', 'an StlError');
  } finally {
    if (!entry.dead) freeAll(M, blocks);
  }
  if (entry.dead) {
    // The instance aborted: its meshes say so, and the next EditableMesh gets a fresh one.
    assert.throws(() => other.nTriangles, (e) => e instanceof StlError && /lost/.test(e.message));
    assert.notEqual(await _internal.getFull(), entry);
  } else {
    assert.equal(JSON.stringify(other.planRepair()), expected, 'the same instance carries on');
  }
  other.dispose();
  em.dispose();
  const again = await EditableMesh.from(mesh);
  assert.equal(JSON.stringify(again.planRepair()), expected);
  again.dispose();
});
