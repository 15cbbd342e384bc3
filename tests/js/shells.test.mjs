// Shells and defects in JS: mesh.shells, mesh.triangleShell, mesh.defects with
// mesh.defect(kind, i), and extractShell, on every fixture, against the native CLI's
// `info --json --shells --defects` (an independent process: the C++ core natively).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { loadStl, extractShell, DEFECT_KINDS, StlError, kInvalid } from 'stltopo';
import { api, fileSource } from '../../dist/instance.node.js';
import { cliCalls } from '../../bin/cli-wasm.mjs';
import { fixtures, fixture, nativeCli, haveNativeCli, runAsync, pool, soupStl } from './helpers.mjs';
import * as worker from 'stltopo/worker';

const skip = !haveNativeCli && `no native CLI at ${nativeCli}`;

function nativeReport(file) {
  const r = spawnSync(nativeCli, ['info', '--json', '--shells', '--defects', '--max-defects', '100000', file],
    { maxBuffer: 1 << 28 });
  return JSON.parse(r.stdout.toString());
}

// The JSON prints a float32 coordinate with the fewest digits that read back to it as a
// float32; JS gives the float32's own value. Math.fround maps the one onto the other.
function fround(item) {
  const f = (x) => (Array.isArray(x) ? x.map(f) : typeof x === 'object' && x ? { min: f(x.min), max: f(x.max) } : Math.fround(x));
  const out = { ...item };
  for (const k of ['bbox', 'positions', 'position']) if (k in out) out[k] = f(out[k]);
  return out;
}

test('mesh.shells and every defect equal the native report on every fixture', { skip }, async () => {
  let compared = 0;
  for (const f of fixtures()) {
    const want = nativeReport(f);
    if (want.error) continue;
    const mesh = await loadStl(readFileSync(f), { shells: true });
    assert.deepEqual(mesh.shells, want.shellList.map(fround), f);
    // The keys in the JSON's order too (deepEqual does not look at the order).
    mesh.shells.forEach((s, i) => assert.deepEqual(Object.keys(s), Object.keys(want.shellList[i]), `${f}: shell ${i}'s keys`));
    assert.equal(mesh.triangleShell.length, mesh.nTriangles);
    for (const kind of DEFECT_KINDS) {
      const list = want.defects[kind];
      assert.equal(mesh.defectCount(kind), list.count, `${f} ${kind}`);
      for (let i = 0; i < list.items.length; ++i) assert.deepEqual(mesh.defect(kind, i), fround(list.items[i]), `${f} ${kind} ${i}`);
    }
    // The shells' triangles are those of triangleShell.
    const perShell = new Array(mesh.shells.length).fill(0);
    for (const s of mesh.triangleShell) if (s !== kInvalid) ++perShell[s];
    assert.deepEqual(perShell, mesh.shells.map((s) => s.triangles), f);
    assert.deepEqual(mesh.validate(), { ok: true }, f);
    ++compared;
  }
  assert.ok(compared >= 70, `${compared} fixtures`);
});

test('without { shells: true } there is no shell report, and asking for one says so', async () => {
  const mesh = await loadStl(readFileSync(fixture('shared.STL')));
  assert.equal(mesh.shells, null);
  assert.equal(mesh.defects, null);
  assert.equal(mesh.triangleShell, null);
  assert.equal(mesh.stats.shells, 1);
  assert.throws(() => mesh.defectCount('holes'), (e) => e instanceof StlError && e.code === 'invalid-argument');
  assert.throws(() => extractShell(mesh, 0), (e) => e instanceof StlError && e.code === 'invalid-argument');
  const withShells = await loadStl(readFileSync(fixture('shared.STL')), { shells: true });
  assert.throws(() => withShells.defect('holes', 0), (e) => e.code === 'invalid-argument');
  assert.throws(() => withShells.defect('bogus', 0), (e) => e.code === 'invalid-argument');
  assert.throws(() => extractShell(withShells, 1), (e) => e.code === 'invalid-argument');
  assert.deepEqual(withShells.stats, mesh.stats);
});

test('view and worker loads give the same shells and defects; a corrupted triangleShell fails validate()', async () => {
  const bytes = readFileSync(fixture('Spider_binary.stl'));
  const copy = await loadStl(bytes, { shells: true });
  const view = await loadStl(bytes, { shells: true, view: true });
  const worker = await loadStl(bytes, { shells: true, worker: true });
  for (const m of [view, worker]) {
    assert.deepEqual(m.shells, copy.shells);
    assert.deepEqual(Array.from(m.triangleShell), Array.from(copy.triangleShell));
    for (const kind of DEFECT_KINDS) {
      for (let i = 0; i < m.defectCount(kind); ++i) assert.deepEqual(m.defect(kind, i), copy.defect(kind, i));
    }
    assert.deepEqual(m.validate(), { ok: true });
  }
  view.dispose();
  const t = copy.triangleShell.findIndex((s) => s === 1);
  copy.triangleShell[t] = 2;
  const v = copy.validate();
  assert.equal(v.ok, false);
  assert.match(v.message, /triangleShell differs from the shells/);
});

test('extractShell: each shell of every fixture, positions compacted, attributes, colours and solids kept', async () => {
  let checked = 0;
  for (const f of fixtures()) {
    let mesh;
    try {
      mesh = await loadStl(readFileSync(f), { shells: true, normals: true });
    } catch {
      continue;
    }
    for (const sh of mesh.shells.slice(0, 40)) {
      const part = extractShell(mesh, sh.id);
      assert.equal(part.triangles.length, 3 * sh.triangles, f);
      assert.equal(part.positions.length, 3 * sh.vertices, f);
      assert.equal(part.colorConvention, mesh.colorConvention);
      let k = 0;
      let seen = -1;
      for (let t = 0; t < mesh.nTriangles; ++t) {
        if (mesh.triangleShell[t] !== sh.id) continue;
        for (let c = 0; c < 3; ++c) {
          const v = part.triangles[3 * k + c];
          assert.ok(v <= seen + 1, 'ids by first appearance');
          seen = Math.max(seen, v);
          const w = mesh.triangles[3 * t + c];
          for (let i = 0; i < 3; ++i) assert.equal(part.positions[3 * v + i], mesh.positions[3 * w + i]);
          assert.equal(part.normals[3 * k + c], mesh.normals[3 * t + c]);
        }
        assert.equal(part.attributes[k], mesh.attributes[t]);
        if (mesh.colors) {
          assert.equal(part.colorValid[k], mesh.colorValid[t]);
          for (let i = 0; i < 3; ++i) assert.equal(part.colors[3 * k + i], mesh.colors[3 * t + i]);
        }
        ++k;
      }
      assert.equal(part.solids.reduce((n, s) => n + s.triangleCount, 0), sh.triangles);
      if (typeof sh.solid === 'number') assert.deepEqual(part.solids.map((s) => s.name), [mesh.solids[sh.solid].name]);
      ++checked;
    }
  }
  assert.ok(checked >= 250, `${checked} shells`);
});

test('mesh.shells of a soup: handed over as columns, built on first read, the native list', { skip }, async () => {
  // 40,000 shells. As one JSON string, the list of a 1.4M-triangle soup passed V8's string
  // limit (ERR_STRING_TOO_LONG out of loadStl), and its objects took 900 bytes of JS heap a
  // shell on every load; as JSON pieces, its formatting in wasm and parse in JS took 5 s at
  // 500k shells.
  const n = 40000;
  const bytes = soupStl(n);
  const dir = mkdtempSync(path.join(tmpdir(), 'stltopo-soup-'));
  try {
    const file = path.join(dir, 'soup.stl');
    writeFileSync(file, bytes);
    const want = nativeReport(file).shellList.map(fround);
    assert.equal(want.length, n);
    for (const m of [await loadStl(bytes, { shells: true }), await loadStl(bytes, { shells: true, view: true }),
      await worker.loadStl(bytes, { shells: true })]) {
      assert.equal(typeof Object.getOwnPropertyDescriptor(m, 'shells').get, 'function', 'not parsed by the load');
      const shells = m.shells;
      assert.equal(Object.getOwnPropertyDescriptor(m, 'shells').value, shells, 'parsed once, then a plain property');
      assert.deepEqual(shells, want);
      assert.ok(Object.keys(m).includes('shells'), 'own and enumerable');
      m.shells = null;
      assert.equal(m.shells, null, 'and writable');
      m.dispose?.();
    }
    const set = await loadStl(bytes, { shells: true });
    set.shells = [];
    assert.deepEqual(set.shells, [], 'a list set before the first read stays');
    assert.equal((await loadStl(bytes)).shells, null, 'no shells without { shells: true }');
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

// `stltopo split`: the npm CLI writes the same files (byte for byte) and prints the same
// lines as the native one, on every fixture, in both formats; errors and usage the same.
import { mkdtempSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const npmCli = fileURLToPath(new URL('../../bin/stltopo.mjs', import.meta.url));

const cliWasm = cliCalls(api.internal); // what bin/stltopo.mjs calls
const text = (r) => ({ status: r.status, stdout: r.stdout.toString(), stderr: r.stderr.toString() });

function runSplit(cmd, args) {
  const r = spawnSync(cmd, args, { maxBuffer: 1 << 28 });
  return { status: r.status, stdout: r.stdout.toString(), stderr: r.stderr.toString() };
}

test('split: native and npm CLIs write the same files and lines on every fixture', { skip }, async () => {
  const tmp = mkdtempSync(path.join(tmpdir(), 'stltopo-split-'));
  try {
    // A few fixtures at a time: a native CLI process for each, against an npm CLI process (about
    // 210 ms to start) for each fixture the native CLI fails on and one in three of the others,
    // and against the npm CLI's own call (cliCalls(...).split of bin/cli-wasm.mjs, around which
    // bin/stltopo.mjs only makes the folder and files) in this process for the rest.
    let processes = 0;
    const counts = await pool(fixtures(), async (f, i) => {
      const args = i % 3 === 0 ? ['--ascii'] : i % 3 === 1 ? ['--binary'] : [];
      const a = path.join(tmp, `a${i}`), b = path.join(tmp, `b${i}`);
      const na = text(await runAsync(nativeCli, ['split', f, a, ...args]));
      const names = na.status === 0 ? readdirSync(a).sort() : [];
      if (na.status !== 0 || i % 3 === 0) {
        ++processes;
        const nb = text(await runAsync(process.execPath, [npmCli, 'split', f, b, ...args]));
        assert.equal(nb.status, na.status, f);
        assert.equal(nb.stdout.replaceAll(b, a), na.stdout, f);
        assert.equal(nb.stderr, na.stderr, f);
        if (na.status !== 0) return 0;
        assert.deepEqual(readdirSync(b).sort(), names, f);
        for (const name of names) assert.ok(readFileSync(path.join(a, name)).equals(readFileSync(path.join(b, name))), `${f} ${name}`);
        rmSync(b, { recursive: true });
      } else {
        const w = args.length ? { format: args[0].slice(2) } : {};
        const lines = [], files = [];
        for await (const item of cliWasm.split(await fileSource(f), w)) {
          if (item.shells !== undefined) continue;
          if (!ArrayBuffer.isView(item)) {
            const base = path.basename(f), dot = base.lastIndexOf('.'); // as splitPath in bin/stltopo.mjs
            const file = path.join(a, `${dot > 0 ? base.slice(0, dot) : base}-shell-${item.k}.stl`);
            lines.push(item.line(file));
            files.push({ file, chunks: [] });
          } else {
            files.at(-1).chunks.push(Buffer.from(item));
          }
        }
        assert.equal(lines.map((l) => `${l}\n`).join(''), na.stdout, `${f} (in process)`);
        assert.deepEqual(files.map((x) => path.basename(x.file)).sort(), names, f);
        for (const x of files) assert.ok(readFileSync(x.file).equals(Buffer.concat(x.chunks)), `${x.file} (in process)`);
      }
      const lines = na.stdout.trimEnd().split('\n').filter(Boolean).map((l) => JSON.parse(l));
      assert.equal(lines.length, names.length, f);
      rmSync(a, { recursive: true });
      return names.length;
    });
    assert.ok(processes >= 25, `${processes} npm CLI processes`);
    const files = counts.reduce((x, y) => x + y, 0);
    assert.ok(files >= 300, `${files} files`);
    // Errors: a bad input, OUTDIR that is a file, usage.
    writeFileSync(path.join(tmp, 'file'), 'x');
    for (const args of [['split', 'no/such.stl', path.join(tmp, 'x')], ['split', fixture('shared.STL'), path.join(tmp, 'file')],
      ['split'], ['split', fixture('shared.STL')], ['split', fixture('shared.STL'), tmp, '--bogus']]) {
      const na = runSplit(nativeCli, args);
      const nb = runSplit(process.execPath, [npmCli, ...args]);
      assert.deepEqual(nb, na, args.join(' '));
      assert.notEqual(na.status, 0);
    }
  } finally {
    rmSync(tmp, { recursive: true, force: true });
  }
});

test('split: each file reads back as its shell, with the shell report of its line', { skip }, async () => {
  const tmp = mkdtempSync(path.join(tmpdir(), 'stltopo-split-'));
  try {
    const f = fixture('Spider_binary.stl');
    const out = runSplit(nativeCli, ['split', f, path.join(tmp, 'out')]);
    assert.equal(out.status, 0, out.stderr);
    const whole = await loadStl(readFileSync(f), { shells: true });
    const lines = out.stdout.trimEnd().split('\n').map((l) => JSON.parse(l));
    assert.equal(lines.length, whole.shells.length);
    for (const { file, shell } of lines) {
      assert.equal(path.basename(file), `Spider_binary-shell-${shell.id}.stl`);
      const part = await loadStl(readFileSync(file), { shells: true });
      assert.equal(part.shells.length, 1);
      // The same report on its own (its id and solid index are its own file's).
      for (const key of ['triangles', 'vertices', 'edges', 'boundaryEdges', 'nonManifoldEdges', 'inconsistentEdges',
        'nonManifoldVertices', 'holes', 'seams', 'closed', 'manifold', 'orientation', 'area', 'volume', 'bbox']) {
        assert.deepEqual(part.shells[0][key], whole.shells[shell.id][key], `${file} ${key}`);
      }
      const part2 = extractShell(whole, shell.id);
      assert.deepEqual(Array.from(part.positions), Array.from(part2.positions), file);
      assert.deepEqual(Array.from(part.triangles), Array.from(part2.triangles), file);
    }
  } finally {
    rmSync(tmp, { recursive: true, force: true });
  }
});
