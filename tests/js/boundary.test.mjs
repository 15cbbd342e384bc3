// The C++/JS boundary: the bindings' array table (STLTOPO_JS_ARRAYS) is what the mesh
// holds and what index.d.ts and docs/JS-API.md say; worker loads hand over what the
// worker built; options and error codes mean the same on both sides.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, mkdtempSync, rmSync, copyFileSync } from 'node:fs';
import { spawnSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import { pathToFileURL } from 'node:url';
import path from 'node:path';
import { loadStl, loadStlFile, StlError, fromIndexed } from 'stltopo';
import * as worker from 'stltopo/worker';
import { api } from '../../dist/instance.node.js';
import { fixture, gridStl, root, nativeCli, haveNativeCli, soupStl } from './helpers.mjs';

const { layout, module: M } = await api.internal.getModule();
const counts = (m) => ({
  vertex: m.nVertices, triangle: m.nTriangles, halfedge: m.nHalfedges, pair: m.nHalfedges / 2,
  loop: m.loops ? m.loops.offsets.length - 1 : 0, 'loop+1': m.loops ? m.loops.offsets.length : 0,
  'loop entry': m.loops ? m.loops.halfedges.length : 0,
  'non-manifold edge': m.defects ? m.defectCount('nonManifoldEdges') : 0,
  'non-manifold edge+1': m.defects ? m.defectCount('nonManifoldEdges') + 1 : 0,
  'edge entry': m.defects ? m.defects.nonManifoldEdgeTriangles.length : 0,
  'inconsistent edge': m.defects ? m.defectCount('inconsistentEdges') : 0,
  'non-manifold vertex': m.defects ? m.defectCount('nonManifoldVertices') : 0,
  'degenerate triangle': m.defects ? m.defectCount('degenerateTriangles') : 0,
});
const at = (m, d) => (d.group ? m[d.group] && m[d.group][d.key] : m[d.key]);

test('every row of the array table is on the mesh: its type, its length, null when absent', async () => {
  assert.ok(layout.length >= 21);
  // VisCAM colours, normals kept, topology, shells: every condition holds.
  const g = gridStl(3);
  new DataView(g.buffer).setUint16(84 + 48, 0x8000 | 31, true);
  for (const view of [false, true]) {
    const m = await loadStl(g, { normals: true, view, shells: true });
    const n = counts(m);
    // The rows of fromIndexed() meshes, on one of the grid's own arrays.
    const fi = await fromIndexed(m.positions, m.triangles, { view });
    n['input vertex'] = m.nVertices;
    for (const d of layout) {
      const a = at(d.when === 'indexed' ? fi : m, d);
      assert.equal(a?.constructor.name, d.type, `${d.name} (view ${view})`);
      assert.equal(a.length, d.width * n[d.element], `${d.name} has ${d.width} per ${d.element}`);
    }
    m.dispose();
    fi.dispose();
  }
  const bare = await loadStl(gridStl(3), { topology: false });
  for (const d of layout) {
    if (d.when === 'mesh') assert.ok(at(bare, d), d.name);
    else if (d.group) assert.equal(bare[d.group], null, d.name);
    else assert.equal(bare[d.key], null, d.name);
  }
});

test('index.d.ts and docs/JS-API.md list exactly the table (scripts/gen-api-docs.mjs --check)', () => {
  const r = spawnSync(process.execPath, ['scripts/gen-api-docs.mjs', '--check'], { cwd: root });
  assert.equal(r.status, 0, r.stderr.toString());
});

test('worker loads: the arrays the worker built (prev, face, vert) arrive, nothing is rebuilt on this thread', async () => {
  const bytes = readFileSync(fixture('Spider_binary.stl'));
  const w = await worker.loadStl(bytes);
  const inline = await loadStl(bytes);
  for (const d of layout.filter((x) => x.derived)) {
    const desc = Object.getOwnPropertyDescriptor(w[d.group] || w, d.key);
    assert.ok('value' in desc && !desc.get, `${d.name} is a plain property of the worker result`);
    assert.deepEqual(desc.value, at(inline, d), d.name);
  }
  assert.deepEqual(w.validate(), { ok: true });
});

test('maxTriangles: 0 is an invalid-argument, as in both CLIs (inline and worker)', async () => {
  const bytes = gridStl(2);
  const bad = (e) => e instanceof StlError && e.code === 'invalid-argument' && /maxTriangles/.test(e.message);
  for (const n of [0, -1, 1.5, 2 ** 32]) {
    await assert.rejects(loadStl(bytes, { maxTriangles: n }), bad, String(n));
    await assert.rejects(worker.loadStl(bytes, { maxTriangles: n }), bad, String(n));
  }
  assert.equal((await loadStl(bytes, { maxTriangles: 8 })).nTriangles, 8);
  await assert.rejects(loadStl(bytes, { maxTriangles: 7 }), (e) => e.code === 'too-large');
  // The CLIs refuse 0 too (usage error).
  const cli = spawnSync(process.execPath, ['bin/stltopo.mjs', 'info', '--max-triangles', '0', 'x.stl'], { cwd: root });
  assert.equal(cli.status, 2);
});

test('loadStlFile(URL): file: URLs are paths (also with %-escapes), other URLs are not, inline and in the worker', async () => {
  const dir = mkdtempSync(path.join(tmpdir(), 'stltopo url %20 #'));
  try {
    const f = path.join(dir, 'a b%c.stl');
    copyFileSync(fixture('Cube.stl'), f);
    const url = pathToFileURL(f);
    assert.match(url.href, /%25/);
    assert.equal((await loadStlFile(url)).nTriangles, 12);
    assert.equal((await worker.loadStlFile(url)).nTriangles, 12);
    // Not a file URL: the path part must not be read as a local path.
    const web = new URL(`https://example.com${pathToFileURL(fixture('Cube.stl')).pathname}`);
    const bad = (e) => e instanceof StlError && e.code === 'invalid-argument';
    await assert.rejects(loadStlFile(web), bad);
    await assert.rejects(worker.loadStlFile(web), bad);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test('error codes: every code of the core round-trips through errorJson; an unknown name says so', async () => {
  const n = M._codeCount();
  assert.ok(n >= 15);
  const names = [];
  for (let c = 1; c < n; ++c) {
    const code = M._codeName(c);
    names.push(code);
    const line = JSON.parse(await api.internal.errorJson('f.stl', { code, message: `${code}: x` }));
    assert.equal(line.error.code, code);
    assert.equal(line.error.message, `${code}: x`);
  }
  assert.equal(new Set(names).size, n - 1);
  assert.ok(!names.includes('unknown'));
  const line = JSON.parse(await api.internal.errorJson('f.stl', { code: 'no-such-code', message: 'no-such-code: x' }));
  assert.equal(line.error.code, 'invalid-argument');
  assert.match(line.error.message, /unknown error code 'no-such-code'/);
});

test('the npm CLI prints the native bytes for a missing file (errorJson from JS)', { skip: !haveNativeCli && 'no native CLI' }, () => {
  const args = ['info', '--json', 'no/such.stl'];
  const a = spawnSync(nativeCli, args, { cwd: root });
  const b = spawnSync(process.execPath, ['bin/stltopo.mjs', ...args], { cwd: root });
  assert.ok(a.stdout.equals(b.stdout));
  assert.equal(JSON.parse(b.stdout.toString()).error.code, 'invalid-argument');
});

test('the entry points export the public API only (no _internal, no fileSource), and exports maps no internal file', async () => {
  const pkg = JSON.parse(readFileSync(path.join(root, 'package.json'), 'utf8'));
  // ./worker-thread and the two .wasm files: the files a bundler is pointed at (README, Bundlers).
  assert.deepEqual(Object.keys(pkg.exports).sort(),
    ['.', './package.json', './stltopo-full.wasm', './stltopo-wasm.wasm', './three', './worker', './worker-thread']);
  const pub = ['DEFECT_KINDS', 'EdgeKind', 'GEOMETRY_DEFECT_KINDS', 'Mesh', 'REPAIR_DEFAULTS', 'REPAIR_STEPS', 'StlError', 'extractShell',
    'fromIndexed', 'init', 'kInvalid', 'loadStl', 'loadStlFile', 'planUnion', 'toStl', 'unionShells', 'writeStl'];
  // The editable mesh lives where it is made: EditableMesh in the main entries, WorkerEditableMesh
  // (held in a worker) in the worker's; both have planRepair, the worker also applyRepair (on a
  // copy, returning the repaired mesh).
  assert.deepEqual(Object.keys(await import('stltopo')).sort(), [...pub, 'EditableMesh', 'planRepair'].sort());
  assert.deepEqual(Object.keys(worker).sort(), [...pub, 'WorkerEditableMesh', 'applyRepair', 'planRepair'].sort());
  assert.deepEqual(Object.keys(await import('stltopo/three')).sort(),
    ['fromBufferGeometry', 'holesToLineSegments', 'problemEdgesToLineSegments', 'srgbByteTable', 'toBufferGeometry']);
  await assert.rejects(import('stltopo/dist/instance.node.js'), { code: 'ERR_PACKAGE_PATH_NOT_EXPORTED' });
});

test('holes and seams are built on first read: a soup loads without a loop object, then gives them all', async () => {
  // A soup (no corner shared): a hole a triangle. Its loop objects, some 340 bytes of JS heap
  // each, were built by every load, and ended Node with a fatal out-of-memory at 11M.
  const n = 5000;
  const bytes = soupStl(n);
  for (const m of [await loadStl(bytes), await loadStl(bytes, { view: true }), await worker.loadStl(bytes)]) {
    for (const key of ['holes', 'seams']) {
      assert.equal(typeof Object.getOwnPropertyDescriptor(m, key).get, 'function', `${key} not built by the load`);
    }
    assert.equal(m.stats.holes, n);
    const holes = m.holes;
    assert.equal(Object.getOwnPropertyDescriptor(m, 'holes').value, holes, 'built once, then a plain property');
    assert.equal(Object.getOwnPropertyDescriptor(m, 'seams').value.length, 0, 'seams built with them');
    assert.equal(holes.length, n);
    const { offsets, halfedges } = m.loops;
    holes.forEach((h, i) => {
      assert.equal(h.id, i);
      assert.equal(h.face, n + i);
      assert.deepEqual([...h.halfedges], [...halfedges.subarray(offsets[i], offsets[i + 1])]);
      assert.deepEqual([...h.vertices], [...h.halfedges].map((e) => m.halfedges.vert[e]));
      assert.equal(h.edgeCount, 3);
    });
    assert.deepEqual(Object.keys(m).filter((k) => k === 'holes' || k === 'seams'), ['holes', 'seams'], 'still own, enumerable');
    m.holes = [];
    assert.deepEqual(m.holes, [], 'and writable');
    m.dispose?.();
  }
  // Set before the first read: the value set stays when the other list is built.
  const set = await loadStl(bytes);
  set.holes = [];
  assert.deepEqual(set.seams, []);
  assert.deepEqual(set.holes, [], 'the holes set before seams were read');
  set.seams = ['x'];
  assert.deepEqual(set.seams, ['x']);
});
