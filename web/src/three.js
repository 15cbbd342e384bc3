// stltopo/three: turn a loaded mesh into three.js objects (three is a peer
// dependency). Copies (the default loadStl result) are shared with three
// without copying; { view: true } meshes are copied, since their views into
// wasm memory detach when it grows and die with mesh.dispose().
import {
  BufferAttribute,
  BufferGeometry,
  Float32BufferAttribute,
  LineBasicMaterial,
  LineSegments,
} from 'three';

const own = (mesh, a) => (mesh.view ? a.slice() : a);

/**
 * An indexed BufferGeometry (position + index, vertex normals), or, with
 * { colors: true } on a mesh that has per-triangle colours, a non-indexed one
 * with a per-vertex `color` attribute (uncoloured triangles get defaultColor).
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
    const c = new Uint8Array(nt * 9);
    for (let t = 0; t < nt; ++t) {
      const has = !valid || valid[t] !== 0;
      for (let k = 0; k < 3; ++k) {
        const v = tri[3 * t + k];
        const o = 9 * t + 3 * k;
        p[o] = pos[3 * v];
        p[o + 1] = pos[3 * v + 1];
        p[o + 2] = pos[3 * v + 2];
        c[o] = has ? rgb[3 * t] : defaultColor[0];
        c[o + 1] = has ? rgb[3 * t + 1] : defaultColor[1];
        c[o + 2] = has ? rgb[3 * t + 2] : defaultColor[2];
      }
    }
    g.setAttribute('position', new BufferAttribute(p, 3));
    g.setAttribute('color', new BufferAttribute(c, 3, true));
  } else {
    g.setAttribute('position', new BufferAttribute(own(mesh, mesh.positions), 3));
    g.setIndex(new BufferAttribute(own(mesh, mesh.triangles), 1));
  }
  if (normals && mesh.nTriangles > 0) g.computeVertexNormals();
  g.computeBoundingBox();
  g.computeBoundingSphere();
  return g;
}

// Segments for a list of half-edges: one per half-edge e, from org(e) to dst(e).
function segmentsGeometry(mesh, halfedges, colorOf) {
  const vert = mesh.halfedges.vert;
  const pos = mesh.positions;
  const p = new Float32Array(halfedges.length * 6);
  const c = colorOf ? new Float32Array(halfedges.length * 6) : null;
  for (let i = 0; i < halfedges.length; ++i) {
    const e = halfedges[i];
    const a = vert[e];
    const b = vert[(e ^ 1) >>> 0];
    p.set([pos[3 * a], pos[3 * a + 1], pos[3 * a + 2], pos[3 * b], pos[3 * b + 1], pos[3 * b + 2]], 6 * i);
    if (c) {
      const col = colorOf(e);
      c.set(col, 6 * i);
      c.set(col, 6 * i + 3);
    }
  }
  const g = new BufferGeometry();
  g.setAttribute('position', new Float32BufferAttribute(p, 3));
  if (c) g.setAttribute('color', new Float32BufferAttribute(c, 3));
  return g;
}

function toRgb(color) {
  return [((color >> 16) & 255) / 255, ((color >> 8) & 255) / 255, (color & 255) / 255];
}

/**
 * The boundary loops that are holes as one LineSegments (one segment per hole
 * edge). { seams: true } adds the seam loops in seamColor. userData.halfedges
 * maps segment i to its boundary half-edge; userData.loops to its loop id.
 */
export function holesToLineSegments(mesh, { color = 0xff2040, seams = false, seamColor = 0xffa000, material } = {}) {
  if (!mesh.halfedges) throw new Error('stltopo/three: the mesh has no topology (loaded with topology: false)');
  const loops = seams ? [...mesh.holes, ...mesh.seams].sort((a, b) => a.id - b.id) : mesh.holes;
  let n = 0;
  for (const l of loops) n += l.halfedges.length;
  const halfedges = new Uint32Array(n);
  const loopIds = new Uint32Array(n);
  let i = 0;
  for (const l of loops) {
    halfedges.set(l.halfedges, i);
    loopIds.fill(l.id, i, i + l.halfedges.length);
    i += l.halfedges.length;
  }
  const isSeam = mesh.loops.isSeam;
  const holeRgb = toRgb(color);
  const seamRgb = toRgb(seamColor);
  const face = mesh.halfedges.face;
  const g = segmentsGeometry(mesh, halfedges, seams ? (e) => (isSeam[face[e] - mesh.nTriangles] ? seamRgb : holeRgb) : null);
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
  const nmRgb = toRgb(nonManifoldColor);
  const icRgb = toRgb(inconsistentColor);
  const g = segmentsGeometry(mesh, halfedges, (e) => (kind[e >>> 1] === 3 ? nmRgb : icRgb));
  const lines = new LineSegments(g, material || new LineBasicMaterial({ vertexColors: true }));
  lines.name = 'stltopo-problem-edges';
  lines.userData = { halfedges, kinds: Uint8Array.from(kinds) };
  return lines;
}
