// planUnion() and unionShells(): the boolean union of overlapping closed shells through
// manifold-3d, passed in by the caller (README, "Overlapping shells: a boolean union").
// Judges: the exact figures of hand-built bodies (two 20 mm cubes overlapping by a 10 mm cube
// are 15,000 mm³), manifold-3d's own volume of its union, and manifold-3d accepting every
// shell the union made; on every fixture with overlapping shells.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { fromIndexed, loadStl, planUnion, unionShells, extractShell } from 'stltopo';
import * as inWorker from 'stltopo/worker';
import Module from 'manifold-3d';
import { fixtures, manifoldVerdict } from './helpers.mjs';

const manifold = await Module();
manifold.setup();

// An axis-aligned cube, outward (or inward), as { P, T }.
function cube(x0, y0, z0, s, inward = false) {
  const P = [];
  for (let i = 0; i < 8; ++i) P.push(x0 + (i & 1 ? s : 0), y0 + (i & 2 ? s : 0), z0 + (i & 4 ? s : 0));
  const T = [0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5];
  if (inward) for (let t = 0; t < T.length; t += 3) [T[t + 1], T[t + 2]] = [T[t + 2], T[t + 1]];
  return { P, T };
}
function tetra(a, b, c, d) {
  return { P: [...a, ...b, ...c, ...d], T: [0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2] };
}
function join(...parts) {
  const P = [], T = [];
  for (const p of parts) {
    const o = P.length / 3;
    P.push(...p.P);
    T.push(...p.T.map((v) => v + o));
  }
  return { positions: new Float32Array(P), triangles: new Uint32Array(T) };
}
const load = (m, o = { shells: true, intersections: true }) => fromIndexed(m.positions, m.triangles, o);
const close = (a, b, what) => assert.ok(Math.abs(a - b) <= 1e-9 * Math.max(1, Math.abs(b)), `${what}: ${a} vs ${b}`);

// manifold-3d's verdict on shell s of a mesh loaded with shells.
const verdict = (mesh, s) => manifoldVerdict(manifold, extractShell(mesh, s));

test('two overlapping cubes become one solid of 15,000 mm³; a separate cube keeps its triangles, ids order and words', async () => {
  const m = join(cube(100, 0, 0, 5), cube(0, 0, 0, 20), cube(10, 10, 10, 20));
  const words = new Uint16Array(36).map((_, t) => (t < 12 ? 7 + t : 0));
  const mesh = await fromIndexed(m.positions, m.triangles, { shells: true, intersections: true, attributes: words });
  assert.equal(mesh.stats.solid, false);
  close(mesh.stats.volume, 16125, 'volume before');
  const before = { p: mesh.positions.slice(), t: mesh.triangles.slice() };

  const plan = await planUnion(mesh);
  assert.deepEqual(plan, { groups: [{ index: 0, shells: [1, 2], triangles: 24, volume: 16000, fit: true, reason: null }], complete: true });

  const r = await unionShells(mesh, { manifold });
  assert.equal(r.groups.length, 1);
  assert.equal(r.groups[0].united, true);
  assert.equal(r.groups[0].result.volume, 15000);
  const after = r.mesh;
  assert.equal(after.stats.solid, true);
  assert.equal(after.stats.selfIntersections, 0);
  assert.equal(after.stats.shells, 2);
  close(after.stats.volume, 15125, 'volume after');
  close(after.shells[1].volume, 15000, 'union shell volume');
  // The separate cube first, as it was, with its attribute words; the union after it.
  const corner = (x, t, c) => [...x.positions.subarray(3 * x.triangles[3 * t + c], 3 * x.triangles[3 * t + c] + 3)];
  for (let t = 0; t < 12; ++t) for (let c = 0; c < 3; ++c) assert.deepEqual(corner(after, t, c), corner(mesh, t, c));
  assert.deepEqual([...after.attributes.subarray(0, 12)], [...words.subarray(0, 12)]);
  assert.ok(after.attributes.subarray(12).every((w) => w === 0));
  assert.equal(after.nTriangles, 12 + r.groups[0].result.triangles);
  assert.equal(verdict(after, 1), 'NoError');
  // The input is not changed.
  assert.deepEqual(mesh.positions, before.p);
  assert.deepEqual(mesh.triangles, before.t);
});

test('interpenetrating tetrahedra: the union is solid, smaller than the sum, and its volume is manifold-3d\'s', async () => {
  const m = join(tetra([0, 0, 0], [10, 0, 0], [0, 10, 0], [0, 0, 10]), tetra([2, 2, 2], [12, 2, 2], [2, 12, 2], [2, 2, 12]));
  const mesh = await load(m);
  assert.equal(mesh.stats.intersectionKinds.crossing > 0, true);
  const r = await unionShells(mesh, { manifold });
  assert.equal(r.groups[0].united, true);
  assert.equal(r.mesh.stats.solid, true);
  assert.equal(r.mesh.shells.length, 1);
  assert.ok(r.mesh.stats.volume < mesh.stats.volume);
  assert.ok(Math.abs(r.mesh.stats.volume - r.groups[0].result.volume) <= 1e-6 * r.groups[0].result.volume);
});

test('groups that cannot be united say why, and nothing is made', async () => {
  const open = cube(0, 0, 0, 20);
  open.T = open.T.slice(3); // one triangle less: 3 boundary edges
  const cases = [
    [join(open, cube(10, 10, 10, 20)), /shell 0 is not closed \(3 boundary edges\)/],
    [join(cube(0, 0, 0, 20, true), cube(10, 10, 10, 20)), /shell 0 is inside out \(inward\): orient it outward first/],
  ];
  for (const [m, why] of cases) {
    const mesh = await load(m);
    const plan = await planUnion(mesh);
    assert.equal(plan.groups.length, 1);
    assert.equal(plan.groups[0].fit, false);
    assert.match(plan.groups[0].reason, why);
    const r = await unionShells(mesh, { manifold });
    assert.equal(r.mesh, null);
    assert.equal(r.groups[0].united, false);
    assert.match(r.groups[0].reason, why);
  }
  // Nested and apart are not overlapping: no group.
  const nested = await load(join(cube(0, 0, 0, 30), cube(10, 10, 10, 5), cube(100, 0, 0, 1)));
  assert.deepEqual((await planUnion(nested)).groups, []);
  assert.equal((await unionShells(nested, { manifold })).mesh, null);
});

test('a mesh loaded without shells or intersections gets its pass; options are checked', async () => {
  const m = join(cube(0, 0, 0, 20), cube(10, 10, 10, 20), cube(0, 50, 0, 20), cube(5, 55, 5, 20));
  const plain = await load(m, {});
  const full = await load(m);
  assert.deepEqual(await planUnion(plain), await planUnion(full));
  const a = await unionShells(plain, { manifold });
  const b = await unionShells(full, { manifold });
  assert.deepEqual(a.mesh.positions, b.mesh.positions);
  assert.deepEqual(a.mesh.triangles, b.mesh.triangles);
  assert.deepEqual(a.groups, b.groups);
  // Only the second group.
  const one = await unionShells(full, { manifold, groups: [1] });
  assert.deepEqual(one.groups.map((g) => g.united), [false, true]);
  assert.equal(one.groups[0].reason, 'not chosen');
  assert.equal(one.mesh.shells.length, 3);
  assert.equal((await unionShells(full, { manifold, groups: [] })).mesh, null);
  // A result loaded as the caller asks.
  const bare = await unionShells(full, { manifold, load: { topology: false } });
  assert.equal(bare.mesh.halfedges, null);

  await assert.rejects(unionShells(full), { code: 'invalid-argument', message: /needs \{ manifold \}: the manifold-3d module/ });
  await assert.rejects(unionShells(full, { manifold: {} }), { code: 'invalid-argument', message: /not a manifold-3d module/ });
  await assert.rejects(unionShells(full, { manifold, groups: [2] }), { code: 'invalid-argument', message: /group 2 does not exist \(the mesh has 2 groups/ });
  await assert.rejects(unionShells(full, { manifold, groups: 0 }), { code: 'invalid-argument', message: /must be an array/ });
  await assert.rejects(planUnion({}), { code: 'invalid-argument', message: /need a Mesh/ });
});

test('stltopo/worker unites the same way', async () => {
  const m = join(cube(0, 0, 0, 20), cube(10, 10, 10, 20));
  const main = await unionShells(await load(m), { manifold });
  const w = await inWorker.unionShells(await inWorker.fromIndexed(m.positions, m.triangles), { manifold });
  assert.deepEqual(w.groups, main.groups);
  assert.deepEqual(w.mesh.positions, main.mesh.positions);
  assert.deepEqual(w.mesh.triangles, main.mesh.triangles);
  assert.equal(w.mesh.stats.solid, true);
});

test('every fixture: each group that fits is united into closed manifold shells that manifold-3d accepts, of its volume', async () => {
  let united = 0, unfit = 0, files = 0;
  for (const f of fixtures()) {
    let mesh;
    try {
      mesh = await loadStl(readFileSync(f), { shells: true, intersections: true });
    } catch {
      continue;
    }
    const plan = await planUnion(mesh);
    if (!plan.groups.some((g) => g.fit)) {
      unfit += plan.groups.length;
      continue;
    }
    const where = path.relative('tests/fixtures', f);
    const r = await unionShells(mesh, { manifold });
    ++files;
    let nKept = 0;
    const gone = new Set(r.groups.filter((g) => g.united).flatMap((g) => g.shells));
    for (let t = 0; t < mesh.nTriangles; ++t) if (!gone.has(mesh.triangleShell[t])) ++nKept;
    let volume = 0;
    for (const g of r.groups) {
      if (!g.fit) {
        ++unfit;
        continue;
      }
      assert.equal(g.united, true, `${where}: group ${g.index}: ${g.reason}`);
      volume += g.result.volume;
      ++united;
    }
    // The shells made of the union's triangles (those after the kept ones).
    const made = new Set();
    for (let t = nKept; t < r.mesh.nTriangles; ++t) made.add(r.mesh.triangleShell[t]);
    let madeVolume = 0;
    for (const s of made) {
      const sh = r.mesh.shells[s];
      assert.ok(sh.closed && sh.manifold && sh.orientation === 'outward', `${where}: shell ${s} ${JSON.stringify(sh)}`);
      assert.equal(verdict(r.mesh, s), 'NoError', `${where}: shell ${s}`);
      madeVolume += sh.volume;
    }
    assert.ok(Math.abs(madeVolume - volume) <= 1e-6 * volume, `${where}: ${madeVolume} vs manifold-3d's ${volume}`);
    // The kept triangles as they were, in file order.
    for (let t = 0, k = 0; t < mesh.nTriangles; ++t) {
      if (gone.has(mesh.triangleShell[t])) continue;
      for (let c = 0; c < 3; ++c) {
        const a = mesh.triangles[3 * t + c], b = r.mesh.triangles[3 * k + c];
        for (let x = 0; x < 3; ++x) assert.equal(r.mesh.positions[3 * b + x], mesh.positions[3 * a + x], `${where} triangle ${t}`);
      }
      ++k;
    }
  }
  assert.ok(files >= 3 && united >= 6 && unfit >= 10, `files ${files}, united ${united}, unfit ${unfit}`);
});
