// stltopo/three: geometry and line helpers.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { loadStl } from 'stltopo';
import { toBufferGeometry, holesToLineSegments, problemEdgesToLineSegments } from 'stltopo/three';
import { BufferGeometry, LineSegments, Color, SRGBColorSpace } from 'three';
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
  // STL colours are sRGB bytes; three.js's vertex colours are linear (working colour space).
  const linear = (byte) => Math.fround(new Color().setRGB(byte / 255, 0, 0, SRGBColorSpace).r);
  assert.equal(c.normalized, false);
  assert.ok(c.array instanceof Float32Array);
  const want = (t) => [...m.colors.subarray(3 * t, 3 * t + 3)].map(linear);
  assert.deepEqual([...c.array.subarray(0, 3)], want(0));
  assert.deepEqual([...c.array.subarray(9, 12)], want(1));
  // A mid value, where sRGB and linear differ: VisCAM R = 16 of 31.
  dv.setUint16(84 + 48, 0x8000 | (16 << 10), true);
  const mid = await loadStl(g);
  const r = toBufferGeometry(mid, { colors: true }).getAttribute('color').array[0];
  assert.ok(Math.abs(r - linear(mid.colors[0])) < 1e-7 && Math.abs(r - mid.colors[0] / 255) > 0.1, `red ${r} for byte ${mid.colors[0]}`);
  // Uncoloured triangles: defaultColor, also sRGB bytes.
  const plain = await loadStl(gridStl(2));
  dv.setUint16(84 + 48, 0, true);
  const some = await loadStl(g); // triangle 0 without colour, triangle 1 blue
  assert.equal(some.colorConvention, 'viscam');
  const d = toBufferGeometry(some, { colors: true, defaultColor: [128, 64, 255] }).getAttribute('color').array;
  assert.deepEqual([...d.subarray(0, 3)], [128, 64, 255].map(linear));
  assert.equal(plain.colors, null);
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

test('holesToLineSegments: a hole has the same colour with and without seams', async () => {
  const m = await loadStl(gridStl(3));
  const color = 0x3080c0;
  const plain = holesToLineSegments(m, { color });
  const withSeams = holesToLineSegments(m, { color, seams: true });
  const want = new Color(color); // what LineBasicMaterial({ color }) draws
  assert.deepEqual([plain.material.color.r, plain.material.color.g, plain.material.color.b], [want.r, want.g, want.b]);
  const c = withSeams.geometry.getAttribute('color').array;
  for (let i = 0; i < c.length; i += 3) assert.deepEqual([...c.subarray(i, i + 3)], [want.r, want.g, want.b].map(Math.fround), `vertex ${i / 3}`);
  assert.equal(withSeams.material.vertexColors, true);
});

test('holesToLineSegments: reads neither halfedges.face nor halfedges.vert of a copy (no JS rebuild)', async () => {
  for (const seams of [false, true]) {
    const m = await loadStl(readFileSync(fixture('Spider_binary.stl'))); // 4 holes, 8 seams
    assert.ok(m.holes.length > 0 && m.seams.length > 0);
    const lines = holesToLineSegments(m, { seams });
    for (const k of ['face', 'vert', 'prev']) {
      assert.equal(typeof Object.getOwnPropertyDescriptor(m.halfedges, k).get, 'function', `${k} was built (seams: ${seams})`);
    }
    // The segments are still org -> dst of their half-edges.
    const p = lines.geometry.getAttribute('position').array;
    const he = lines.userData.halfedges;
    for (let i = 0; i < he.length; ++i) {
      const a = m.org(he[i]);
      const b = m.dst(he[i]);
      assert.deepEqual([...p.subarray(6 * i, 6 * i + 6)], [...m.positions.subarray(3 * a, 3 * a + 3), ...m.positions.subarray(3 * b, 3 * b + 3)]);
      assert.equal(lines.userData.loops[i], m.lFace(he[i]) - m.nTriangles);
    }
  }
});
