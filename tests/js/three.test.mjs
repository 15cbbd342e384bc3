// stltopo/three: geometry and line helpers.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { loadStl } from 'stltopo';
import { toBufferGeometry, holesToLineSegments, problemEdgesToLineSegments } from 'stltopo/three';
import { BufferGeometry, LineSegments } from 'three';
import { fixture, gridStl } from './helpers.mjs';

test('toBufferGeometry: indexed, sharing the copies', async () => {
  const m = await loadStl(readFileSync(fixture('bunny.stl')));
  const g = toBufferGeometry(m);
  assert.ok(g instanceof BufferGeometry);
  assert.equal(g.getAttribute('position').array, m.positions);
  assert.equal(g.getIndex().array, m.triangles);
  assert.equal(g.getAttribute('normal').count, m.nVertices);
  assert.ok(g.boundingBox.max.x >= g.boundingBox.min.x);
  // Without colours, { colors: true } still gives the indexed geometry.
  assert.notEqual(toBufferGeometry(m, { colors: true }).getIndex(), null);
});

test('toBufferGeometry: a view mesh is copied (views detach)', async () => {
  const m = await loadStl(readFileSync(fixture('bunny.stl')), { view: true });
  const g = toBufferGeometry(m);
  assert.notEqual(g.getAttribute('position').array.buffer, m.positions.buffer);
  assert.deepEqual(g.getAttribute('position').array, m.positions);
  m.dispose();
});

test('toBufferGeometry({ colors: true }): non-indexed with per-face colours', async () => {
  // VisCAM colours: bit 15 set, R bits 10-14, G 5-9, B 0-4.
  const g = gridStl(2);
  const dv = new DataView(g.buffer);
  dv.setUint16(84 + 48, 0x8000 | (31 << 10), true); // triangle 0 red
  dv.setUint16(84 + 50 + 48, 0x8000 | 31, true); // triangle 1 blue
  const m = await loadStl(g);
  assert.equal(m.colorConvention, 'viscam');
  const geo = toBufferGeometry(m, { colors: true });
  assert.equal(geo.getIndex(), null);
  assert.equal(geo.getAttribute('position').count, 3 * m.nTriangles);
  const c = geo.getAttribute('color');
  assert.equal(c.normalized, true);
  assert.deepEqual([...c.array.subarray(0, 3)], [...m.colors.subarray(0, 3)]);
  assert.deepEqual([...c.array.subarray(9, 12)], [...m.colors.subarray(3, 6)]);
});

test('holesToLineSegments: one segment per hole edge', async () => {
  const m = await loadStl(gridStl(5));
  const lines = holesToLineSegments(m);
  assert.ok(lines instanceof LineSegments);
  assert.equal(lines.geometry.getAttribute('position').count, 2 * 20);
  assert.equal(lines.userData.halfedges.length, 20);
  const e = lines.userData.halfedges[0];
  const p = lines.geometry.getAttribute('position').array;
  const a = m.org(e);
  assert.deepEqual([...p.subarray(0, 3)], [...m.positions.subarray(3 * a, 3 * a + 3)]);
  const closed = await loadStl(readFileSync(fixture('bunny.stl')));
  assert.equal(holesToLineSegments(closed).geometry.getAttribute('position').count, 2 * closed.stats.holeSizes.reduce((x, y) => x + y, 0));
});

test('problemEdgesToLineSegments: non-manifold and inconsistent edges', async () => {
  for (const name of ['shared.STL', 'multibody.stl', 'wrench.stl', 'bunny.stl']) {
    const m = await loadStl(readFileSync(fixture(name)));
    const lines = problemEdgesToLineSegments(m);
    const expected = m.stats.nonManifoldEdges + m.stats.inconsistentEdges;
    assert.equal(lines.userData.halfedges.length, expected, name);
    assert.equal(lines.geometry.getAttribute('color').count, 2 * expected, name);
    if (name !== 'bunny.stl') assert.ok(expected > 0, name);
  }
});
