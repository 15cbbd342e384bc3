// Threads in JS (issue 24): loads through the threaded wasm module (stltopo-wasm-mt,
// stltopo-full-mt) give byte-identical arrays and report JSON for 1, 2 and 4 threads, on
// every fixture, the fuzz seeds and the generated cases of tests/test_threads.cpp, with the
// stages split down to single items (the test grain) so that the small files take the
// threaded paths too; and the npm CLI's --threads N prints the native CLI's bytes.
import test from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, readdirSync, existsSync, statSync } from 'node:fs';
import { execFileSync, spawnSync } from 'node:child_process';
import path from 'node:path';
import { loadStl } from 'stltopo';
import { api } from '../../dist/instance.node.js';
import { fixtures, root, nativeCli, haveNativeCli, damagedTorus, indexedStl, shuffleTriangles } from './helpers.mjs';

const COUNTS = [4, 2, 1]; // 4 first: the threaded module's pool is sized by its first load

// Every array (copies: the derived ones too), the counts and the report of a load.
function snapshot(m) {
  const out = { stats: JSON.stringify(m.stats), nVertices: m.nVertices, nTriangles: m.nTriangles,
    warnings: JSON.stringify(m.warnings), solids: JSON.stringify(m.solids), shells: JSON.stringify(m.shells),
    holes: JSON.stringify(m.holes), seams: JSON.stringify(m.seams) };
  const walk = (obj, prefix) => {
    for (const [k, v] of Object.entries(obj || {})) {
      if (ArrayBuffer.isView(v)) out[prefix + k] = Buffer.from(v.buffer, v.byteOffset, v.byteLength).toString('base64');
    }
  };
  walk(m, '');
  for (const g of ['halfedges', 'problems', 'loops', 'defects', 'intersections']) walk(m[g], `${g}.`);
  if (m.halfedges) for (const k of ['prev', 'face', 'vert']) out[`halfedges.${k}`] = Buffer.from(m.halfedges[k].buffer).toString('base64');
  return out;
}

// The outcome of loading bytes with `threads`: the snapshot, or the error's code and message.
async function outcome(bytes, threads, options = {}) {
  try {
    const m = await loadStl(bytes, { ...options, threads });
    return { threads: m.threads, snap: snapshot(m) };
  } catch (e) {
    return { threads, error: `${e.code}: ${e.message}` };
  }
}

async function expectSame(name, bytes, options) {
  const results = [];
  for (const t of COUNTS) results.push(await outcome(bytes, t, options));
  for (let i = 1; i < results.length; ++i) {
    assert.deepEqual(results[i].error, results[results.length - 1].error, `${name}: error with ${COUNTS[i]} threads`);
  }
  const one = results[results.length - 1];
  for (let i = 0; i < results.length - 1; ++i) {
    assert.deepEqual(results[i].error, one.error, `${name}: ${COUNTS[i]} threads vs 1 (error)`);
    if (one.error) continue;
    assert.equal(results[i].threads, COUNTS[i], `${name}: mesh.threads`);
    const a = results[i].snap, b = one.snap;
    assert.deepEqual(Object.keys(a).sort(), Object.keys(b).sort(), `${name}: the same arrays`);
    for (const k of Object.keys(b)) assert.ok(a[k] === b[k], `${name}: ${k} differs between ${COUNTS[i]} threads and 1`);
  }
  if (!one.error) assert.equal(one.threads, 1);
}

const corePool = () => api.internal.moduleFor('load', { threads: 4, topology: true }); // the threaded core
const fullPool = () => api.internal.moduleFor('load', { threads: 4, topology: true, shells: true });

async function withGrain(g, fn) {
  const [core, full] = [await corePool(), await fullPool()];
  for (const e of [core, full]) e.module._setParallelGrainForTesting(g);
  try {
    await fn();
  } finally {
    for (const e of [core, full]) e.module._setParallelGrainForTesting(0);
  }
}
const splits = async () => (await corePool()).module._parallelSplitsForTesting() + (await fullPool()).module._parallelSplitsForTesting();

test('threads: the threaded modules load in Node, with a pool of 3 workers', async () => {
  const core = await corePool();
  assert.equal(core.pool, 3);
  assert.notEqual(core, await api.internal.moduleFor('load', { threads: 1, topology: true }));
  assert.ok(core.module.wasmMemory.buffer instanceof SharedArrayBuffer, 'shared memory');
  assert.equal(api.internal.threadsError('core'), null);
  const full = await fullPool();
  assert.equal(full.pool, 3);
});

test('threads: every fixture gives the same arrays and report for 1, 2 and 4 threads', async () => {
  const before = await splits();
  let n = 0;
  await withGrain(1, async () => {
    for (const f of fixtures()) {
      const bytes = readFileSync(f);
      const name = path.relative(root, f);
      await expectSame(name, bytes, {});
      await expectSame(`${name} (shells, intersections)`, bytes, { intersections: true });
      ++n;
    }
  });
  assert.ok(n > 50, `${n} fixtures`);
  assert.ok((await splits()) > before + 100, 'the threaded paths ran');
});

test('threads: the fuzz seeds give the same results for 1, 2 and 4 threads', async () => {
  const dir = path.join(root, 'tests/fuzz/seeds');
  const files = existsSync(dir)
    ? readdirSync(dir, { recursive: true }).filter((f) => statSync(path.join(dir, f)).isFile()).sort() : [];
  await withGrain(1, async () => {
    for (const f of files) await expectSame(`seed ${f}`, readFileSync(path.join(dir, f)), { intersections: true });
  });
  assert.ok(files.length > 20, `${files.length} seeds`);
});

// tests/test_threads.cpp's generated cases: a torus in grid order and shuffled (corners
// rotated), signed zeros, several binary parts, a non-finite coordinate late in the file, a
// truncated file and VisCAM attribute words; at the stages' own grain, 1 and 64.
function generated() {
  const { positions, triangles } = damagedTorus(120, 90, 7);
  const grid = indexedStl(positions, triangles, 'grid');
  const shuffled = indexedStl(positions, shuffleTriangles(triangles, 5), 'shuffled');
  const cube = new Float32Array([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]);
  const cubeTris = new Uint32Array([0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7]);
  const negZero = cube.map((x) => (x === 0 ? -0 : x));
  const posAll = new Float32Array([...cube, ...negZero, ...positions]);
  const triAll = new Uint32Array([...cubeTris, ...cubeTris.map((v) => v + 8), ...triangles.map((v) => v + 16)]);
  const signedZeros = indexedStl(posAll, triAll, 'zeros');
  const second = Buffer.from(shuffled);
  second.write('COLOR=\x10\x20\x30\xff second part', 0, 'latin1');
  const parts = Buffer.concat([grid, second, grid]);
  const nonFinite = Buffer.from(shuffled);
  nonFinite.writeFloatLE(NaN, 84 + 50 * 15000 + 12 + 12 + 4);
  const truncated = shuffled.subarray(0, shuffled.length - 75);
  const withWords = Buffer.from(grid);
  for (let r = 0; r < 2000; ++r) withWords[84 + 50 * r * 7 + 49] = 0x80 | (r & 0x7f);
  return { grid, shuffled, 'signed zeros': signedZeros, parts, 'non-finite': nonFinite, truncated, 'viscam words': withWords };
}

test('threads: the generated cases of the native thread test, at grain 0, 1 and 64', async () => {
  const cases = generated();
  for (const g of [0, 1, 64]) {
    const before = await splits();
    await withGrain(g, async () => {
      for (const [name, bytes] of Object.entries(cases)) await expectSame(`${name} grain ${g}`, bytes, { shells: true });
    });
    // At the stages' own grains (0) these cases are too small to split: the read splits only
    // parts of 131,072 records or more (the view test below reads one on threads).
    if (g !== 0) assert.ok((await splits()) > before, `grain ${g}: the threaded paths ran`);
  }
  const e = await outcome(cases['non-finite'], 4);
  assert.match(e.error, /^non-finite: /);
});

test('threads: view meshes of the threaded module read through memory that grew on other threads', async () => {
  const { positions, triangles } = damagedTorus(400, 300, 3); // ~240k triangles: the heap grows during the load
  const bytes = indexedStl(positions, triangles);
  const copy = await loadStl(bytes, { threads: 1 });
  const before = await splits();
  const view = await loadStl(bytes, { threads: 4, view: true });
  try {
    assert.ok((await splits()) > before, 'the threaded paths ran at their own grains');
    assert.equal(view.threads, 4);
    assert.deepEqual(view.triangles, copy.triangles);
    assert.deepEqual(view.halfedges.next, copy.halfedges.next);
    assert.deepEqual(view.halfedges.prev, copy.halfedges.prev);
    assert.deepEqual(view.validate(), copy.validate());
  } finally {
    view.dispose();
  }
});

test('threads: options.threads is checked; 0 is the machine\'s cores', async () => {
  for (const bad of [-1, 1.5, '2', 1025]) {
    await assert.rejects(loadStl(new Uint8Array(84), { threads: bad }), { code: 'invalid-argument' });
  }
  assert.equal(api.internal.threadsFor({ threads: null }), 1, 'Node: one thread unless asked');
  assert.equal(api.internal.threadsFor({ threads: 3 }), 3);
  assert.ok(api.internal.threadsFor({ threads: 0 }) >= 1);
});

test('threads: the npm CLI prints the native CLI\'s bytes with --threads 2 and 4', { skip: !haveNativeCli && 'no native CLI' }, () => {
  const files = fixtures().filter((f) => /\.stl$/i.test(f)).slice(0, 40);
  for (const flags of [['--json'], ['--json', '--shells', '--defects'], ['--json', '--intersections'], []]) {
    for (const t of ['2', '4']) {
      const args = ['info', ...flags, '--threads', t, ...files];
      const native = spawnSync(nativeCli, args, { encoding: 'buffer' });
      const npm = spawnSync(process.execPath, [path.join(root, 'bin/stltopo.mjs'), ...args], { encoding: 'buffer' });
      assert.equal(npm.status, native.status, `${flags.join(' ')} --threads ${t}: exit status`);
      assert.ok(npm.stdout.equals(native.stdout), `${flags.join(' ')} --threads ${t}: stdout`);
      assert.ok(npm.stderr.equals(native.stderr), `${flags.join(' ')} --threads ${t}: stderr`);
    }
  }
  // A script that loaded through the threaded module ends by itself (the pool is unref'd).
  const out = execFileSync(process.execPath, ['--input-type=module', '-e',
    "import { loadStl } from 'stltopo'; const m = await loadStl(new Uint8Array(84), { threads: 2 }); console.log(m.threads);"],
  { cwd: root, timeout: 30000, encoding: 'utf8' });
  assert.equal(out.trim(), '2');
});
