// Edits per second through the npm package (wasm), the same sequence as stltopo_edits.
//   node bench/edits.mjs FILE [N] [--json]
// Times N edits of each kind on random elements (fixed seed): removeTriangle; addTriangle
// (the removed ones put back); flipEdge, splitEdge, collapseEdge; reverseTriangle; fillHole
// (fan) on the holes of up to N fresh removals that share no vertex. Refused edits count as attempts. No arrays or
// stats are read between edits, except the corners of the triangle to remove (one copy of
// the triangles array per 4096 removals). The rate is per CPU second of the process.
import { loadStlFile, EditableMesh } from 'stltopo';

const args = process.argv.slice(2).filter((a) => a !== '--json');
const json = process.argv.includes('--json');
const file = args[0];
const n = Number(args[1] || 100000);
const mesh = await loadStlFile(file);
const em = await EditableMesh.from(mesh);
em.reserve(2 * n, 4 * n); // no timed edit is the one that doubles an array
let seed = 1n;
const rand = (bound) => {
  seed = (seed * 6364136223846793005n + 1442695040888963407n) & 0xffffffffffffffffn;
  return Number((seed >> 33n) % BigInt(bound));
};
const tri = () => em.triangles;
const liveTriangle = () => {
  const t0 = em.nTriangles;
  let t = rand(t0);
  const T = tri();
  while (T[3 * t] === 0xffffffff) t = (t + 1) % t0;
  return t;
};
const rows = [];
function timed(op, body, count = n) {
  let done = 0;
  const t0 = performance.now();
  const c0 = process.cpuUsage();
  for (let i = 0; i < count; ++i) {
    try {
      body(i);
      ++done;
    } catch (e) {
      if (e.code !== 'edit-refused' && e.code !== 'invalid-argument') throw e;
    }
  }
  const c = process.cpuUsage(c0);
  const cpu = (c.user + c.system) / 1e3;
  const ms = performance.now() - t0;
  rows.push({ op, attempts: count, done, ms, cpu, perSecond: Math.round(count / (cpu / 1e3)) });
}
// Random triangles and half-edges are drawn before each timed run (reading the arrays is
// O(n) after an edit, by contract), so the timed loops make only the edits.
const pickTriangles = () => {
  const T = tri();
  const out = [];
  const seen = new Set();
  while (out.length < n) {
    let t = rand(em.nTriangles);
    while (T[3 * t] === 0xffffffff || seen.has(t)) t = (t + 1) % em.nTriangles;
    seen.add(t);
    out.push(t);
  }
  return out;
};
const pickHalfedges = () => {
  const V = em.halfedges.vert;
  return Array.from({ length: n }, () => {
    let e = rand(em.nHalfedges);
    while (V[e] === 0xffffffff) e = (e + 1) % em.nHalfedges;
    return e;
  });
};
let ts = pickTriangles();
const T0 = tri();
const corners = ts.map((t) => [T0[3 * t], T0[3 * t + 1], T0[3 * t + 2]]);
timed('removeTriangle', (i) => em.removeTriangle(ts[i]));
timed('addTriangle', (i) => em.addTriangle(...corners[i]));
let hs = pickHalfedges();
timed('flipEdge', (i) => em.flipEdge(hs[i]));
hs = pickHalfedges();
timed('splitEdge', (i) => em.splitEdge(hs[i], 0.5));
hs = pickHalfedges();
timed('collapseEdge', (i) => em.collapseEdge(hs[i], 0.5));
ts = pickTriangles();
timed('reverseTriangle', (i) => em.reverseTriangle(ts[i]));
// Holes that share no vertex: triangles none of whose corners an earlier pick used.
{
  const T = tri();
  const used = new Uint8Array(em.nVertices);
  ts = [];
  for (let k = 0; ts.length < n && k < 50 * n; ++k) {
    const t = rand(em.nTriangles);
    if (T[3 * t] === 0xffffffff || used[T[3 * t]] || used[T[3 * t + 1]] || used[T[3 * t + 2]]) continue;
    used[T[3 * t]] = used[T[3 * t + 1]] = used[T[3 * t + 2]] = 1;
    ts.push(t);
  }
}
const th = em.triangleHalfedge;
const holes = ts.map((t) => th[t]);
for (const t of ts) em.removeTriangle(t);
const nHoles = holes.length;
timed('fillHole', (i) => em.fillHole({ halfedges: [holes[i]] }), nHoles);
const v = em.validate();
if (!v.ok) throw new Error(`validate after the edits: ${v.message}`);
if (json) console.log(JSON.stringify({ triangles: mesh.nTriangles, edits: rows.map((r) => ({ op: r.op, attempts: r.attempts, done: r.done, ms: r.ms, cpuMs: r.cpu, perCpuSecond: r.perSecond })) }));
else console.log(`${file}: ${mesh.nTriangles} triangles, ${n} edits per kind (wasm)`);
if (!json) for (const r of rows) console.log(`  ${r.op.padEnd(16)} ${String(r.attempts).padStart(8)} attempts ${String(r.done).padStart(8)} done ${r.ms.toFixed(1).padStart(9)} ms wall ${r.cpu.toFixed(1).padStart(9)} ms cpu ${String(r.perSecond).padStart(12)} /s cpu`);
em.dispose();
