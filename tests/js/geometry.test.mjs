// Exact geometry in JS (issue 21): loadStl(..., { intersections: true }), mesh.intersections,
// the geometry defect kinds, mesh.findIntersections() on any mesh, and the npm CLI's
// --intersections, all against the native CLI (an independent process).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync, readdirSync } from 'node:fs';
import path from 'node:path';
import { loadStl, GEOMETRY_DEFECT_KINDS } from 'stltopo';
import { loadStl as loadInWorker } from 'stltopo/worker';
import { fixtures, root, nativeCli, haveNativeCli } from './helpers.mjs';

const skip = !haveNativeCli && `no native CLI at ${nativeCli}`;
const casesDir = path.join(root, 'tests/judge/cases');
const cases = readdirSync(casesDir).filter((f) => f.endsWith('.stl')).map((f) => path.join(casesDir, f));

function native(file, extra = []) {
  const r = spawnSync(nativeCli, ['info', '--json', '--intersections', '--shells', '--defects', '--max-defects', '100000',
    ...extra, file], { maxBuffer: 1 << 28 });
  return JSON.parse(r.stdout.toString());
}

const KEYS = ['zeroAreaTriangles', 'duplicateTriangles', 'selfIntersections', 'intersectionKinds', 'intersectingTriangles',
  'intersectionsComplete', 'solid'];

test('{ intersections: true }: stats, shells and every geometry defect equal the native report', { skip }, async () => {
  let pairs = 0;
  for (const f of [...cases, ...fixtures().filter((x) => /teapot|Spider|box\.STL|featuretype/i.test(x))]) {
    const want = native(f);
    if (want.error) continue;
    const mesh = await loadStl(readFileSync(f), { intersections: true });
    for (const k of KEYS) assert.deepEqual(mesh.stats[k], want[k], `${f}: ${k}`);
    assert.deepEqual(mesh.shells.map((s) => [s.selfIntersects, s.intersectsShells, s.parent, s.depth]),
      want.shellList.map((s) => [s.selfIntersects, s.intersectsShells, s.parent, s.depth]), `${f}: shells`);
    mesh.shells.forEach((s, i) => assert.deepEqual(Object.keys(s), Object.keys(want.shellList[i]), `${f}: shell ${i}'s keys`));
    for (const kind of ['zeroAreaTriangles', 'duplicateTriangles', 'selfIntersections']) {
      const n = mesh.defectCount(kind);
      assert.equal(n, want.defects[kind].count, `${f}: ${kind} count`);
      for (let i = 0; i < n; ++i) assert.deepEqual(mesh.defect(kind, i), want.defects[kind].items[i], `${f}: ${kind} ${i}`);
    }
    pairs += mesh.intersections.kinds.length;
  }
  assert.ok(pairs > 1000, `only ${pairs} pairs compared`);
  assert.deepEqual(GEOMETRY_DEFECT_KINDS, ['zeroAreaTriangles', 'duplicateTriangles', 'selfIntersections']);
});

test('plain loads give the cheap counts and null intersection keys; findIntersections() fills them in', { skip }, async () => {
  const f = path.join(casesDir, 'overlapping_cubes.stl');
  const mesh = await loadStl(readFileSync(f));
  assert.equal(mesh.stats.zeroAreaTriangles, 0);
  assert.equal(mesh.stats.selfIntersections, null);
  assert.equal(mesh.stats.solid, null);
  assert.equal(mesh.intersections, null);
  assert.throws(() => mesh.defectCount('selfIntersections'), /intersections: true/);
  const want = native(f);
  const r = await mesh.findIntersections();
  for (const k of KEYS) assert.deepEqual(r.stats[k], want[k], k);
  assert.equal(r.intersections.kinds.length, want.selfIntersections);
  assert.deepEqual(Array.from(r.intersections.pairs.subarray(0, 2)), want.defects.selfIntersections.items[0].triangles);
  // In a worker, too.
  const w = await loadInWorker(readFileSync(f), { intersections: true });
  assert.equal(w.stats.selfIntersections, want.selfIntersections);
  assert.equal(w.stats.solid, false);
});

test('maxPairs cuts the pass: intersectionsComplete false, solid false', { skip }, async () => {
  const f = path.join(casesDir, 'overlapping_cubes.stl');
  const mesh = await loadStl(readFileSync(f), { intersections: true, maxPairs: 3 });
  assert.equal(mesh.stats.selfIntersections, 3);
  assert.equal(mesh.stats.intersectionsComplete, false);
  assert.equal(mesh.stats.solid, false);
  assert.deepEqual(mesh.stats, (() => { const j = native(f, ['--max-pairs', '3']); delete j.file; delete j.shellList; delete j.defects; return j; })());
  await assert.rejects(loadStl(readFileSync(f), { intersections: true, maxPairs: 0 }), /maxPairs/);
});
