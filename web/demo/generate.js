// Meshes the page builds itself, written as binary STL so that they go through the same reader as
// a dropped file. Every vertex comes from one table, so identical corners weld exactly.

/**
 * Packs triangles into a binary STL.
 * corners: Float32Array, 9 floats per triangle (x0 y0 z0 x1 y1 z1 x2 y2 z2).
 * attributes: Uint16Array (one per triangle) or null.
 * Returns an ArrayBuffer of 84 + 50·n bytes; the normals are written as zero.
 */
export function writeBinaryStl(corners, attributes, header) {
  const n = corners.length / 9;
  const buf = new ArrayBuffer(84 + 50 * n);
  const bytes = new Uint8Array(buf);
  const text = new TextEncoder().encode(header.slice(0, 80));
  bytes.set(text, 0);
  const dv = new DataView(buf);
  dv.setUint32(80, n, true);
  let o = 84;
  for (let t = 0; t < n; t++) {
    o += 12; // normal (0, 0, 0)
    for (let i = 0; i < 9; i++, o += 4) dv.setFloat32(o, corners[9 * t + i], true);
    dv.setUint16(o, attributes ? attributes[t] : 0, true);
    o += 2;
  }
  return buf;
}

/** VisCAM/SolidView colour attribute: bit 15 set = colour valid, 5 bits each of R, G, B. */
function viscam(r, g, b) {
  const c = (v) => Math.round(v * 31) & 31;
  return 0x8000 | (c(r) << 10) | (c(g) << 5) | c(b);
}

/**
 * A 6×6-per-side box without its top: one hole of 24 edges, coloured per face (VisCAM bits).
 */
export function coloredOpenBox() {
  const n = 6;
  const size = [40, 30, 20];
  const tris = [];
  const attrs = [];
  // Sides in grid units (0/±1 per axis): origin, two edge directions (right-handed, so the normal
  // points outwards), colour. Corners are integer grid points scaled once, so shared edges weld.
  const sides = [
    { o: [0, 0, 0], u: [0, 1, 0], v: [1, 0, 0], rgb: [0.55, 0.55, 0.6] }, // bottom (-z)
    { o: [0, 0, 0], u: [1, 0, 0], v: [0, 0, 1], rgb: [0.95, 0.45, 0.2] }, // front (-y)
    { o: [1, 1, 0], u: [-1, 0, 0], v: [0, 0, 1], rgb: [0.25, 0.6, 0.95] }, // back (+y)
    { o: [0, 1, 0], u: [0, -1, 0], v: [0, 0, 1], rgb: [0.3, 0.8, 0.4] }, // left (-x)
    { o: [1, 0, 0], u: [0, 1, 0], v: [0, 0, 1], rgb: [0.9, 0.8, 0.25] }, // right (+x)
  ];
  const point = (s, i, j) => [0, 1, 2].map((k) => ((s.o[k] * n + s.u[k] * i + s.v[k] * j) * size[k]) / n);
  for (const s of sides) {
    for (let i = 0; i < n; i++) {
      for (let j = 0; j < n; j++) {
        const a = point(s, i, j), b = point(s, i + 1, j), c = point(s, i + 1, j + 1), d = point(s, i, j + 1);
        const shade = 0.82 + 0.18 * ((i + j) % 2);
        const attr = viscam(s.rgb[0] * shade, s.rgb[1] * shade, s.rgb[2] * shade);
        tris.push(...a, ...b, ...c, ...a, ...c, ...d);
        attrs.push(attr, attr);
      }
    }
  }
  return writeBinaryStl(new Float32Array(tris), new Uint16Array(attrs), 'stltopo demo: open box, VisCAM colours');
}

/**
 * A torus of 1000 × 506 quads with 8 holes of 24 × 12 quads cut out: 1,007,392 triangles.
 * Returns an ArrayBuffer of about 50 MB.
 */
export function bigTorus({ nu = 1000, nv = 506, holes = 8, holeSize = 24 } = {}) {
  const R = 60, r = 22;
  const table = new Float32Array(nu * nv * 3);
  for (let i = 0; i < nu; i++) {
    const a = (2 * Math.PI * i) / nu;
    for (let j = 0; j < nv; j++) {
      const b = (2 * Math.PI * j) / nv;
      const k = 3 * (i * nv + j);
      table[k] = (R + r * Math.cos(b)) * Math.cos(a);
      table[k + 1] = (R + r * Math.cos(b)) * Math.sin(a);
      table[k + 2] = r * Math.sin(b);
    }
  }
  const cut = new Uint8Array(nu * nv);
  for (let h = 0; h < holes; h++) {
    const i0 = Math.floor(((h + 0.3) * nu) / holes);
    const j0 = Math.floor(((h % 4) * nv) / 4 + nv / 16);
    for (let i = i0; i < i0 + holeSize; i++) {
      for (let j = j0; j < j0 + Math.round(holeSize / 2); j++) cut[(i % nu) * nv + (j % nv)] = 1;
    }
  }
  let nCut = 0;
  for (const c of cut) nCut += c;
  const nTriangles = 2 * (nu * nv - nCut);
  const corners = new Float32Array(nTriangles * 9);
  let o = 0;
  const put = (i, j) => {
    const k = 3 * ((i % nu) * nv + (j % nv));
    corners[o++] = table[k];
    corners[o++] = table[k + 1];
    corners[o++] = table[k + 2];
  };
  for (let i = 0; i < nu; i++) {
    for (let j = 0; j < nv; j++) {
      if (cut[i * nv + j]) continue;
      put(i, j); put(i + 1, j); put(i + 1, j + 1);
      put(i, j); put(i + 1, j + 1); put(i, j + 1);
    }
  }
  return writeBinaryStl(corners, null, `stltopo demo: torus, ${nTriangles} triangles, ${holes} holes`);
}

export const generators = { coloredOpenBox, bigTorus };
