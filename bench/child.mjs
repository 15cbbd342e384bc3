// One benchmark measurement in a fresh Node process (spawned by bench/run.mjs).
//   node --expose-gc bench/child.mjs MODE FILE WARM BUDGET_MS
// MODE: wasm-read | wasm-full | wasm-view | three | three-halfedge | write
// (write: the file's mesh written as binary and ASCII STL, WARM times each, by stltopo's
// toStl (wasm) and by three.js's STLExporter on the STLLoader mesh; MB/s of output)
// (wasm-view: loadStl(bytes, { view: true }), arrays left in wasm memory, then dispose())
// Prints one JSON line: first-call time, warm times (up to WARM more calls while the
// total stays under BUDGET_MS), peak RSS above this process before the file was read
// (process.resourceUsage().maxRSS, KiB), the wasm linear-memory size, and check counts.
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';

const [mode, file, warmArg = '2', budgetArg = '10000'] = process.argv.slice(2);
const warmMax = Number(warmArg);
const budgetMs = Number(budgetArg);
const gc = globalThis.gc || (() => {});
const maxRss = () => process.resourceUsage().maxRSS; // KiB
const out = { mode };

// [wall ms or { ms, stages }, result, process CPU ms (all threads: includes GC helpers
// and background compilation)]
async function timed(fn) {
  gc();
  const c0 = process.cpuUsage();
  const t0 = performance.now();
  const r = await fn();
  const t = performance.now() - t0;
  const c = process.cpuUsage(c0);
  return [t, r, (c.user + c.system) / 1000];
}

async function run(setup, call, check, release = () => {}) {
  const t0 = performance.now();
  await setup();
  out.initMs = performance.now() - t0;
  gc();
  out.rssIdleKiB = maxRss();
  const bytes = readFileSync(file); // a Node Buffer (Uint8Array), read outside the timing
  out.inputBytes = bytes.length;
  let [first, r, firstCpu] = await timed(() => call(bytes));
  out.firstCpuMs = firstCpu;
  out.rssPeakKiB = maxRss();
  out.firstMs = first.ms ?? first;
  if (first.stages) out.firstStages = first.stages;
  Object.assign(out, check(r));
  release(r);
  // Nothing of a call is kept through the next one, so that an allocator that keeps freed
  // memory (the -kept contenders) can give its pages to the next call.
  r = null;
  const warm = [];
  const warmCpu = [];
  const warmStages = [];
  const tw = performance.now();
  let last = out.firstMs;
  while (warm.length < warmMax && performance.now() - tw + last < budgetMs) {
    const [t, r2, cpu] = await timed(() => call(bytes));
    last = t.ms ?? t;
    warm.push(last);
    warmCpu.push(cpu);
    if (t.stages) warmStages.push(t.stages);
    release(r2);
  }
  out.warmMs = warm;
  out.warmCpuMs = warmCpu;
  if (warmStages.length) out.warmStages = warmStages;
}

if (mode === 'wasm-read' || mode === 'wasm-full' || mode === 'wasm-view') {
  const topology = mode !== 'wasm-read';
  const view = mode === 'wasm-view';
  const { loadStl } = await import('stltopo');
  const _internal = (await import('../dist/instance.node.js')).api.internal;
  await run(
    async () => {
      await _internal.getModule();
      out.heapIdleBytes = (await _internal.heap()).size;
    },
    // The whole cost (issue 24): the wasm-full figure includes the first read of every
    // half-edge array (a copy builds prev, face and vert in JS then; a view reads them in place).
    async (bytes) => {
      const mesh = await loadStl(bytes, { topology, view });
      if (topology) for (const k of ['next', 'prev', 'vert', 'face']) void mesh.halfedges[k].length;
      return mesh;
    },
    (mesh) => ({ triangles: mesh.nTriangles, vertices: mesh.nVertices, holes: mesh.holes.length, edges: mesh.stats.edges }),
    (mesh) => mesh.dispose(),
  );
  // The wasm linear memory never shrinks: its size after the first call is the high-water
  // mark of the heap (WebAssembly.Memory buffer byteLength, via emscripten_get_heap_size).
  out.heapBytes = (await _internal.heap()).size;
  if (mode === 'wasm-full') {
    // Copies leave halfedges.prev, face and vert to be rebuilt in JS on first read (the
    // core does not build prev and face for them): what that first read costs, once (it is
    // inside the figures above too).
    const mesh = await loadStl(readFileSync(file), { topology, view });
    gc();
    const t0 = performance.now();
    const { prev, face, vert } = mesh.halfedges;
    out.derivedHalfedgesMs = performance.now() - t0;
    if (prev.length !== mesh.nHalfedges || face.length !== prev.length || vert.length !== prev.length) {
      throw new Error('derived half-edge arrays have the wrong length');
    }
  }
} else if (mode === 'three' || mode === 'three-halfedge') {
  let STLLoader, mergeVertices, HalfedgeDS;
  const halfedge = mode === 'three-halfedge';
  await run(
    async () => {
      ({ STLLoader } = await import('three/examples/jsm/loaders/STLLoader.js'));
      ({ mergeVertices } = await import('three/examples/jsm/utils/BufferGeometryUtils.js'));
      if (halfedge) ({ HalfedgeDS } = await import('three-mesh-halfedge/build/index.esm.js'));
    },
    (bytes) => {
      // STLLoader.parse wants an ArrayBuffer (or a string); the Buffer's bytes are a view
      // into Node's pool, so hand it exactly the file's range.
      const ab = bytes.byteOffset === 0 && bytes.byteLength === bytes.buffer.byteLength
        ? bytes.buffer
        : bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
      const t0 = performance.now();
      const geometry = new STLLoader().parse(ab);
      const t1 = performance.now();
      geometry.deleteAttribute('normal');
      const merged = mergeVertices(geometry);
      const t2 = performance.now();
      const stages = { parseMs: t1 - t0, mergeMs: t2 - t1 };
      let struct = null;
      if (halfedge) {
        struct = new HalfedgeDS();
        struct.setFromGeometry(merged);
        stages.halfedgeMs = performance.now() - t2;
      }
      return { ms: performance.now() - t0, stages, merged, struct };
    },
    (r) => {
      const res = {
        triangles: r.merged.index.count / 3,
        vertices: r.merged.attributes.position.count,
      };
      if (r.struct) {
        res.halfedges = r.struct.halfedges.length;
        res.boundaryHalfedges = r.struct.halfedges.reduce((n, h) => n + (h.face ? 0 : 1), 0);
      }
      return res;
    },
  );
} else if (mode === 'write') {
  const { loadStl, toStl } = await import('stltopo');
  const { STLLoader } = await import('three/examples/jsm/loaders/STLLoader.js');
  const { STLExporter } = await import('three/examples/jsm/exporters/STLExporter.js');
  const THREE = await import('three');
  const bytes = readFileSync(file);
  out.inputBytes = bytes.length;
  const mesh = await loadStl(bytes, { topology: false });
  const ab = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const object = new THREE.Mesh(new STLLoader().parse(ab), new THREE.MeshBasicMaterial());
  const reps = Math.max(1, warmMax);
  const measure = async (fn) => {
    const ms = [];
    let size = 0;
    for (let r = 0; r < reps; ++r) {
      gc();
      const t0 = performance.now();
      size = await fn();
      ms.push(performance.now() - t0);
    }
    ms.sort((a, b) => a - b);
    const med = ms[Math.floor(ms.length / 2)];
    return { bytes: size, ms: med, mbPerSecond: size / 1e3 / med };
  };
  out.triangles = mesh.nTriangles;
  out.wasm = {
    binary: await measure(async () => (await toStl(mesh)).length),
    ascii: await measure(async () => (await toStl(mesh, { format: 'ascii' })).length),
  };
  const exporter = new STLExporter();
  out.threeExporter = {
    binary: await measure(async () => exporter.parse(object, { binary: true }).byteLength),
    ascii: await measure(async () => exporter.parse(object, { binary: false }).length),
  };
} else {
  console.error(`child.mjs: unknown mode ${mode}`);
  process.exit(2);
}
process.stdout.write(`${JSON.stringify(out)}\n`);
