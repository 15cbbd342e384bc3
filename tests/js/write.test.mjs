// Writing STL and meshes from indexed arrays in the npm package: round trips on every
// fixture, array by array; the same bytes as the native writer (npm CLI convert against
// the native CLI); chunks; the worker; fromIndexed and stltopo/three's fromBufferGeometry
// against loadStl; coded errors.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync, mkdtempSync, readdirSync, writeFileSync, existsSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { loadStl, fromIndexed, writeStl, toStl, StlError } from 'stltopo';
import * as worker from 'stltopo/worker';
import { fromBufferGeometry } from 'stltopo/three';
import { BufferGeometry, BufferAttribute } from 'three';
import { STLLoader } from 'three/examples/jsm/loaders/STLLoader.js';
import { api, fileSource } from '../../dist/instance.node.js';
import { cliCalls } from '../../bin/cli-wasm.mjs';
import { fixtures, fixture, nativeCli, haveNativeCli, root, meshArrays, runAsync, pool } from './helpers.mjs';

const readable = [];
for (const f of fixtures()) {
  try {
    await loadStl(readFileSync(f), { topology: false });
    readable.push(f);
  } catch {}
}
const name = (f) => path.relative(root, f);

const sameBytes = (a, b) => a.length === b.length && Buffer.from(a.buffer, a.byteOffset, a.length).equals(Buffer.from(b.buffer, b.byteOffset, b.length));
// Float32Arrays bit for bit.
const sameBits = (a, b) => a.length === b.length && sameBytes(new Uint8Array(a.buffer, a.byteOffset, a.byteLength), new Uint8Array(b.buffer, b.byteOffset, b.byteLength));

function assertSameMesh(a, b, what, { colors = true } = {}) {
  assert.ok(sameBits(a.positions, b.positions), `${what}: positions`);
  assert.deepEqual(b.triangles, a.triangles, `${what}: triangles`);
  assert.deepEqual(b.solids, a.solids, `${what}: solids`);
  if (colors) {
    assert.deepEqual(b.attributes, a.attributes, `${what}: attributes`);
    assert.equal(b.colorConvention, a.colorConvention, `${what}: colorConvention`);
    assert.deepEqual(b.colors, a.colors, `${what}: colors`);
    assert.deepEqual(b.colorValid, a.colorValid, `${what}: colorValid`);
  }
}

test('toStl: every fixture reads back with the same arrays, binary and ASCII', async () => {
  assert.ok(readable.length >= 50);
  for (const f of readable) {
    const m = await loadStl(readFileSync(f));
    const bin = await toStl(m);
    assert.ok(bin instanceof Uint8Array);
    const back = await loadStl(bin);
    assert.equal(back.format, 'binary');
    assertSameMesh(m, back, `${name(f)} binary`);
    assert.equal(bin.length, 84 * m.solids.length + 50 * m.nTriangles);
    const asc = await toStl(m, { format: 'ascii' });
    const backA = await loadStl(asc);
    assert.equal(backA.format, 'ascii');
    // ASCII keeps no attribute words or colours, and cuts names at control bytes.
    assert.ok(sameBits(m.positions, backA.positions), `${name(f)} ascii positions`);
    assert.deepEqual(backA.triangles, m.triangles, `${name(f)} ascii triangles`);
    assert.deepEqual(backA.solids.map((s) => s.triangleCount), m.solids.map((s) => s.triangleCount));
    if (m.format === 'ascii') assertSameMesh(m, backA, `${name(f)} ascii`);
    // The same topology.
    assert.deepEqual({ ...backA.stats, format: m.stats.format, solids: m.stats.solids, warnings: m.stats.warnings },
      { ...m.stats, colors: 'none', normalMismatches: backA.stats.normalMismatches }, name(f));
  }
});

test('toStl in Node copies a binary file once into an array of its size, and does not trust the figures for it', async () => {
  // One solid, and two (a binary file has 84 bytes a solid and 50 a triangle); copies and views.
  const meshes = [];
  for (const f of ['rear_case.stl', 'multibody.stl']) {
    const bytes = readFileSync(fixture(f));
    meshes.push(await loadStl(bytes), await loadStl(bytes, { view: true }));
  }
  assert.deepEqual(meshes.map((m) => m.solids.length), [1, 1, 2, 2]);
  for (const m of meshes) {
    const chunks = [];
    for await (const c of writeStl(m)) chunks.push(c);
    const whole = Buffer.concat(chunks);
    const bin = await toStl(m);
    assert.ok(sameBytes(bin, whole));
    assert.equal(bin.buffer.byteLength, bin.length);
    // The array is sized from nTriangles and solids; a changed figure still gives the file.
    const n = m.nTriangles;
    for (const wrong of [0, 1, n + 7, 1e15, -1, NaN]) {
      m.nTriangles = wrong;
      assert.ok(sameBytes(await toStl(m), whole), `nTriangles ${wrong}`);
    }
    m.nTriangles = n;
    if (m.dispose) m.dispose();
  }
});

test('writeStl: bounded chunks that join to toStl; views and the worker write the same bytes', async () => {
  const bytes = readFileSync(fixture('rear_case.stl'));
  const m = await loadStl(bytes);
  for (const format of ['binary', 'ascii']) {
    const whole = await toStl(m, { format });
    const chunks = [];
    for await (const c of writeStl(m, { format, chunkBytes: 20000 })) chunks.push(c);
    assert.ok(chunks.length > 1);
    assert.ok(chunks.every((c) => c instanceof Uint8Array && c.length <= 20000 && c.length > 0));
    assert.ok(sameBytes(Buffer.concat(chunks), whole), format);
    const view = await loadStl(bytes, { view: true });
    assert.ok(sameBytes(await toStl(view, { format }), whole), `${format} view`);
    view.dispose();
    // A mesh loaded in a worker is written in a worker.
    const wm = await worker.loadStl(bytes);
    const wchunks = [];
    for await (const c of writeStl(wm, { format, chunkBytes: 100000 })) wchunks.push(c);
    assert.ok(sameBytes(Buffer.concat(wchunks), whole), `${format} worker`);
    // Stopping early is fine, and the next write works.
    for await (const c of worker.writeStl(m, { format, chunkBytes: 20000 })) { assert.ok(c.length > 0); break; }
    assert.ok(sameBytes(await toStl(wm, { format }), whole));
  }
  // Options.
  const named = await loadStl(await toStl(m, { name: 'renamed', format: 'ascii' }));
  assert.equal(named.solids[0].name, 'renamed');
  await assert.rejects(toStl(m, { format: 'obj' }), (e) => e instanceof StlError && e.code === 'invalid-argument');
  await assert.rejects(toStl({}, {}), (e) => e.code === 'invalid-argument');
});

test('fromIndexed: every fixture as a triangle soup gives the mesh, stats and topology of loadStl', async () => {
  for (const f of readable) {
    const m = await loadStl(readFileSync(f));
    const soup = new Float32Array(9 * m.nTriangles);
    for (let c = 0; c < 3 * m.nTriangles; ++c) soup.set(m.positions.subarray(3 * m.triangles[c], 3 * m.triangles[c] + 3), 3 * c);
    const ids = Uint32Array.from({ length: 3 * m.nTriangles }, (_, i) => i);
    const magics = m.colorConvention === 'magics'; // its colours need the header's COLOR=
    const fi = await fromIndexed(soup, ids, { solids: m.solids, attributes: magics ? undefined : m.attributes });
    assert.equal(fi.format, 'unknown');
    const a = meshArrays(m), b = meshArrays(fi);
    for (const k of Object.keys(a)) {
      if (['normals', ...(magics ? ['attributes', 'colors', 'colorValid'] : [])].includes(k)) continue;
      assert.deepEqual(b[k], a[k], `${name(f)}: ${k}`);
    }
    const drop = ({ format, normalMismatches, warnings, colors, ...rest }) => rest;
    assert.deepEqual(drop(fi.stats), drop(m.stats), name(f));
    assert.deepEqual(fi.holes.map((h) => [...h.vertices]), m.holes.map((h) => [...h.vertices]));
    for (let c = 0; c < ids.length; ++c) assert.equal(fi.inputVertexMap[c], m.triangles[c]);
    assert.deepEqual(fi.validate(), { ok: true }, name(f));
    assert.equal(m.inputVertexMap, null);
  }
});

test('fromIndexed: weld none keeps the caller ids, the worker and view options, coded errors', async () => {
  // Two triangles over a shared edge, the shared corners duplicated (a UV seam).
  const pos = new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]);
  const tri = new Uint32Array([0, 1, 2, 3, 4, 5]);
  const welded = await fromIndexed(pos, tri);
  assert.equal(welded.nVertices, 4);
  assert.equal(welded.stats.holes, 1);
  assert.deepEqual([...welded.inputVertexMap], [0, 1, 2, 1, 3, 2]);
  const kept = await fromIndexed(pos, tri, { weld: 'none' });
  assert.equal(kept.nVertices, 6);
  assert.equal(kept.stats.holes, 2);
  assert.deepEqual([...kept.inputVertexMap], [0, 1, 2, 3, 4, 5]);
  assert.deepEqual(kept.validate(), { ok: true });
  const tol = await fromIndexed(pos, tri, { weld: { tolerance: 1e-6 } });
  assert.equal(tol.stats.holes, 1);
  const inWorker = await worker.fromIndexed(pos, tri, { weld: 'none' });
  assert.deepEqual(meshArrays(inWorker), meshArrays(kept));
  assert.deepEqual(inWorker.validate(), { ok: true });
  const viaOption = await fromIndexed([...pos], [...tri], { worker: true });
  assert.deepEqual(meshArrays(viaOption), meshArrays(welded));
  const view = await fromIndexed(pos, tri, { view: true });
  assert.deepEqual([...view.positions], [...welded.positions]);
  assert.deepEqual(view.validate(), { ok: true });
  view.dispose();
  const code = async (p, t, o) => {
    try {
      await fromIndexed(p, t, o);
    } catch (e) {
      assert.ok(e instanceof StlError);
      assert.ok(e.message.startsWith(`${e.code}: `), e.message);
      return e;
    }
    assert.fail('no error');
  };
  let e = await code(pos, new Uint32Array([0, 1, 6]));
  assert.equal(e.code, 'invalid-index');
  assert.equal(e.triangle, 0);
  e = await code(pos, new Uint32Array([0, 1]));
  assert.equal(e.code, 'invalid-argument');
  e = await code(pos.subarray(0, 17), tri);
  assert.equal(e.code, 'invalid-argument');
  const nan = pos.slice();
  nan[13] = NaN;
  e = await code(nan, tri);
  assert.equal(e.code, 'non-finite');
  assert.match(e.message, /vertex 4/);
  e = await code(pos, tri, { solids: [{ name: 'a', firstTriangle: 0, triangleCount: 3 }] });
  assert.equal(e.code, 'invalid-argument');
  e = await code(pos, tri, { solids: [{ name: 'a', firstTriangle: 0, triangleCount: 2 }, { name: 'b', firstTriangle: 1, triangleCount: 1 }] });
  assert.match(e.message, /overlaps/);
  e = await code(pos, tri, { weld: 'glue' });
  assert.equal(e.code, 'invalid-argument');
  // The module keeps working after the errors.
  assert.equal((await fromIndexed(pos, tri)).nVertices, 4);
});

// Where three.js's STLLoader reads other triangles than stltopo, and why.
const STLLOADER_DIFFERS = {
  'Pix4D_OpenMesh/src/Unittests/TestFiles/cube1.stl': 'no endsolid: STLLoader finds no solid (stltopo: missing-endsolid warning)',
  'wolph_numpy-stl/tests/stl_ascii/HalfDonut.stl': "upper-case keywords: STLLoader's /solid...endsolid/ is case-sensitive and finds no solid",
  'wolph_numpy-stl/tests/stl_binary/HalfDonut.stl': "one trailing byte: STLLoader's exact-size test fails and it reads the 'solid' header as ASCII",
  'mikedh_trimesh/models/empty.stl': 'no triangles: STLLoader throws (DataView offset)',
  'mikedh_trimesh/models/emptyIO/stl_empty_ascii.stl': 'no triangles: STLLoader throws (DataView offset)',
  'regress/detect-solid-at-eof.stl': "'solid' and nothing else: STLLoader throws",
  'regress/topology-zero-vertices.stl': 'no triangles: STLLoader throws',
};

test('stltopo/three: STLLoader output through fromBufferGeometry has the topology of loadStl, on every fixture', async () => {
  const loader = new STLLoader();
  const differs = [];
  for (const f of readable) {
    const bytes = readFileSync(f);
    const m = await loadStl(bytes);
    let geometry;
    try {
      geometry = loader.parse(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length));
    } catch {
      differs.push(path.relative(path.join(root, 'tests/fixtures'), f));
      continue;
    }
    const g = await fromBufferGeometry(geometry);
    if (g.nTriangles !== m.nTriangles) {
      differs.push(path.relative(path.join(root, 'tests/fixtures'), f));
      continue;
    }
    // The same floats (STLLoader's ASCII numbers: parseFloat, then float32), the same weld.
    assert.ok(sameBits(g.positions, m.positions), name(f));
    assert.deepEqual(g.triangles, m.triangles, name(f));
    assert.deepEqual(g.halfedges.next, m.halfedges.next, name(f));
    assert.deepEqual(g.halfedges.vert, m.halfedges.vert, name(f));
    assert.deepEqual(g.holes.map((h) => [...h.halfedges]), m.holes.map((h) => [...h.halfedges]), name(f));
    for (const k of ['edges', 'boundaryEdges', 'nonManifoldEdges', 'inconsistentEdges', 'holes', 'holeSizes', 'seams', 'shells',
      'eulerCharacteristic', 'genus', 'watertight', 'manifold', 'area', 'volume', 'bbox']) {
      assert.deepEqual(g.stats[k], m.stats[k], `${name(f)}: ${k}`);
    }
  }
  assert.deepEqual(differs.sort(), Object.keys(STLLOADER_DIFFERS).sort());
});

test('stltopo/three: fromBufferGeometry takes indexed geometry (seams welded unless weld: none) and groups as solids', async () => {
  // A square of two triangles with the diagonal's corners duplicated, as renderers split UV seams.
  const g = new BufferGeometry();
  g.setAttribute('position', new BufferAttribute(new Float32Array([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0]), 3));
  g.setIndex([0, 1, 2, 3, 4, 5]);
  g.addGroup(0, 3, 0);
  g.addGroup(3, 3, 1);
  const m = await fromBufferGeometry(g);
  assert.equal(m.nVertices, 4);
  assert.equal(m.stats.holes, 1);
  assert.deepEqual(m.solids.map((s) => [s.name, s.triangleCount]), [['material 0', 1], ['material 1', 1]]);
  assert.equal((await fromBufferGeometry(g, { weld: 'none' })).stats.holes, 2);
  // Non-indexed geometry is welded exactly, whatever weld says.
  g.setIndex(null);
  assert.equal((await fromBufferGeometry(g, { weld: 'none' })).nVertices, 4);
  await assert.rejects(fromBufferGeometry(new BufferGeometry()), (e) => e.code === 'invalid-argument');
});

// ---------------------------------------------------------------------------
// npm CLI convert against the native CLI.
const npmCli = path.join(root, 'bin/stltopo.mjs');
const skip = !haveNativeCli && `no native CLI at ${nativeCli}`;
const cliWasm = cliCalls(api.internal); // what bin/stltopo.mjs calls
const run = (cmd, args, input) => spawnSync(cmd, args, { cwd: root, input, maxBuffer: 1 << 28 });

test('convert: the npm CLI writes the native CLI\'s bytes on every fixture', { skip }, async () => {
  const dir = mkdtempSync(path.join(tmpdir(), 'stltopo-convert-'));
  // Every fixture with each set of flags. The npm CLI's convert is its argument parsing and
  // output file around cliCalls(...).convert (bin/cli-wasm.mjs): that call runs here on every
  // job, in this process, against a native CLI process; the npm CLI itself runs as a process on
  // one job in eight (each flag set among them), as a user runs it. One
  // process per job took 48 s of the suite (about 210 ms per npm CLI start), this takes ~13.
  // Each set of flags with the write options the npm CLI makes of it.
  const flagSets = [
    { flags: [], w: {} },
    { flags: ['--ascii'], w: { format: 'ascii' } },
    { flags: ['--binary', '--colors', 'viscam', '--name', 'x'], w: { format: 'binary', colors: 'viscam', name: 'x' } },
  ];
  const jobs = [];
  for (const f of readable) for (const set of flagSets) jobs.push({ f, ...set });
  let processes = 0;
  await pool(jobs, async ({ f, flags, w }, i) => {
    const a = path.join(dir, `native${i}.stl`), b = path.join(dir, `npm${i}.stl`);
    const rn = await runAsync(nativeCli, ['convert', f, a, ...flags], undefined, { cwd: root });
    assert.equal(rn.status, 0, rn.stderr.toString());
    const chunks = [];
    for await (const c of cliWasm.convert(await fileSource(f), w)) chunks.push(Buffer.from(c));
    assert.ok(readFileSync(a).equals(Buffer.concat(chunks)), `${name(f)} ${flags.join(' ')} (in process)`);
    if (i % 8 === 0) {
      ++processes;
      const rw = await runAsync(process.execPath, [npmCli, 'convert', f, b, ...flags], undefined, { cwd: root });
      assert.equal(rw.status, 0, rw.stderr.toString());
      assert.ok(readFileSync(a).equals(readFileSync(b)), `${name(f)} ${flags.join(' ')}`);
      rmSync(b);
    }
    rmSync(a);
  });
  assert.ok(processes >= 20, `${processes} npm CLI processes`);
  // Standard input and output.
  const f = fixture('multibody.stl');
  const rn = run(nativeCli, ['convert', '-', '-', '--binary'], readFileSync(f));
  const rw = run(process.execPath, [npmCli, 'convert', '-', '-', '--binary'], readFileSync(f));
  assert.equal(rw.status, 0);
  assert.ok(rw.stdout.equals(rn.stdout) && rn.stdout.length > 84);
  assert.deepEqual(readdirSync(dir), []); // no temporary file left
});

test('convert: the same errors, exit codes and usage; a failure leaves no OUT', { skip }, () => {
  const dir = mkdtempSync(path.join(tmpdir(), 'stltopo-convert-err-'));
  const bad = path.join(dir, 'bad.stl');
  writeFileSync(bad, 'solid x\n facet normal 0 0 zero\n');
  for (const args of [
    ['convert', bad, path.join(dir, 'out.stl')],
    ['convert', path.join(dir, 'missing.stl'), path.join(dir, 'out.stl')],
    ['convert', fixture('multibody.stl'), path.join(dir, 'no/such/dir/out.stl')],
    ['convert', fixture('multibody.stl')],
    ['convert', fixture('multibody.stl'), 'x.stl', '--colors', 'rainbow'],
    ['convert', fixture('multibody.stl'), 'x.stl', '--name'],
    ['convert', fixture('multibody.stl'), 'x.stl', '--bogus'],
    ['--help'],
  ]) {
    const n = run(nativeCli, args), w = run(process.execPath, [npmCli, ...args]);
    assert.equal(w.status, n.status, args.join(' '));
    assert.ok(w.stdout.equals(n.stdout), `stdout of ${args.join(' ')}`);
    assert.ok(w.stderr.equals(n.stderr), `stderr of ${args.join(' ')}:\n${n.stderr}\n${w.stderr}`);
  }
  assert.deepEqual(readdirSync(dir), ['bad.stl']);
  assert.ok(!existsSync(path.join(root, 'x.stl')));
});
