// Repair as a plan (issue 23) through the package: planRepair / applyRepair / undo on the
// main thread, the plan's prediction against the result, undo back to the input bytes,
// manifold-3d as the judge of every repaired closed shell (it builds it, with the same
// volume), the CLI pair (native and npm print the same bytes), and bad options.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, mkdtempSync, rmSync } from 'node:fs';
import { execFileSync, spawnSync } from 'node:child_process';
import os from 'node:os';
import path from 'node:path';
import { loadStl, fromIndexed, toStl, planRepair, EditableMesh, extractShell } from 'stltopo';
import Module from 'manifold-3d';
import { fixtures, root, nativeCli, haveNativeCli, damagedTorus } from './helpers.mjs';

const wasm = await Module();
wasm.setup();

const admesh = (model, kase) => path.join(root, 'tests/judge/admesh', model, `${kase}-bad.stl`);

async function bytesOf(x) {
  return new Uint8Array(await toStl(x));
}

test('plan, apply, undo: the result is the plan\'s prediction, and undo gives back the input bytes', async () => {
  const t = damagedTorus(30, 12, 5);
  const mesh = await fromIndexed(t.positions, t.triangles);
  const before = await bytesOf(mesh);
  const plan = await planRepair(mesh, { steps: ['duplicates', 'zero-area', 'stitch', 'split-nonmanifold', 'fill-holes', 'orient'] });
  assert.ok(plan.steps.length === 6 && typeof plan.fingerprint === 'string');
  assert.ok(plan.before.duplicateTriangles > 0 && plan.before.inconsistentEdges > 0, JSON.stringify(plan.before));
  for (const s of plan.steps) for (const it of s.items) assert.ok(it.triangles instanceof Uint32Array);
  const em = await EditableMesh.from(mesh);
  try {
    const log = em.applyRepair(plan);
    assert.deepEqual(log.after, plan.after);
    const { file, ...afterReport } = log.afterReport;
    assert.equal(file, '');
    assert.deepEqual(afterReport, em.stats);
    assert.equal(log.after.duplicateTriangles, 0);
    assert.equal(log.after.inconsistentEdges, 0);
    assert.ok(log.steps.every((s) => s.status === 'ok'));
    assert.ok(log.steps[0].removedTriangles instanceof Uint32Array && log.steps[0].removedTriangles.length > 0);
    assert.deepEqual(em.validate(), { ok: true });
    assert.equal(em.undoableSteps, 6);
    const undone = [];
    for (let name; (name = em.undo()) !== null;) {
      undone.push(name);
      assert.deepEqual(em.validate(), { ok: true });
    }
    assert.deepEqual(undone, plan.steps.map((s) => s.step).reverse());
    assert.deepEqual(new Uint8Array(em.toStl()), before);
  } finally {
    em.dispose();
  }
});

test('planRepair(mesh) plans from the arrays what the EditableMesh made from them plans', async () => {
  const t = damagedTorus(30, 12, 5);
  // An indexed mesh with an unused vertex and a repeated position: the editor welds and
  // compacts them, so the plan (its fingerprint, ids and figures) is of the compacted mesh.
  const positions = new Float32Array([...t.positions, 9, 9, 9, ...t.positions.slice(0, 3)]);
  const nv = t.positions.length / 3;
  const triangles = Uint32Array.from(t.triangles, (v) => (v === 0 ? nv + 1 : v));
  const cases = [await fromIndexed(t.positions, t.triangles), { positions, triangles },
    await loadStl(readFileSync(admesh('block', 'nearby')))];
  for (const [k, mesh] of cases.entries()) {
    for (const options of [{}, { intersections: false, steps: ['fill-holes', 'orient', 'small-shells'] }]) {
      const plan = await planRepair(mesh, options);
      const em = await EditableMesh.from(mesh);
      try {
        assert.deepEqual(plan, em.planRepair(options), `case ${k}`);
        // And it applies to that EditableMesh.
        const log = em.applyRepair(plan);
        assert.deepEqual(log.after, plan.after, `case ${k}`);
      } finally {
        em.dispose();
      }
    }
  }
  await assert.rejects(planRepair({ positions: new Float32Array(3), triangles: Uint32Array.of(0, 1, 2) }),
    (e) => e.code === 'invalid-argument' && e.triangle === 0);
});

test('a deferred EditableMesh (planRepair and applyRepair as its first calls) repairs as a built one: plan, log, bytes, undo', async () => {
  const t = damagedTorus(30, 12, 5);
  const mesh = await fromIndexed(t.positions, t.triangles);
  const input = await bytesOf(mesh);
  const options = { steps: ['duplicates', 'zero-area', 'stitch', 'split-nonmanifold', 'fill-holes', 'orient'] };
  // built: an editor read before it plans; deferred: planRepair and applyRepair first.
  const run = async (build, planOn) => {
    const em = await EditableMesh.from(mesh);
    try {
      if (build) assert.equal(em.stats.triangles, mesh.stats.triangles);
      const plan = planOn === 'em' ? em.planRepair(options) : await planRepair(mesh, options);
      const log = em.applyRepair(plan);
      const out = { plan, log, bytes: new Uint8Array(em.toStl()), stats: em.stats, undoable: em.undoableSteps };
      assert.deepEqual(em.validate(), { ok: true });
      while (em.undo() !== null) assert.deepEqual(em.validate(), { ok: true });
      out.undone = new Uint8Array(em.toStl());
      return out;
    } finally {
      em.dispose();
    }
  };
  const built = await run(true, 'em');
  assert.deepEqual(built.undone, input);
  for (const planOn of ['em', 'mesh']) {
    const deferred = await run(false, planOn);
    assert.deepEqual(deferred, built, planOn);
  }
  // Refused on a deferred editor: nothing changes, and it still works.
  const other = await fromIndexed(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]), new Uint32Array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]));
  const plan = await planRepair(other);
  const em = await EditableMesh.from(mesh);
  try {
    assert.equal(em.undoableSteps, 0);
    assert.equal(em.undo(), null);
    assert.throws(() => em.applyRepair(plan), (e) => e.code === 'invalid-argument' && /another mesh/.test(e.message));
    assert.throws(() => em.applyRepair({}), (e) => e.code === 'invalid-argument');
    assert.deepEqual(new Uint8Array(em.toStl()), input);
    assert.deepEqual(em.applyRepair(em.planRepair(options)), built.log);
  } finally {
    em.dispose();
  }
});

// Two boxes that cross (self-intersections), one face flipped and one removed: a repair
// that changes the mesh and leaves pairs for the intersection pass.
async function crossingBoxes() {
  const positions = [], triangles = [];
  const box = (o, s) => {
    const v0 = positions.length / 3;
    for (let i = 0; i < 8; ++i) positions.push(o + (i & 1 ? s : 0), o + (i & 2 ? s : 0), o + (i & 4 ? s : 0));
    const quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    for (const [a, b, c, d] of quads) triangles.push(v0 + a, v0 + b, v0 + c, v0 + a, v0 + c, v0 + d);
  };
  box(0, 10);
  box(5, 10);
  [triangles[1], triangles[2]] = [triangles[2], triangles[1]];
  triangles.length -= 3;
  return fromIndexed(new Float32Array(positions), new Uint32Array(triangles));
}

test('apply takes the pass\'s figures from the last plan only for its mesh: the same log as with a fresh pass', async () => {
  const mesh = await crossingBoxes();
  const other = damagedTorus(20, 10, 3);
  const plan = await planRepair(mesh);
  assert.ok(plan.after.selfIntersections > 0, JSON.stringify(plan.after));
  const logOf = async () => {
    const em = await EditableMesh.from(mesh);
    try {
      return em.applyRepair(plan);
    } finally {
      em.dispose();
    }
  };
  const taken = await logOf(); // right after its plan: the figures are the plan's
  await planRepair(await fromIndexed(other.positions, other.triangles)); // another plan since: not
  const fresh = await logOf();
  assert.deepEqual(fresh, taken);
  assert.deepEqual(fresh.after, plan.after);
  assert.deepEqual(fresh.before, plan.before);
});

test('a plan made for another mesh, a custom attribute and bad options are refused without a change', async () => {
  const a = await fromIndexed(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]), new Uint32Array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]));
  const b = await fromIndexed(new Float32Array([0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 2]), new Uint32Array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]));
  const plan = await planRepair(a);
  const em = await EditableMesh.from(b);
  try {
    const stl = em.toStl();
    assert.throws(() => em.applyRepair(plan), (e) => e.code === 'invalid-argument' && /another mesh/.test(e.message));
    assert.deepEqual(em.toStl(), stl);
    assert.throws(() => em.applyRepair({}), (e) => e.code === 'invalid-argument');
    assert.equal(em.undo(), null);
  } finally {
    em.dispose();
  }
  await assert.rejects(planRepair(a, { steps: ['holes'] }), (e) => e.code === 'invalid-argument' && /unknown repair step/.test(e.message));
  await assert.rejects(planRepair(a, { stitchTolerance: -1 }), (e) => e.code === 'invalid-argument');
  await assert.rejects(planRepair(a, { maxHoleEdges: 1.5 }), (e) => e.code === 'invalid-argument');
  await assert.rejects(planRepair(a, { exclude: [{ step: 'orient' }] }), (e) => e.code === 'invalid-argument');
  await assert.rejects(planRepair(null), (e) => e.code === 'invalid-argument');
});

// manifold-3d builds every closed shell of the repaired mesh, with the same volume.
function judgeShells(repaired, where) {
  let built = 0;
  for (const sh of repaired.shells) {
    if (!(sh.closed && sh.manifold)) continue;
    const part = extractShell(repaired, sh.id);
    let status, volume = NaN;
    try {
      const m = new wasm.Manifold(new wasm.Mesh({ numProp: 3, vertProperties: part.positions, triVerts: part.triangles }));
      status = m.status();
      if (status === 'NoError') volume = m.volume();
      m.delete();
    } catch (e) {
      status = e.code || String(e.message);
    }
    if (sh.orientation === 'outward') {
      assert.equal(status, 'NoError', `${where} shell ${sh.id}`);
      assert.ok(Math.abs(volume - sh.volume) <= 1e-6 * Math.max(1, Math.abs(sh.volume)), `${where} shell ${sh.id}: ${volume} vs ${sh.volume}`);
      ++built;
    }
  }
  return built;
}

test('manifold-3d accepts every repaired closed shell, with the same volume (fixtures, admesh pairs, generated damage)', async () => {
  const inputs = [...fixtures().filter((f) => readFileSync(f).length < 4e6), admesh('block', 'normal-directions'),
    admesh('conveyor', 'fill-holes'), admesh('hourglass', 'remove-unconnected')];
  let built = 0, repaired = 0;
  for (const f of inputs) {
    let mesh;
    try {
      mesh = await loadStl(readFileSync(f));
    } catch {
      continue;
    }
    const plan = await planRepair(mesh, { maxPairs: 200000 });
    const em = await EditableMesh.from(mesh);
    try {
      em.applyRepair(plan);
      const out = await loadStl(em.toStl(), { shells: true });
      built += judgeShells(out, f);
      ++repaired;
    } finally {
      em.dispose();
    }
  }
  for (let seed = 1; seed <= 4; ++seed) {
    const t = damagedTorus(20 + seed, 10, seed);
    const em = await EditableMesh.from(await fromIndexed(t.positions, t.triangles));
    try {
      em.applyRepair(em.planRepair({ steps: ['duplicates', 'zero-area', 'stitch', 'fill-holes', 'orient'] }));
      built += judgeShells(await loadStl(em.toStl(), { shells: true }), `torus ${seed}`);
    } finally {
      em.dispose();
    }
  }
  assert.ok(repaired > 50 && built > 60, `repaired ${repaired}, built ${built}`);
});

test('stltopo repair: the npm CLI prints the native CLI\'s bytes and writes the same file', { skip: !haveNativeCli }, () => {
  const dir = mkdtempSync(path.join(os.tmpdir(), 'stltopo-repair-'));
  try {
    const cases = [
      [admesh('block', 'remove-unconnected'), []],
      [admesh('conveyor', 'normal-directions'), ['--steps', 'orient,small-shells', '--no-intersections']],
      [admesh('block', 'fill-holes'), ['--plan']],
      [admesh('hourglass', 'fill-holes'), ['--exclude', 'fill-holes:0', '--max-hole-edges', '2']],
      [admesh('block', 'remove-unconnected'), ['--threads', '2']],
      [admesh('hourglass', 'fill-holes'), ['--threads', '0', '--stitch-tolerance', '0.001']],
    ];
    for (const [f, args] of cases) {
      const out = path.join(dir, 'out.stl');
      const run = (cmd, pre) => {
        const r = spawnSync(cmd, [...pre, 'repair', f, out, ...args], { encoding: 'buffer' });
        const bytes = args.includes('--plan') ? null : readFileSync(out);
        rmSync(out, { force: true });
        return { status: r.status, stdout: r.stdout.toString(), stderr: r.stderr.toString(), bytes };
      };
      const n = run(nativeCli, []);
      const j = run(process.execPath, [path.join(root, 'bin/stltopo.mjs')]);
      assert.equal(j.stdout, n.stdout, `${f} ${args}`);
      assert.equal(j.status, n.status);
      assert.ok(n.status === 0 || n.status === 3, n.stderr);
      if (n.bytes) assert.deepEqual(j.bytes, n.bytes);
      const parsed = JSON.parse(n.stdout);
      assert.equal(parsed.file, f);
    }
    // Usage errors: the same message and status 2.
    for (const bad of [['--steps', 'holes'], ['--stitch-tolerance', '-1'], ['--exclude', 'orient'], ['--bogus'],
      ['--threads', '-1'], ['--threads', '1025'], ['--threads']]) {
      const n = spawnSync(nativeCli, ['repair', admesh('block', 'exact'), path.join(dir, 'x.stl'), ...bad]);
      const j = spawnSync(process.execPath, [path.join(root, 'bin/stltopo.mjs'), 'repair', admesh('block', 'exact'), path.join(dir, 'x.stl'), ...bad]);
      assert.equal(n.status, 2);
      assert.equal(j.status, 2);
      assert.equal(j.stderr.toString(), n.stderr.toString());
    }
    // A missing input: error JSON on stderr, status 1, nothing written.
    const n = spawnSync(nativeCli, ['repair', path.join(dir, 'none.stl'), path.join(dir, 'x.stl')]);
    const j = spawnSync(process.execPath, [path.join(root, 'bin/stltopo.mjs'), 'repair', path.join(dir, 'none.stl'), path.join(dir, 'x.stl')]);
    assert.equal(n.status, 1);
    assert.equal(j.status, 1);
    assert.equal(j.stderr.toString(), n.stderr.toString());
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test('stltopo/worker: planRepair and applyRepair in a worker give the main thread\'s plan, log and result', async () => {
  const worker = await import('stltopo/worker');
  const t = damagedTorus(26, 10, 9);
  const mesh = await fromIndexed(t.positions, t.triangles);
  const options = { steps: ['duplicates', 'zero-area', 'orient', 'fill-holes'], fill: ['refine'] };
  const here = await planRepair(mesh, options);
  const there = await worker.planRepair(mesh, options);
  assert.deepEqual(there.steps, here.steps);
  assert.deepEqual(there.after, here.after);
  assert.equal(there.fingerprint, here.fingerprint);
  const em = await EditableMesh.from(mesh);
  try {
    const log = em.applyRepair(here);
    const { mesh: repaired, log: wlog } = await worker.applyRepair(mesh, there, { shells: true });
    assert.deepEqual(wlog.steps, log.steps);
    assert.deepEqual(wlog.after, log.after);
    assert.deepEqual(new Uint8Array(await toStl(repaired)), new Uint8Array(em.toStl()));
    assert.equal(repaired.stats.inconsistentEdges, 0);
    // The input is unchanged (it is the undo of the whole repair).
    assert.equal(mesh.stats.inconsistentEdges, here.before.inconsistentEdges);
  } finally {
    em.dispose();
  }
  await assert.rejects(worker.planRepair(mesh, { steps: ['nope'] }), (e) => e.code === 'invalid-argument');
  await assert.rejects(worker.applyRepair(mesh, {}), (e) => e.code === 'invalid-argument');
  const other = await fromIndexed(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), new Uint32Array([0, 1, 2]));
  await assert.rejects(worker.applyRepair(other, there), (e) => e.code === 'invalid-argument' && /another mesh/.test(e.message));
});
