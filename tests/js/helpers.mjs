// Shared helpers for the Node tests (node:test). The package is imported by
// its own name ('stltopo' resolves to dist/ through package.json "exports").
import { readdirSync, statSync, existsSync } from 'node:fs';
import { spawn } from 'node:child_process';
import { availableParallelism } from 'node:os';
import { fileURLToPath } from 'node:url';
import path from 'node:path';

export const root = fileURLToPath(new URL('../../', import.meta.url));
export const fixturesDir = path.join(root, 'tests/fixtures');

/** Every fixture file (all regular files under tests/fixtures except docs). */
export function fixtures() {
  const out = [];
  const walk = (d) => {
    for (const name of readdirSync(d).sort()) {
      const p = path.join(d, name);
      const st = statSync(p);
      if (st.isDirectory()) walk(p);
      else if (st.isFile() && !/\.(md|txt|json|py)$/i.test(name)) out.push(p);
    }
  };
  walk(fixturesDir);
  return out;
}

/** A fixture by (case-insensitive) file name. */
export function fixture(name) {
  const f = fixtures().find((p) => path.basename(p).toLowerCase() === name.toLowerCase());
  if (!f) throw new Error(`fixture ${name} not found`);
  return f;
}

/** The native CLI (scripts/test.sh builds it); STLTOPO_NATIVE_CLI overrides. */
export const nativeCli = process.env.STLTOPO_NATIVE_CLI || path.join(root, 'build/stltopo');
export const haveNativeCli = existsSync(nativeCli);

/** A ReadableStream that delivers `bytes` in chunks of `size` bytes. */
export function chunkedStream(bytes, size) {
  let off = 0;
  return new ReadableStream({
    pull(controller) {
      if (off >= bytes.length) {
        controller.close();
        return;
      }
      controller.enqueue(bytes.slice(off, off + size));
      off += size;
    },
  });
}

/** A binary STL: an n x n grid of quads (2n^2 triangles), optionally closed into a torus. */
export function gridStl(n, { header = 'grid' } = {}) {
  const nt = 2 * n * n;
  const buf = new ArrayBuffer(84 + 50 * nt);
  const u8 = new Uint8Array(buf);
  u8.set(new TextEncoder().encode(header).subarray(0, 80));
  const dv = new DataView(buf);
  dv.setUint32(80, nt, true);
  let o = 84;
  const put = (x, y) => {
    dv.setFloat32(o, x, true);
    dv.setFloat32(o + 4, y, true);
    dv.setFloat32(o + 8, 0, true);
    o += 12;
  };
  for (let i = 0; i < n; ++i) {
    for (let j = 0; j < n; ++j) {
      o += 12; // normal 0
      put(i, j); put(i + 1, j); put(i + 1, j + 1);
      o += 2;
      o += 12;
      put(i, j); put(i + 1, j + 1); put(i, j + 1);
      o += 2;
    }
  }
  return u8;
}

/**
 * A torus grid (n x m quads) with damage: triangles removed (holes), flipped (inconsistent
 * edges) and repeated (duplicates), drawn from `seed`. Indexed arrays (fromIndexed's input);
 * indexedStl() gives the same mesh as a file.
 */
export function damagedTorus(n, m, seed) {
  const positions = [];
  for (let i = 0; i < n; ++i) {
    for (let j = 0; j < m; ++j) {
      const u = (2 * Math.PI * i) / n, v = (2 * Math.PI * j) / m;
      positions.push((3 + Math.cos(v)) * Math.cos(u), (3 + Math.cos(v)) * Math.sin(u), Math.sin(v));
    }
  }
  let s = seed;
  const rnd = () => ((s = (s * 1103515245 + 12345) >>> 0) % 1000) / 1000;
  const id = (i, j) => ((i + n) % n) * m + ((j + m) % m);
  const tris = [];
  for (let i = 0; i < n; ++i) {
    for (let j = 0; j < m; ++j) {
      for (const t of [[id(i, j), id(i + 1, j), id(i + 1, j + 1)], [id(i, j), id(i + 1, j + 1), id(i, j + 1)]]) {
        const r = rnd();
        if (r < 0.02) continue;
        if (r < 0.06) [t[1], t[2]] = [t[2], t[1]];
        tris.push(...t);
        if (r > 0.98) tris.push(...t);
      }
    }
  }
  return { positions: new Float32Array(positions), triangles: new Uint32Array(tris) };
}

/**
 * The triangles in an order drawn from `seed` (a Fisher-Yates shuffle), each with its corners
 * rotated once (b, c, a): a file whose triangles are not in spatial order.
 */
/**
 * A binary STL of n triangles that share no corner (a soup: a shell and a hole a triangle),
 * triangle t at x = t.
 */
export function soupStl(n) {
  const bytes = new Uint8Array(84 + 50 * n);
  const dv = new DataView(bytes.buffer);
  dv.setUint32(80, n, true);
  for (let t = 0; t < n; ++t) {
    const corners = [[t, 0, 0], [t + 0.5, 1, 0], [t, 0, 1]];
    corners.forEach((c, k) => c.forEach((x, j) => dv.setFloat32(84 + 50 * t + 12 + 12 * k + 4 * j, x, true)));
  }
  return bytes;
}

export function shuffleTriangles(triangles, seed) {
  const nt = triangles.length / 3;
  let s = seed;
  const rnd = (k) => ((s = (s * 1103515245 + 12345) >>> 0) % k);
  const order = [...Array(nt).keys()];
  for (let i = nt - 1; i > 0; --i) {
    const j = rnd(i + 1);
    [order[i], order[j]] = [order[j], order[i]];
  }
  const out = new Uint32Array(triangles.length);
  order.forEach((t, i) => {
    out[3 * i] = triangles[3 * t + 1];
    out[3 * i + 1] = triangles[3 * t + 2];
    out[3 * i + 2] = triangles[3 * t];
  });
  return out;
}

/** Indexed positions and triangles as a binary STL (a Buffer; normals and attribute words 0). */
export function indexedStl(positions, triangles, header = '') {
  const nt = triangles.length / 3;
  const buf = Buffer.alloc(84 + 50 * nt);
  buf.write(header, 0);
  buf.writeUInt32LE(nt, 80);
  for (let t = 0; t < nt; ++t) {
    for (let k = 0; k < 3; ++k) {
      const v = triangles[3 * t + k];
      for (let c = 0; c < 3; ++c) buf.writeFloatLE(positions[3 * v + c], 84 + 50 * t + 12 + 12 * k + 4 * c);
    }
  }
  return buf;
}

/** The arrays of a mesh as plain arrays keyed by name, for deep comparisons. */
export function meshArrays(m) {
  const out = {
    positions: m.positions, triangles: m.triangles, attributes: m.attributes,
    colors: m.colors, colorValid: m.colorValid, normals: m.normals,
  };
  if (m.halfedges) {
    Object.assign(out, m.halfedges, m.problems, {
      triangleHalfedge: m.triangleHalfedge, vertexHalfedge: m.vertexHalfedge,
      loopHalfedge: m.loopHalfedge, vertexWeld: m.vertexWeld,
      loopOffsets: m.loops.offsets, loopHalfedges: m.loops.halfedges,
    });
  }
  return out;
}

/**
 * Runs cmd with args (stdin: `input`, if given) as spawnSync does, without blocking:
 * resolves to { status, stdout, stderr } (Buffers).
 */
export function runAsync(cmd, args, input, options = {}) {
  return new Promise((resolve, reject) => {
    const p = spawn(cmd, args, options);
    const out = [], err = [];
    p.stdout.on('data', (d) => out.push(d));
    p.stderr.on('data', (d) => err.push(d));
    p.on('error', reject);
    p.on('close', (status) => resolve({ status, stdout: Buffer.concat(out), stderr: Buffer.concat(err) }));
    p.stdin.end(input);
  });
}

/**
 * Runs job(item, index) for every item, `width` at a time (default: the machine's cores
 * plus one, as the jobs are processes that wait on each other's I/O), and resolves to the
 * results in the items' order. The first rejection rejects it, after the running jobs end.
 */
export async function pool(items, job, width = availableParallelism() + 1) {
  const results = new Array(items.length);
  let next = 0, failure = null;
  const worker = async () => {
    while (next < items.length && !failure) {
      const i = next++;
      try {
        results[i] = await job(items[i], i);
      } catch (e) {
        failure = failure || e;
      }
    }
  };
  await Promise.all(Array.from({ length: Math.min(width, items.length) }, worker));
  if (failure) throw failure;
  return results;
}

/**
 * manifold-3d's verdict on an indexed part ({ positions, triangles }, as extractShell gives):
 * 'NoError' or the error status it threw or reported. `wasm`: the manifold-3d module, set up.
 */
export function manifoldVerdict(wasm, part) {
  try {
    const m = new wasm.Manifold(new wasm.Mesh({ numProp: 3, vertProperties: part.positions, triVerts: part.triangles }));
    const s = m.status();
    m.delete();
    return s;
  } catch (e) {
    return e.code || String(e.message);
  }
}
