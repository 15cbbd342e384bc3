// Every fixture loads (or fails with the native CLI's error), stats equal the
// native JSON, validate() passes, and the navigation identities hold.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, existsSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { loadStl, loadStlFile, StlError, kInvalid } from 'stltopo';
import { fixtures, fixture, nativeCli, haveNativeCli, root } from './helpers.mjs';

const files = fixtures();

function nativeJson() {
  const rel = files.map((f) => path.relative(root, f));
  let out;
  try {
    out = execFileSync(nativeCli, ['info', '--json', ...rel], { cwd: root, maxBuffer: 1 << 28 });
  } catch (e) {
    out = e.stdout; // exit 1: some fixtures are broken on purpose
  }
  const lines = out.toString('utf8').trimEnd().split('\n');
  assert.equal(lines.length, files.length);
  return new Map(rel.map((r, i) => [files[i], JSON.parse(lines[i])]));
}

test('there are fixtures', () => {
  assert.ok(files.length >= 20, `only ${files.length} fixtures`);
});

test('every fixture: mesh.stats equals the native JSON (minus "file"), or the same error', { skip: !haveNativeCli && 'no native CLI' }, async () => {
  const expected = nativeJson();
  let ok = 0;
  let failed = 0;
  for (const f of files) {
    const want = expected.get(f);
    delete want.file;
    try {
      const m = await loadStlFile(f);
      assert.ok(!want.error, `${f}: native failed with ${JSON.stringify(want.error)}`);
      assert.deepEqual(m.stats, want, f);
      ++ok;
    } catch (e) {
      if (!(e instanceof StlError)) throw e;
      assert.ok(want.error, `${f}: ${e.message}`);
      assert.equal(e.code, want.error.code, f);
      assert.equal(e.message, want.error.message, f);
      assert.equal(e.offset, want.error.offset, f);
      assert.equal(e.line, want.error.line, f);
      assert.equal(e.triangle, want.error.triangle, f);
      ++failed;
    }
  }
  assert.ok(ok > failed);
});

test('every fixture: validate() passes and the navigation identities hold', async () => {
  for (const f of files) {
    let m;
    try {
      m = await loadStl(readFileSync(f));
    } catch (e) {
      assert.ok(e instanceof StlError, `${f}: ${e}`);
      continue;
    }
    assert.deepEqual(m.validate(), { ok: true }, f);
    assert.equal(m.positions.length, 3 * m.nVertices);
    assert.equal(m.triangles.length, 3 * m.nTriangles);
    assert.equal(m.attributes.length, m.nTriangles);
    assert.equal(m.nHalfedges, m.halfedges.next.length);
    for (const k of ['next', 'prev', 'vert', 'face']) assert.equal(m.halfedges[k].length, m.nHalfedges);
    assert.equal(m.problems.pairKind.length, m.nHalfedges / 2);
    assert.equal(m.holes.length, m.stats.holes);
    assert.equal(m.seams.length, m.stats.seams);
    assert.deepEqual(m.holes.map((h) => h.edgeCount), m.stats.holeSizes);
    const step = Math.max(1, Math.floor(m.nHalfedges / 2000));
    for (let e = 0; e < m.nHalfedges; e += step) {
      assert.equal(m.sym(m.sym(e)), e);
      assert.equal(m.org(m.oNext(e)), m.org(e));
      assert.equal(m.lFace(m.lNext(e)), m.lFace(e));
      assert.equal(m.dst(m.dNext(e)), m.dst(e));
      assert.equal(m.rFace(m.rNext(e)), m.rFace(e));
      assert.equal(m.lPrev(m.lNext(e)), e);
      assert.equal(m.oPrev(m.oNext(e)), e);
      assert.equal(m.dPrev(m.dNext(e)), e);
      assert.equal(m.rPrev(m.rNext(e)), e);
      assert.equal(m.dst(e), m.org(m.lNext(e)));
    }
    for (const h of [...m.holes, ...m.seams]) {
      assert.deepEqual([...m.faceHalfedges(h.halfedges[0])], [...h.halfedges]);
      assert.equal(m.lFace(h.halfedges[0]), h.face);
      assert.equal(h.face, m.nTriangles + h.id);
      for (let i = 0; i < h.halfedges.length; ++i) assert.equal(h.vertices[i], m.org(h.halfedges[i]));
      assert.ok(h.perimeter > 0);
    }
    for (let v = 0; v < m.nVertices; v += Math.max(1, Math.floor(m.nVertices / 200))) {
      const e0 = m.vertexHalfedge[v];
      if (e0 === kInvalid) continue;
      for (const e of m.outgoingHalfedges(e0)) assert.equal(m.org(e), v);
    }
    for (let t = 0; t < m.nTriangles; t += Math.max(1, Math.floor(m.nTriangles / 200))) {
      const e0 = m.triangleHalfedge[t];
      if (e0 === kInvalid) continue;
      const loop = [...m.faceHalfedges(e0)];
      assert.equal(loop.length, 3);
      for (const e of loop) assert.equal(m.lFace(e), t);
    }
  }
});

test('copies rebuild prev, face and vert in JS: equal to the arrays of the core (views), every fixture, exact and tolerance weld', async () => {
  let compared = 0;
  for (const f of files) {
    const bytes = readFileSync(f);
    for (const weld of ['exact', { tolerance: 1e-3 }]) {
      let copy;
      let view;
      try {
        copy = await loadStl(bytes, { weld });
        view = await loadStl(bytes, { weld, view: true });
      } catch (e) {
        assert.ok(e instanceof StlError, `${f}: ${e}`);
        continue;
      }
      try {
        for (const k of ['prev', 'face', 'vert']) {
          const a = copy.halfedges[k];
          assert.ok(a instanceof Uint32Array, `${f} ${k}`);
          assert.ok(Buffer.from(a.buffer, a.byteOffset, a.byteLength).equals(
            Buffer.from(view.halfedges[k].buffer, view.halfedges[k].byteOffset, view.halfedges[k].byteLength)), `${f} ${k}`);
          assert.equal(copy.halfedges[k], a, 'rebuilt once, then kept');
        }
        assert.deepEqual(copy.holes.map((h) => [...h.vertices]), view.holes.map((h) => [...h.vertices]), f);
        compared += 1;
      } finally {
        view.dispose();
      }
    }
  }
  assert.ok(compared >= 40, `only ${compared} comparisons`);
});

test('facts from the source projects: numpy-stl and trimesh', async () => {
  // The MANIFEST quotes these from the projects' own tests.
  const bwb = await loadStlFile(fixture('bwb.stl'));
  assert.equal(bwb.stats.normalMismatches, 155);
  const half = await loadStlFile(fixture('HalfDonut.stl').replace('stl_ascii', 'stl_binary'));
  assert.deepEqual(half.warnings.map((w) => w.code), ['trailing-bytes']);
  const two = await loadStlFile(fixture('triangle_with_two_solids.stl'));
  assert.equal(two.solids.length, 2);
  assert.equal(two.solids[1].firstTriangle, two.solids[0].triangleCount);
});

test('options: topology false, normals, tolerance weld', async () => {
  const f = fixture('bwb.stl');
  const bare = await loadStlFile(f, { topology: false, normals: true });
  assert.equal(bare.halfedges, null);
  assert.equal(bare.problems, null);
  assert.deepEqual(bare.holes, []);
  assert.equal(bare.normals.length, 3 * bare.nTriangles);
  assert.equal(bare.stats.edges, undefined);
  assert.deepEqual(bare.validate().ok, false);
  const welded = await loadStlFile(f, { weld: { tolerance: 1e-3 } });
  assert.deepEqual(welded.validate(), { ok: true });
  assert.equal(welded.positions.length, bare.positions.length); // coordinates never move
});

// The FNV-1a-style 64-bit hash of an array's bytes that tests/dump_arrays.cpp prints (its
// offset basis is 1469598103934665603 = 0x14650fb0739d0383; the prime is 2^40 + 0x1b3),
// in two 32-bit halves.
function fnv64(a) {
  const bytes = new Uint8Array(a.buffer, a.byteOffset, a.byteLength);
  let lo = 0x739d0383;
  let hi = 0x14650fb0;
  for (let i = 0; i < bytes.length; ++i) {
    lo = (lo ^ bytes[i]) >>> 0;
    const l = lo * 0x1b3;
    const carry = Math.floor(l / 4294967296);
    hi = (hi * 0x1b3 + carry + ((lo << 8) >>> 0)) % 4294967296;
    lo = l % 4294967296;
  }
  return hi.toString(16).padStart(8, '0') + lo.toString(16).padStart(8, '0');
}

const dumpArrays = process.env.STLTOPO_DUMP_ARRAYS || path.join(root, 'build/tests/dump_arrays');
test('every fixture: every array of the mesh equals the native core\'s (tests/dump_arrays), exact and tolerance weld, copies and views',
  { skip: !existsSync(dumpArrays) && `no ${dumpArrays}` }, async () => {
    const { api } = await import('../../dist/instance.node.js');
    const { layout } = await api.internal.getModule();
    const lines = execFileSync(dumpArrays, files, { maxBuffer: 1 << 26 }).toString().trimEnd().split('\n');
    assert.equal(lines.length, files.length);
    let compared = 0;
    for (let i = 0; i < files.length; ++i) {
      // "<file> read:ok name=len:hash ... exact:ok name=... lean:ok ... tol:ok ..."
      const parts = lines[i].slice(files[i].length + 1).split(' ');
      const sections = {};
      let cur = null;
      for (const p of parts) {
        const m = /^(read|exact|lean|tol):(.*)$/.exec(p);
        if (m) sections[cur = m[1]] = { status: m[2] };
        else if (cur && p.includes('=')) sections[cur][p.slice(0, p.indexOf('='))] = p.slice(p.indexOf('=') + 1);
      }
      if (sections.read.status !== 'ok') continue;
      const bytes = readFileSync(files[i]);
      for (const [section, weld] of [['exact', 'exact'], ['tol', { tolerance: 1e-3 }]]) {
        for (const view of [false, true]) {
          let m;
          try {
            m = await loadStl(bytes, { weld, view, normals: true, shells: true });
          } catch (e) {
            assert.notEqual(sections[section].status, 'ok', `${files[i]}: ${e.message}`);
            continue;
          }
          for (const d of layout) {
            const a = d.group ? m[d.group][d.key] : m[d.key];
            if (d.when === 'indexed') { // fromIndexed() only (tests/js/write.test.mjs)
              assert.equal(a, null, d.name);
              continue;
            }
            const want = sections[d.when === 'topology' || d.when === 'shells' ? section : 'read'][d.name];
            assert.ok(want, `${d.name} missing from dump_arrays`);
            if (a === null) assert.match(want, /^0:/, `${files[i]} ${d.name}`);
            else assert.equal(`${a.length}:${fnv64(a)}`, want, `${files[i]} ${section} ${d.name} view ${view}`);
          }
          m.dispose();
          ++compared;
        }
      }
    }
    assert.ok(compared >= 80, `only ${compared} comparisons`);
  });
