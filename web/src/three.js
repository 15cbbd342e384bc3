// stltopo/three: turn a loaded mesh into three.js objects (three is a peer
// dependency). Copies (the default loadStl result) are shared with three
// without copying; { view: true } meshes are copied, since their views into
// wasm memory detach when it grows and die with mesh.dispose().
import {
  BufferAttribute,
  BufferGeometry,
  Color,
  Float32BufferAttribute,
  LineBasicMaterial,
  LineSegments,
  SRGBColorSpace,
} from 'three';
import { stlError } from './errors.js';

const own = (mesh, a) => (mesh.view ? a.slice() : a);

/**
 * The 256 sRGB byte values in three.js's working colour space (linear unless
 * ColorManagement is off): STL colours are sRGB bytes, vertex colours are working-space
 * floats.
 */
export function srgbByteTable() {
  const c = new Color();
  return Float32Array.from({ length: 256 }, (_, i) => c.setRGB(i / 255, 0, 0, SRGBColorSpace).r);
}

// A 0xRRGGBB colour (sRGB, as THREE.Color takes it) in the working colour space.
const workingRgb = (hex) => new Color(hex).toArray();

/**
 * An indexed BufferGeometry (position + index, vertex normals), or, with
 * { colors: true } on a mesh that has per-triangle colours, a non-indexed one
 * with a per-vertex `color` attribute: the sRGB colour bytes converted to the
 * working colour space, as floats (uncoloured triangles get defaultColor, sRGB bytes).
 */
export function toBufferGeometry(mesh, { colors = false, normals = true, defaultColor = [200, 200, 200] } = {}) {
  const g = new BufferGeometry();
  if (colors && mesh.colors) {
    const nt = mesh.nTriangles;
    const pos = mesh.positions;
    const tri = mesh.triangles;
    const rgb = mesh.colors;
    const valid = mesh.colorValid;
    const p = new Float32Array(nt * 9);
    const c = new Float32Array(nt * 9);
    const lin = srgbByteTable();
    const fallback = defaultColor.map((x) => lin[Math.max(0, Math.min(255, Math.round(x)))]);
    for (let t = 0; t < nt; ++t) {
      const has = !valid || valid[t] !== 0;
      const r = has ? lin[rgb[3 * t]] : fallback[0];
      const gr = has ? lin[rgb[3 * t + 1]] : fallback[1];
      const b = has ? lin[rgb[3 * t + 2]] : fallback[2];
      for (let k = 0; k < 3; ++k) {
        const v = tri[3 * t + k];
        const o = 9 * t + 3 * k;
        p[o] = pos[3 * v];
        p[o + 1] = pos[3 * v + 1];
        p[o + 2] = pos[3 * v + 2];
        c[o] = r;
        c[o + 1] = gr;
        c[o + 2] = b;
      }
    }
    g.setAttribute('position', new BufferAttribute(p, 3));
    g.setAttribute('color', new BufferAttribute(c, 3));
  } else {
    g.setAttribute('position', new BufferAttribute(own(mesh, mesh.positions), 3));
    g.setIndex(new BufferAttribute(own(mesh, mesh.triangles), 1));
  }
  if (normals && mesh.nTriangles > 0) g.computeVertexNormals();
  g.computeBoundingBox();
  g.computeBoundingSphere();
  return g;
}

// Segments from vertex a(i) to vertex b(i), i < n, coloured colorOf(i) (working-space RGB)
// when colorOf is given.
function segmentsGeometry(mesh, n, a, b, colorOf) {
  const pos = mesh.positions;
  const p = new Float32Array(n * 6);
  const c = colorOf ? new Float32Array(n * 6) : null;
  for (let i = 0; i < n; ++i) {
    const u = a(i);
    const v = b(i);
    p.set([pos[3 * u], pos[3 * u + 1], pos[3 * u + 2], pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]], 6 * i);
    if (c) {
      const col = colorOf(i);
      c.set(col, 6 * i);
      c.set(col, 6 * i + 3);
    }
  }
  const g = new BufferGeometry();
  g.setAttribute('position', new Float32BufferAttribute(p, 3));
  if (c) g.setAttribute('color', new Float32BufferAttribute(c, 3));
  return g;
}

/**
 * The boundary loops that are holes as one LineSegments (one segment per hole
 * edge). { seams: true } adds the seam loops in seamColor. userData.halfedges
 * maps segment i to its boundary half-edge; userData.loops to its loop id. A loop's
 * colour depends only on the loop (a hole is `color` with or without seams); the
 * segments come from the loops' vertex lists (no half-edge array is read).
 */
export function holesToLineSegments(mesh, { color = 0xff2040, seams = false, seamColor = 0xffa000, material } = {}) {
  if (!mesh.halfedges) throw new Error('stltopo/three: the mesh has no topology (loaded with topology: false)');
  const loops = seams ? [...mesh.holes, ...mesh.seams].sort((a, b) => a.id - b.id) : mesh.holes;
  let n = 0;
  for (const l of loops) n += l.halfedges.length;
  const halfedges = new Uint32Array(n);
  const loopIds = new Uint32Array(n);
  const from = new Uint32Array(n); // org and dst of segment i, from the loops' vertex lists
  const to = new Uint32Array(n);
  let i = 0;
  for (const l of loops) {
    const len = l.halfedges.length;
    halfedges.set(l.halfedges, i);
    loopIds.fill(l.id, i, i + len);
    from.set(l.vertices, i);
    to.set(l.vertices.subarray(1), i);
    if (len) to[i + len - 1] = l.vertices[0];
    i += len;
  }
  const isSeam = mesh.loops.isSeam;
  const holeRgb = workingRgb(color);
  const seamRgb = workingRgb(seamColor);
  const g = segmentsGeometry(mesh, n, (k) => from[k], (k) => to[k], seams ? (k) => (isSeam[loopIds[k]] ? seamRgb : holeRgb) : null);
  const m = material || (seams ? new LineBasicMaterial({ vertexColors: true }) : new LineBasicMaterial({ color }));
  const lines = new LineSegments(g, m);
  lines.name = 'stltopo-holes';
  lines.userData = { halfedges, loops: loopIds };
  return lines;
}

/**
 * The non-manifold (nonManifoldColor) and inconsistent (inconsistentColor)
 * edges as one LineSegments with vertex colours, one segment per undirected
 * edge. userData.halfedges maps segment i to a half-edge of that edge and
 * userData.kinds to its EdgeKind (2 inconsistent, 3 non-manifold).
 */
export function problemEdgesToLineSegments(mesh, { nonManifoldColor = 0xff00ff, inconsistentColor = 0xffa000, material } = {}) {
  if (!mesh.halfedges) throw new Error('stltopo/three: the mesh has no topology (loaded with topology: false)');
  const kind = mesh.problems.pairKind;
  const vert = mesh.halfedges.vert;
  const seen = new Set();
  const list = [];
  const kinds = [];
  for (let k = 0; k < kind.length; ++k) {
    if (kind[k] < 2) continue;
    const a = vert[2 * k];
    const b = vert[2 * k + 1];
    const key = a < b ? `${a},${b}` : `${b},${a}`;
    if (seen.has(key)) continue; // a non-manifold edge holds several pairs
    seen.add(key);
    list.push(2 * k);
    kinds.push(kind[k]);
  }
  const halfedges = Uint32Array.from(list);
  const nmRgb = workingRgb(nonManifoldColor);
  const icRgb = workingRgb(inconsistentColor);
  const g = segmentsGeometry(mesh, list.length, (i) => vert[list[i]], (i) => vert[(list[i] ^ 1) >>> 0],
    (i) => (kinds[i] === 3 ? nmRgb : icRgb));
  const lines = new LineSegments(g, material || new LineBasicMaterial({ vertexColors: true }));
  lines.name = 'stltopo-problem-edges';
  lines.userData = { halfedges, kinds: Uint8Array.from(kinds) };
  return lines;
}

/**
 * A stltopo Mesh (what loadStl() gives) from a three.js BufferGeometry, indexed or not:
 * position (any item type, interleaved or not) becomes positions; the index, or 0, 1, 2, ...
 * for a non-indexed geometry, becomes triangles; groups become solids named
 * "material <materialIndex>" (sorted by start; a group running past the end stops there).
 * Non-indexed geometry is welded exactly (weld: 'none' would leave every triangle apart);
 * indexed geometry takes options.weld ('exact' by default, so that the seams renderers
 * split vertices at for normals and UVs do not show as holes). The other options are
 * fromIndexed()'s (worker, view, topology, ...). drawRange is not looked at.
 */
export async function fromBufferGeometry(geometry, options = {}) {
  const pos = geometry && geometry.getAttribute && geometry.getAttribute('position');
  if (!pos) throw stlError('invalid-argument', 'fromBufferGeometry() needs a BufferGeometry with a position attribute');
  let positions;
  if (!pos.isInterleavedBufferAttribute && pos.itemSize === 3 && pos.array instanceof Float32Array && !pos.normalized) {
    positions = pos.array.length === 3 * pos.count ? pos.array : pos.array.subarray(0, 3 * pos.count);
  } else {
    positions = new Float32Array(3 * pos.count);
    for (let v = 0; v < pos.count; ++v) {
      positions[3 * v] = pos.getX(v);
      positions[3 * v + 1] = pos.getY(v);
      positions[3 * v + 2] = pos.getZ(v);
    }
  }
  const index = geometry.getIndex();
  let triangles;
  if (index) {
    triangles = index.array instanceof Uint32Array && index.array.length === index.count ? index.array : Uint32Array.from(index.array.subarray(0, index.count));
  } else {
    triangles = new Uint32Array(pos.count);
    for (let i = 0; i < pos.count; ++i) triangles[i] = i;
  }
  const nt = Math.floor(triangles.length / 3);
  const solids = [...(geometry.groups || [])]
    .sort((a, b) => a.start - b.start)
    .map((g) => {
      const first = Math.floor(g.start / 3);
      const end = Math.min(nt, Number.isFinite(g.count) ? Math.floor((g.start + g.count) / 3) : nt);
      return { name: `material ${g.materialIndex ?? 0}`, firstTriangle: first, triangleCount: Math.max(0, end - first) };
    });
  const { fromIndexed } = await import('stltopo');
  return fromIndexed(positions, triangles, { ...options, solids, weld: index ? options.weld : (options.weld === 'none' ? 'exact' : options.weld) });
}
