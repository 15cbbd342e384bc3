// EditableMesh through the package: edits on a loaded file, refused edits as
// StlError('edit-refused') that change nothing, attributes with JS rules, and the stats
// of an edited mesh equal to a fresh load of the same triangles.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { loadStl, loadStlFile, EditableMesh, StlError } from 'stltopo';
import { fixture, gridStl } from './helpers.mjs';
import { api } from '../../dist/instance.node.js';

const getFull = api.internal.getFull;

const cubeFile = () => fixture('cubeBinary.stl');

// Binary STL bytes of the live triangles of an editable mesh (for a fresh load).
function stlBytes(em) {
  const tri = em.triangles;
  const p = em.positions;
  const live = [];
  for (let t = 0; t < tri.length / 3; ++t) if (tri[3 * t] !== 0xffffffff) live.push(t);
  const out = new Uint8Array(84 + 50 * live.length);
  const dv = new DataView(out.buffer);
  dv.setUint32(80, live.length, true);
  live.forEach((t, i) => {
    for (let c = 0; c < 3; ++c)
      for (let k = 0; k < 3; ++k) dv.setFloat32(84 + 50 * i + 12 + 12 * c + 4 * k, p[3 * tri[3 * t + c] + k], true);
  });
  return out;
}

async function freshStats(em) {
  const m = await loadStl(stlBytes(em));
  const s = { ...m.stats };
  return s;
}

// The topology figures that do not depend on the file's format or header.
const TOPO_KEYS = ['triangles', 'vertices', 'degenerateTriangles', 'edges', 'boundaryEdges', 'nonManifoldEdges',
  'inconsistentEdges', 'nonManifoldVertices', 'holes', 'seams', 'holeSizes', 'shells', 'eulerCharacteristic', 'genus',
  'watertight', 'manifold', 'area', 'volume', 'bbox'];

// First in this file: nothing before it has made an editable mesh.
test('editing is in the full module, instantiated by the first EditableMesh.from(), not by loads', async () => {
  const mesh = await loadStlFile(cubeFile());
  assert.equal(getFull.current(), null, 'loadStl() does not instantiate stltopo-full');
  const em = await EditableMesh.from(mesh);
  const entry = getFull.current();
  assert.ok(entry && entry.module && typeof entry.module._EditableMesh === 'function');
  const core = await api.internal.getModule();
  assert.notEqual(entry.module, core.module);
  assert.equal(typeof core.module._EditableMesh, 'undefined', 'stltopo-wasm has no editing code');
  assert.equal(em.stats.triangles, 12);
  em.dispose();
});

test('out-of-memory in the full module (editing) is an error, not an abort, and it recovers', async () => {
  const mesh = await loadStlFile(cubeFile());
  const entry = await getFull();
  const M = entry.module;
  const n = 120; // a grid of 2 * 120^2 triangles: megabytes of editable arrays
  const grid = await loadStl(gridStl(n));
  try {
    M._testFill(0);
    await assert.rejects(EditableMesh.from(grid), (e) => e instanceof StlError && e.code === 'out-of-memory');
  } finally {
    M._testRelease();
  }
  assert.equal(await getFull(), entry, 'a status, not a wasm abort: the same instance carries on');
  const em = await EditableMesh.from(grid);
  assert.equal(em.stats.triangles, 2 * n * n);
  em.dispose();
  const small = await EditableMesh.from(mesh);
  assert.deepEqual(small.validate(), { ok: true });
  small.dispose();
});

test('from() without a tolerance builds the editor at first use: out of memory then is that call\'s error, and a retry works', async () => {
  const n = 120;
  const grid = await loadStl(gridStl(n));
  const entry = await getFull();
  const M = entry.module;
  const em = await EditableMesh.from(grid); // the arrays are staged and checked, the editor not built
  try {
    try {
      M._testFill(0);
      assert.throws(() => em.nTriangles, (e) => e instanceof StlError && e.code === 'out-of-memory');
      assert.throws(() => em.validate(), (e) => e instanceof StlError && e.code === 'out-of-memory');
    } finally {
      M._testRelease();
    }
    assert.equal(await getFull(), entry);
    assert.equal(em.nTriangles, 2 * n * n);
    assert.deepEqual(em.validate(), { ok: true });
    assert.deepEqual(em.stats.triangles, 2 * n * n);
  } finally {
    em.dispose();
  }
  // A bad id is still refused by from() itself.
  await assert.rejects(EditableMesh.from({ positions: new Float32Array(9), triangles: Uint32Array.of(0, 1, 3) }),
    (e) => e instanceof StlError && e.code === 'invalid-argument' && e.triangle === 0);
});

test('a wasm abort of the full module: the next EditableMesh.from() gets a fresh instance', async () => {
  const mesh = await loadStlFile(cubeFile());
  const entry = await getFull();
  assert.throws(() => entry.module._testAbort(), WebAssembly.RuntimeError);
  const em = await EditableMesh.from(mesh);
  assert.notEqual(getFull.current(), entry);
  assert.equal(em.stats.triangles, 12);
  em.dispose();
});

test('a wasm abort under live editable meshes: their calls give an StlError, not the RuntimeError', async () => {
  // An abort inside a call (operator new failing in a repair plan of millions of items) came
  // out of planRepair() as a raw RuntimeError, and every later call of an editable mesh of
  // that instance threw one too.
  const mesh = await loadStlFile(cubeFile());
  const em = await EditableMesh.from(mesh);
  assert.equal(em.nTriangles, 12);
  const entry = await getFull();
  assert.throws(() => entry.module._testAbort(), WebAssembly.RuntimeError);
  for (const call of [() => em.planRepair(), () => em.removeTriangle(0), () => em.toStl(), () => em.validate()]) {
    assert.throws(call, (e) => e instanceof StlError && e.code === 'invalid-argument' && /lost/.test(e.message));
  }
  em.dispose();
  const fresh = await EditableMesh.from(mesh);
  assert.equal(fresh.planRepair().after.watertight, true);
  fresh.dispose();
});

test('remove a cube face, fill the hole: stats follow and equal a fresh load', async () => {
  const mesh = await loadStlFile(cubeFile());
  const em = await EditableMesh.from(mesh);
  assert.equal(em.stats.watertight, true);
  em.removeTriangle(0);
  assert.deepEqual(em.holes.map((h) => h.edgeCount), [3]);
  assert.equal(em.holes[0].face, em.nTriangles + 0); // as a Mesh: nTriangles (slots) + loop id
  for (const e of em.holes[0].halfedges) assert.equal(em.halfedges.face[e], em.holes[0].face);
  assert.equal(em.stats.boundaryEdges, 3);
  const fresh = await freshStats(em);
  for (const k of TOPO_KEYS) assert.deepEqual(em.stats[k], fresh[k], k);
  const added = em.fillHole(em.holes[0].id, { method: 'ear' });
  assert.equal(added.length, 1);
  assert.equal(em.stats.watertight, true);
  assert.equal(em.stats.genus, 0);
  assert.deepEqual(em.validate(), { ok: true });
  em.dispose();
  mesh.dispose?.();
});

const TETRA = {
  positions: new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]),
  triangles: new Uint32Array([0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2]),
};

test('a refused edit throws StlError edit-refused and changes nothing', async () => {
  const em = await EditableMesh.from(TETRA);
  assert.equal(em.stats.watertight, true);
  const before = { tri: em.triangles.slice(), next: em.halfedges.next.slice(), stats: JSON.stringify(em.stats) };
  // Collapsing any edge of a tetrahedron fails the link condition; flipping any edge
  // would make an edge that exists.
  for (let e = 0; e < em.nHalfedges; ++e) {
    for (const edit of [() => em.collapseEdge(e), () => em.flipEdge(e)]) {
      assert.throws(edit, (err) => err instanceof StlError && err.code === 'edit-refused' && /^edit-refused: /.test(err.message));
    }
  }
  assert.deepEqual(em.triangles, before.tri);
  assert.deepEqual(em.halfedges.next, before.next);
  assert.equal(JSON.stringify(em.stats), before.stats);
  assert.throws(() => em.removeTriangle(99), (e) => e instanceof StlError && e.code === 'invalid-argument');
  em.dispose();
  assert.throws(() => em.stats, (e) => e instanceof StlError && e.code === 'invalid-argument');
});

test('setPosition moves one vertex: the hole perimeter, volume and bbox follow; bad ids and coordinates are refused', async () => {
  const mesh = await loadStlFile(cubeFile());
  const em = await EditableMesh.from(mesh);
  em.removeTriangle(0);
  const hole = em.holes[0];
  const v = hole.vertices[0];
  const before = em.positions.slice();
  const perimeterBefore = hole.perimeter;
  // Out of the hole's plane, twice the cube's size: both of v's hole edges grow.
  const size = em.stats.bbox.max[0] - em.stats.bbox.min[0];
  const z = hole.vertices.map((w) => before[3 * w + 2]);
  assert.ok(z.every((x) => x === z[0]), 'the hole lies in a plane z = const');
  em.setPosition(v, before[3 * v], before[3 * v + 1], before[3 * v + 2] - 2 * size);
  const after = em.positions;
  for (let i = 0; i < before.length; ++i) assert.equal(after[i], i === 3 * v + 2 ? before[i] - 2 * size : before[i], `coordinate ${i}`);
  assert.deepEqual(em.holes[0].vertices, hole.vertices);
  let perimeter = 0;
  const hv = em.holes[0].vertices;
  for (let i = 0; i < hv.length; ++i) {
    const a = hv[i], b = hv[(i + 1) % hv.length];
    perimeter += Math.hypot(after[3 * a] - after[3 * b], after[3 * a + 1] - after[3 * b + 1], after[3 * a + 2] - after[3 * b + 2]);
  }
  assert.ok(Math.abs(em.holes[0].perimeter - perimeter) < 1e-9 * perimeter);
  assert.ok(em.holes[0].perimeter > perimeterBefore + size);
  const fresh = await freshStats(em);
  for (const k of TOPO_KEYS) assert.deepEqual(em.stats[k], fresh[k], k);
  assert.deepEqual(em.validate(), { ok: true });
  const frozen = { pos: em.positions.slice(), stats: JSON.stringify(em.stats) };
  assert.throws(() => em.setPosition(em.nVertices, 0, 0, 0), (e) => e instanceof StlError && e.code === 'invalid-argument');
  assert.throws(() => em.setPosition(v, NaN, 0, 0), (e) => e instanceof StlError && e.code === 'invalid-argument');
  assert.throws(() => em.setPosition(-1, 0, 0, 0), (e) => e instanceof StlError && e.code === 'invalid-argument');
  assert.deepEqual(em.positions, frozen.pos);
  assert.equal(JSON.stringify(em.stats), frozen.stats);
  em.dispose();
  mesh.dispose?.();
});

test('split, flip, collapse and reverse on a sphere keep it closed; compact renumbers', async () => {
  const em = await EditableMesh.from(await loadStlFile(fixture('test_sphere.stl')));
  const chi = em.stats.eulerCharacteristic;
  const v = em.splitEdge(0, 0.5);
  assert.equal(v, em.nVertices - 1);
  em.flipEdge(em.triangleHalfedge[3]);
  const keep = em.collapseEdge(em.triangleHalfedge[40], 0);
  assert.equal(typeof keep, 'number');
  assert.equal(em.stats.eulerCharacteristic, chi);
  em.reverseTriangle(5);
  assert.equal(em.stats.inconsistentEdges, 3);
  em.reverseTriangle(5);
  em.reverseShell(0);
  assert.ok(em.stats.volume < 0);
  assert.equal(em.stats.watertight, true);
  const maps = em.compact();
  assert.ok(maps.triangles instanceof Uint32Array);
  assert.equal(em.nTriangles, em.stats.triangles);
  const fresh = await freshStats(em);
  for (const k of TOPO_KEYS) assert.deepEqual(em.stats[k], fresh[k], k);
  assert.deepEqual(em.validate(), { ok: true });
  // toStl() writes the edited mesh; it reads back with the same figures, binary and ASCII.
  for (const format of ['binary', 'ascii']) {
    const back = await loadStl(em.toStl({ format }));
    for (const k of TOPO_KEYS) assert.deepEqual(back.stats[k], em.stats[k], `${format} ${k}`);
    // The same corners bit for bit (a file numbers its vertices by first appearance).
    const xyz = (m) => { const out = new Float32Array(m.triangles.length * 3); m.triangles.forEach((v, i) => out.set(m.positions.subarray(3 * v, 3 * v + 3), 3 * i)); return out; };
    assert.deepEqual(xyz(back), xyz(em), `${format} corner positions`);
  }
  // Navigation works on the editable arrays.
  const e = em.triangleHalfedge[0];
  assert.equal(em.dst(e), em.org(em.lNext(e)));
  em.dispose();
});

test('attributes: average on split, a JS merge rule on collapse, fail refuses', async () => {
  const em = await EditableMesh.from(await loadStlFile(fixture('test_sphere.stl')));
  const temp = new Float32Array(em.nVertices).map((_, i) => i);
  em.addAttribute('temp', 'vertex', temp, { merge: (a, b) => [Math.max(a[0], b[0])], split: 'average' });
  const e = em.triangleHalfedge[0];
  const a = em.org(e), b = em.dst(e);
  const m = em.splitEdge(e, 0.25);
  assert.equal(em.attribute('temp')[m], Math.fround(0.75 * a + 0.25 * b));
  const e2 = em.triangleHalfedge[50];
  const x = em.org(e2), y = em.dst(e2);
  const keep = em.collapseEdge(e2);
  assert.equal(keep, x);
  assert.equal(em.attribute('temp')[keep], Math.max(x, y));
  const label = new Uint8Array(em.nTriangles).fill(1);
  label[0] = 2;
  em.addAttribute('label', 'triangle', label, { merge: 'fail' });
  const h = em.triangleHalfedge[0];
  let refusedByLabel = false;
  for (const f of [h, em.lNext(h), em.lNext(em.lNext(h))]) {
    try {
      em.flipEdge(f);
    } catch (err) {
      if (err.code === 'edit-refused' && /label/.test(err.message)) refusedByLabel = true;
    }
  }
  assert.ok(refusedByLabel);
  assert.ok(em.attributeNames().includes('attribute'));
  // A rule that throws: its exception comes out of the edit, which changed nothing.
  em.addAttribute('strict', 'vertex', new Uint8Array(em.nVertices), { split: () => { throw new Error('no splits here'); } });
  const nv = em.nVertices;
  assert.throws(() => em.splitEdge(em.triangleHalfedge[3]), /no splits here/);
  assert.equal(em.nVertices, nv);
  assert.deepEqual(em.validate(), { ok: true });
  em.dispose();
});

test('an indexed mesh: addTriangle pairs with the boundary', async () => {
  const positions = new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]);
  const triangles = new Uint32Array([0, 2, 1, 0, 1, 3, 1, 2, 3]);
  const em = await EditableMesh.from({ positions, triangles });
  assert.deepEqual(em.holes.map((h) => h.edgeCount), [3]);
  assert.throws(() => em.addTriangle(0, 2, 3), (e) => e.code === 'edit-refused');
  const t = em.addTriangle(0, 3, 2);
  assert.equal(t, 3);
  assert.equal(em.stats.watertight, true);
  em.dispose();
});

test('the wasm heap returns to its baseline after many editable meshes', async () => {
  const heap = async () => (await getFull()).module._heapInUse();
  const mesh = await loadStlFile(fixture('test_sphere.stl'));
  const round = async () => {
    const em = await EditableMesh.from(mesh);
    em.removeTriangle(0);
    em.fillHole(em.holes[0].id, { method: 'ear' });
    em.addAttribute('w', 'edge', new Float32Array(em.nHalfedges / 2), { merge: 'average' });
    em.splitEdge(em.triangleHalfedge[5]);
    void em.stats;
    em.dispose();
  };
  await round();
  const base = await heap();
  for (let i = 0; i < 30; ++i) await round();
  assert.equal(await heap(), base);
});

test('joins: a crack closed by mergeVertices, a T-junction by splitEdgeAt, a pinch split by splitVertex; refusals change nothing', async () => {
  // Two unit squares side by side in z = 0, their shared side cut apart: vertices 1-2 of the
  // left square and 4-5 of the right one sit on the same line x = 1 (4 = 1, 5 = 2 in position).
  const positions = new Float32Array([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0, 2, 1, 0]);
  const triangles = new Uint32Array([0, 1, 2, 0, 2, 3, 4, 6, 7, 4, 7, 5]);
  const em = await EditableMesh.from({ positions, triangles });
  try {
    assert.equal(em.stats.boundaryEdges, 8);
    // One pair alone would pinch the fans: refused, nothing changes.
    const before = em.triangles.slice();
    assert.throws(() => em.mergeVertices(1, 4), (e) => e instanceof StlError && e.code === 'edit-refused');
    assert.deepEqual(em.triangles, before);
    em.mergeVertices([1, 2], [4, 5]);
    assert.equal(em.stats.boundaryEdges, 6);
    assert.deepEqual(em.validate(), { ok: true });
    const fresh = await freshStats(em);
    for (const k of TOPO_KEYS) assert.deepEqual(em.stats[k], fresh[k], k);
    assert.throws(() => em.mergeVertices([1], [2, 3]), (e) => e.code === 'invalid-argument');
    assert.throws(() => em.mergeVertices('x', 1), (e) => e.code === 'invalid-argument');
  } finally {
    em.dispose();
  }
  // A T-junction: the left square's right side runs 1-4-2 through vertex 4 at (1, 0.5); the
  // right square's left side is the one edge 1-2.
  const p2 = new Float32Array([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0.5, 0, 2, 0, 0, 2, 1, 0]);
  // Left: (0,1,4), (0,4,3), (4,2,3) — its right side runs 1-4-2; right square (1,5,6), (1,6,2).
  const t2 = new Uint32Array([0, 1, 4, 0, 4, 3, 4, 2, 3, 1, 5, 6, 1, 6, 2]);
  const tj = await EditableMesh.from({ positions: p2, triangles: t2 });
  try {
    assert.equal(tj.stats.boundaryEdges, 9);
    const { vert, face } = tj.halfedges;
    let e = -1;
    for (let h = 0; h < tj.nHalfedges; ++h) {
      const ends = [vert[h], tj.dst(h)].sort().join();
      if (face[h] >= tj.nTriangles && ends === '1,2') e = h;
    }
    assert.ok(e >= 0);
    tj.splitEdgeAt(e, 4);
    assert.equal(tj.stats.boundaryEdges, 6);
    assert.deepEqual(tj.validate(), { ok: true });
  } finally {
    tj.dispose();
  }
  // Two tetrahedra sharing one vertex: splitVertex gives the second fan its own vertex.
  const p3 = new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1]);
  const t3 = new Uint32Array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 0, 4, 5, 0, 6, 4, 0, 5, 6, 4, 6, 5]);
  const pinch = await EditableMesh.from({ positions: p3, triangles: t3 });
  try {
    assert.equal(pinch.stats.nonManifoldVertices, 1);
    const r = pinch.splitVertex(0);
    assert.deepEqual(r, { first: 7, count: 1 });
    assert.equal(pinch.stats.nonManifoldVertices, 0);
    assert.deepEqual(Array.from(pinch.positions.slice(21, 24)), [0, 0, 0]);
    assert.throws(() => pinch.splitVertex(0), (e) => e.code === 'edit-refused');
  } finally {
    pinch.dispose();
  }
});
