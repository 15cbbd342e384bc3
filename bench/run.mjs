#!/usr/bin/env node
// The benchmark (issue 7): stltopo against three.js, three-mesh-halfedge, admesh and itself.
//   node bench/run.mjs [--quick] [--tiny] [--reps N] [--warm N] [--sizes 100k,1M,4M]
//                      [--only REGEX] [--contenders a,b] [--halfedge-cap SEC] [--out FILE]
// `npm run bench` (scripts/bench.sh) installs and builds what this needs, then runs it.
//
// Every contender reads the same bytes. One child process per measurement, run one at a
// time; the repetitions alternate between the contenders (rep r runs them all, in an
// order rotated by r), and every figure is the median over the repetitions.
//   native        build-bench/bench/stltopo_stages: in-process C++ API, per-stage times;
//                 first call and warm (median of the later calls in the same process)
//   native-cli    build-bench/stltopo info --json FILE, whole process (procstat: wall
//                 time and peak RSS from wait4)
//   wasm-read     loadStl(bytes, { topology: false }) in Node, first call and warm
//   wasm-full     loadStl(bytes) (full topology), first call and warm
//   wasm-view     loadStl(bytes, { view: true }) + dispose(): the same without copying the
//                 arrays out of wasm memory (shows what the copies cost)
//   three         three.js STLLoader.parse + deleteAttribute('normal') + mergeVertices
//   three-halfedge  the same + three-mesh-halfedge HalfedgeDS.setFromGeometry (binary,
//                 up to 1M triangles, one call per process, killed at --halfedge-cap)
//   admesh        admesh -e FILE, whole process
// Output: markdown tables on stdout (also bench/results/latest.md) and every figure and
// ratio in bench/results/latest.json (--out). Meshes are generated into bench/data/.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const rel = (p) => path.relative(root, p);

// ---------------------------------------------------------------------------
// Options

const SIZES = { tiny: 3000, '100k': 100000, '1M': 1000000, '4M': 4000000 };
const ASCII_SIZES = ['tiny', '100k', '1M'];
const HALFEDGE_SIZES = ['tiny', '100k', '1M'];
const ALL_CONTENDERS = ['native', 'native-cli', 'wasm-read', 'wasm-full', 'wasm-view', 'three', 'three-halfedge', 'admesh'];

function usage(code) {
  (code ? console.error : console.log)(`usage: node bench/run.mjs [options]
  --quick              the 100k cases only, without wasm-view, one warm three.js call (under a minute)
  --tiny               ${SIZES.tiny}-triangle cases, 1 repetition (the npm test smoke run)
  --sizes LIST         comma-separated sizes from ${Object.keys(SIZES).join(',')} (default 100k,1M,4M)
  --reps N             repetitions per contender and case (default 3; --tiny 1)
  --warm N             warm calls after the first one, in-process contenders (default 4)
  --only REGEX         only the cases whose id matches (ids: bin-1M-shuffled-holes, ascii-100k, ...)
  --contenders LIST    subset of ${ALL_CONTENDERS.join(',')}
  --halfedge-cap SEC   time cap of one three-mesh-halfedge run (default 60)
  --child-cap SEC      time cap of any other child process (default 900)
  --first-touch GIB    touch this much memory twice before measuring and report how fast that was
                       (default 1; --tiny 0); see "Memory first touch" below
  --out FILE           JSON results (default bench/results/latest.json; --tiny, --quick: a temp file)
  --no-write           write no result files`);
  process.exit(code);
}

const opt = {
  sizes: null, reps: null, warm: null, only: null, contenders: null, halfedgeCap: 60,
  childCap: 900, out: null, write: true, quick: false, tiny: false, firstTouchGiB: null,
};
{
  const a = process.argv.slice(2);
  for (let i = 0; i < a.length; ++i) {
    const v = () => { if (i + 1 >= a.length) usage(2); return a[++i]; };
    switch (a[i]) {
      case '--quick': opt.quick = true; break;
      case '--tiny': opt.tiny = true; break;
      case '--sizes': opt.sizes = v().split(',').filter(Boolean); break;
      case '--reps': opt.reps = Math.max(1, Number(v()) | 0); break;
      case '--warm': opt.warm = Math.max(0, Number(v()) | 0); break;
      case '--only': opt.only = new RegExp(v()); break;
      case '--contenders': opt.contenders = v().split(',').filter(Boolean); break;
      case '--halfedge-cap': opt.halfedgeCap = Number(v()); break;
      case '--child-cap': opt.childCap = Number(v()); break;
      case '--out': opt.out = path.resolve(v()); break;
      case '--first-touch': opt.firstTouchGiB = Math.max(0, Number(v()) || 0); break;
      case '--no-write': opt.write = false; break;
      case '-h': case '--help': usage(0); break;
      default: console.error(`run.mjs: unknown option ${a[i]}`); usage(2);
    }
  }
  for (const s of opt.sizes || []) if (!(s in SIZES)) { console.error(`run.mjs: unknown size ${s}`); usage(2); }
  // --quick leaves out wasm-view (not a contender of the issue) to stay under a minute.
  opt.contenders ??= opt.quick ? ALL_CONTENDERS.filter((k) => k !== 'wasm-view') : ALL_CONTENDERS;
  for (const c of opt.contenders) if (!ALL_CONTENDERS.includes(c)) { console.error(`run.mjs: unknown contender ${c}`); usage(2); }
  opt.sizes ??= opt.tiny ? ['tiny'] : opt.quick ? ['100k'] : ['100k', '1M', '4M'];
  opt.reps ??= opt.tiny ? 1 : 3;
  opt.warm ??= opt.tiny ? 1 : 4;
  // bench/results/latest.* hold the full run the README's table comes from: --quick and
  // --tiny write elsewhere unless --out says.
  opt.out ??= opt.tiny ? path.join(os.tmpdir(), `stltopo-bench-smoke-${process.pid}.json`)
    : opt.quick ? path.join(os.tmpdir(), `stltopo-bench-quick-${process.pid}.json`)
      : path.join(root, 'bench/results/latest.json');
}

const BUILD = path.join(root, process.env.STLTOPO_BENCH_BUILD_DIR || 'build-bench');
const BIN = {
  genmesh: path.join(BUILD, 'bench/genmesh'),
  stages: path.join(BUILD, 'bench/stltopo_stages'),
  procstat: path.join(BUILD, 'bench/procstat'),
  edits: path.join(BUILD, 'bench/stltopo_edits'),
  cli: path.join(BUILD, 'stltopo'),
  admesh: process.env.ADMESH || 'admesh',
};
const DATA = path.join(root, 'bench/data');
const CHILD = path.join(root, 'bench/child.mjs');
const NODE_FLAGS = ['--expose-gc', '--max-old-space-size=16384'];

for (const [k, p] of Object.entries(BIN)) {
  if (k !== 'admesh' && !fs.existsSync(p)) {
    console.error(`run.mjs: ${rel(p)} is missing; build it with scripts/bench.sh (npm run bench) or\n` +
      `  cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DSTLTOPO_BUILD_BENCH=ON && cmake --build build-bench -j2`);
    process.exit(1);
  }
}
if (!fs.existsSync(path.join(root, 'dist/node.js'))) {
  console.error('run.mjs: dist/ is missing; build the package with npm run build (scripts/build-wasm.sh)');
  process.exit(1);
}

const log = (...m) => console.error(...m);
const errors = [];

// ---------------------------------------------------------------------------
// Helpers

function median(xs) {
  const v = xs.filter((x) => typeof x === 'number' && Number.isFinite(x)).sort((a, b) => a - b);
  if (!v.length) return null;
  const n = v.length;
  return n % 2 ? v[(n - 1) / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}
const round = (x, d = 3) => (x === null || x === undefined ? null : Number(x.toFixed(d)));

function run(cmd, args, { timeoutSec = opt.childCap, env } = {}) {
  const r = spawnSync(cmd, args, {
    cwd: root, encoding: 'utf8', maxBuffer: 64 << 20, timeout: timeoutSec * 1000, killSignal: 'SIGKILL',
    env: env ? { ...process.env, ...env } : process.env,
  });
  const timedOut = r.error && r.error.code === 'ETIMEDOUT';
  return { status: r.status, signal: r.signal, stdout: r.stdout || '', stderr: r.stderr || '', timedOut, error: r.error };
}

function lastJsonLine(text) {
  const lines = text.trim().split('\n').filter((l) => l.startsWith('{'));
  if (!lines.length) throw new Error(`no JSON in output: ${text.slice(0, 300)}`);
  return JSON.parse(lines[lines.length - 1]);
}

// procstat: one whole-process run (wall time + peak RSS), the child's stdout in a temp file.
const tmpOut = path.join(os.tmpdir(), `stltopo-bench-${process.pid}.out`);
function procstat(args, timeoutSec = opt.childCap) {
  const r = run(BIN.procstat, ['--stdout', tmpOut, '--timeout', String(timeoutSec), '--', ...args], { timeoutSec: timeoutSec + 30 });
  if (r.status !== 0) throw new Error(`procstat failed: ${r.stderr || r.error}`);
  const p = JSON.parse(r.stdout.trim());
  p.stdout = fs.existsSync(tmpOut) ? fs.readFileSync(tmpOut, 'utf8') : '';
  return p;
}

function sh(cmd, args) {
  const r = spawnSync(cmd, args, { encoding: 'utf8' });
  return r.status === 0 ? (r.stdout || '').trim() : null;
}

// ---------------------------------------------------------------------------
// Meshes

function meshFile(size, { shuffle = false, holes = false, ascii = false } = {}) {
  const name = `torus-${size}${ascii ? '-ascii' : ''}${shuffle ? '-shuffled' : ''}${holes ? '-holes' : ''}.stl`;
  return path.join(DATA, name);
}

function ensureMesh(file, triangles, flags) {
  const src = path.join(root, 'bench/genmesh.cpp');
  if (fs.existsSync(file) && fs.statSync(file).mtimeMs >= fs.statSync(src).mtimeMs) return;
  log(`generating ${rel(file)}`);
  const r = run(BIN.genmesh, [String(triangles), file + '.part', ...flags]);
  if (r.status !== 0) throw new Error(`genmesh failed: ${r.stderr}`);
  fs.renameSync(file + '.part', file);
}

const cases = [];
fs.mkdirSync(DATA, { recursive: true });
for (const size of opt.sizes) {
  for (const holes of [false, true]) {
    for (const shuffle of [false, true]) {
      const id = `bin-${size}-${shuffle ? 'shuffled' : 'ordered'}${holes ? '-holes' : ''}`;
      cases.push({ id, size, format: 'binary', order: shuffle ? 'shuffled' : 'ordered', holes, file: meshFile(size, { shuffle, holes }), flags: [...(shuffle ? ['--shuffle'] : []), ...(holes ? ['--holes'] : [])] });
    }
  }
  if (ASCII_SIZES.includes(size)) {
    cases.push({ id: `ascii-${size}`, size, format: 'ascii', order: 'ordered', holes: false, file: meshFile(size, { ascii: true }), flags: ['--ascii'] });
  }
}
const selected = cases.filter((c) => !opt.only || opt.only.test(c.id));
if (!selected.length) { console.error('run.mjs: no case selected'); process.exit(2); }
for (const c of selected) ensureMesh(c.file, SIZES[c.size], c.flags);
const idleFile = path.join(DATA, 'torus-idle.stl');
ensureMesh(idleFile, 18, []);

function contendersFor(c) {
  return opt.contenders.filter((k) => k !== 'three-halfedge' || (c.format === 'binary' && HALFEDGE_SIZES.includes(c.size)));
}

// ---------------------------------------------------------------------------
// One measurement per contender

const cliArgs = (file) => [BIN.cli, 'info', '--json', file];
const admeshArgs = (file) => [BIN.admesh, '-e', file];

function parseAdmesh(text) {
  const num = (re) => { const m = text.match(re); return m ? Number(m[1]) : null; };
  const f1 = num(/Facets with 1 disconnected edge\s*:\s*\d+\s+(\d+)/);
  const f2 = num(/Facets with 2 disconnected edges\s*:\s*\d+\s+(\d+)/);
  const f3 = num(/Facets with 3 disconnected edges\s*:\s*\d+\s+(\d+)/);
  return {
    triangles: num(/Number of facets\s*:\s*\d+\s+(\d+)/),
    disconnectedEdges: f1 === null ? null : f1 + 2 * f2 + 3 * f3,
  };
}

// Small cases run in tens of milliseconds, where one busy moment of the machine decides
// the figure: there, a whole-process sample is the median of 3 back-to-back runs (by wall
// time) and the in-process harness makes at least 5 warm calls.
const small = (c) => SIZES[c.size] <= SIZES['100k'];
function procstatMedian(c, args) {
  if (!small(c)) return procstat(args);
  const xs = [procstat(args), procstat(args), procstat(args)].sort((a, b) => a.wallMs - b.wallMs);
  return xs[1];
}

const measure = {
  native(c) {
    const r = run(BIN.stages, [c.file, String(1 + (small(c) ? Math.max(opt.warm, 5) : opt.warm)), '--json']);
    if (r.status !== 0) throw new Error(`stltopo_stages: ${r.stderr}`);
    // The full topology (prev and face included) with the input streamed in 1 MiB chunks,
    // in a process of its own: its peak RSS above the RSS before the read.
    const p = run(BIN.stages, [c.file, '--streamed-peak']);
    if (p.status !== 0) throw new Error(`stltopo_stages --streamed-peak: ${p.stderr}`);
    return { ...lastJsonLine(r.stdout), streamed: lastJsonLine(p.stdout) };
  },
  'native-cli'(c) {
    const p = procstatMedian(c, cliArgs(c.file));
    if (p.status !== 0) throw new Error(`stltopo info exited ${p.status} (signal ${p.signal})`);
    const j = lastJsonLine(p.stdout);
    return { wallMs: p.wallMs, cpuMs: p.userMs + p.sysMs, maxRssKiB: p.maxRssKiB, triangles: j.triangles, vertices: j.vertices, holes: j.holes, boundaryEdges: j.boundaryEdges };
  },
  admesh(c) {
    const p = procstatMedian(c, admeshArgs(c.file));
    if (p.status !== 0) throw new Error(`admesh exited ${p.status} (signal ${p.signal})`);
    return { wallMs: p.wallMs, cpuMs: p.userMs + p.sysMs, maxRssKiB: p.maxRssKiB, ...parseAdmesh(p.stdout) };
  },
  'wasm-read': (c) => nodeChild('wasm-read', c),
  'wasm-full': (c) => nodeChild('wasm-full', c),
  'wasm-view': (c) => nodeChild('wasm-view', c),
  three: (c) => nodeChild('three', c, { warm: opt.quick ? 1 : opt.warm }),
  'three-halfedge': (c) => nodeChild('three-halfedge', c, { warm: 0, capSec: opt.halfedgeCap }),
};

function nodeChild(mode, c, { warm = opt.warm, capSec = opt.childCap } = {}) {
  const budgetMs = opt.tiny ? 2000 : 10000;
  const r = run(process.execPath, [...NODE_FLAGS, CHILD, mode, c.file, String(warm), String(budgetMs)], { timeoutSec: capSec });
  if (r.timedOut) return { timedOut: true, capMs: capSec * 1000 };
  if (r.status !== 0) throw new Error(`${mode} child exited ${r.status} (${r.signal || ''}): ${r.stderr.slice(-600)}`);
  return lastJsonLine(r.stdout);
}

// Idle processes: the baseline of "peak RSS above an idle process".
function idleRss(args) {
  const xs = [];
  for (let i = 0; i < 3; ++i) xs.push(procstat(args).maxRssKiB);
  return median(xs);
}

// ---------------------------------------------------------------------------
// Environment

function gitInfo() {
  const commit = sh('git', ['-C', root, 'rev-parse', 'HEAD']);
  const dirty = sh('git', ['-C', root, 'status', '--porcelain', '--', 'src', 'bindings', 'web/src', 'CMakeLists.txt']);
  return { commit, dirtySources: dirty === null ? null : dirty.length > 0 };
}
function pkgVersion(name) {
  try { return JSON.parse(fs.readFileSync(path.join(root, 'node_modules', name, 'package.json'), 'utf8')).version; } catch { return null; }
}
const cpuModel = (os.cpus()[0] || {}).model || 'unknown';
const env = {
  date: new Date().toISOString(),
  machine: {
    cpu: cpuModel, cores: os.cpus().length, memoryGiB: round(os.totalmem() / 2 ** 30, 1),
    os: `${os.type()} ${os.release()}`, distro: (() => { try { return (fs.readFileSync('/etc/os-release', 'utf8').match(/PRETTY_NAME="([^"]+)"/) || [])[1] || null; } catch { return null; } })(),
    loadAverageAtStart: os.loadavg().map((x) => round(x, 2)),
  },
  versions: {
    node: process.version,
    cxx: (() => { const v = (sh('c++', ['--version']) || '').split('\n')[0]; const m = v.match(/^(\S+).*?(\d+\.\d+\.\d+)/); return m ? `${m[1] === 'c++' ? 'g++' : m[1]} ${m[2]}` : v || null; })(),
    emcc: (() => { const m = (sh('emcc', ['--version']) || '').match(/(\d+\.\d+\.\d+)/); return m ? `emcc ${m[1]}` : null; })(),
    admesh: ((sh(BIN.admesh, ['--version']) || '').match(/[\d.]+/) || [null])[0],
    three: pkgVersion('three'),
    'three-mesh-halfedge': pkgVersion('three-mesh-halfedge'),
    stltopo: JSON.parse(fs.readFileSync(path.join(root, 'package.json'), 'utf8')).version,
  },
  git: gitInfo(),
  wasmBuiltAt: fs.statSync(path.join(root, 'dist/stltopo-wasm.wasm')).mtime.toISOString(),
  options: { sizes: opt.sizes, reps: opt.reps, warm: opt.warm, quick: opt.quick, tiny: opt.tiny, halfedgeCapSec: opt.halfedgeCap, only: opt.only ? String(opt.only) : null, contenders: opt.contenders },
};

// ---------------------------------------------------------------------------
// The run

const t0run = Date.now();
log(`stltopo bench: ${selected.length} cases x ${opt.reps} reps; contenders ${opt.contenders.join(', ')}`);

// Memory first touch. On a VM whose host backs guest memory lazily, the first touch of a
// page the host has not backed costs a host fault and zeroing (seen here: 0.27 GiB/s, ~15 us
// per 4 KiB page, against 10-23 GiB/s for a second pass over the same memory). With free
// page reporting (Firecracker's page_reporting_order=11 here) the guest hands freed 8 MiB
// blocks back to the host within seconds, so this cannot be warmed up for good: every new
// process, and every first call, pays it again for the memory it touches. Whole-process
// and first-call figures include it, in proportion to the memory each contender touches;
// in-process warm figures do not. One child process touches GIB of memory twice and the
// rates are reported (env.memoryFirstTouch), so that a run says what its machine did.
function probeFirstTouch(gib) {
  if (!(gib > 0)) return { gib: 0 };
  const script = `
    const t = [], bufs = [];
    for (let pass = 0; pass < 2; ++pass) {
      const t0 = performance.now();
      for (let i = 0; i < ${Math.round(gib * 4)}; ++i) {
        if (pass === 0) bufs.push(Buffer.allocUnsafeSlow(256 << 20));
        bufs[i].fill(pass + 1);
      }
      t.push(performance.now() - t0);
    }
    console.log(JSON.stringify(t));`;
  const r = spawnSync(process.execPath, ['--max-old-space-size=256', '-e', script], { encoding: 'utf8' });
  if (r.status !== 0) { log(`memory first-touch probe failed: ${(r.stderr || '').slice(-300)}`); return { gib, failed: true }; }
  const [firstMs, againMs] = JSON.parse(r.stdout.trim());
  const out = { gib, firstTouchMs: round(firstMs, 0), secondPassMs: round(againMs, 0), firstTouchGiBps: round(gib / (firstMs / 1e3), 2), secondPassGiBps: round(gib / (againMs / 1e3), 2) };
  log(`memory first touch: ${gib} GiB, ${out.firstTouchGiBps} GiB/s; second pass ${out.secondPassGiBps} GiB/s`);
  return out;
}
{
  const gib = opt.firstTouchGiB ?? (opt.tiny ? 0 : 1);
  env.memoryFirstTouch = probeFirstTouch(Math.max(0, Math.min(gib, Math.floor(os.freemem() / 2 ** 30) - 2)));
}
const idle = {};
if (opt.contenders.includes('native-cli')) idle.cliKiB = idleRss(cliArgs(idleFile));
if (opt.contenders.includes('admesh')) idle.admeshKiB = idleRss(admeshArgs(idleFile));

const results = [];
const cost = {}; // seconds spent per contender, child processes included
for (const c of selected) {
  const contenders = contendersFor(c);
  const samples = Object.fromEntries(contenders.map((k) => [k, []]));
  const dead = new Set();
  for (let rep = 0; rep < opt.reps; ++rep) {
    const order = contenders.map((_, i) => contenders[(i + rep) % contenders.length]);
    for (const k of order) {
      if (dead.has(k)) continue;
      let s;
      const tk = Date.now();
      try {
        s = measure[k](c);
        cost[k] = (cost[k] || 0) + (Date.now() - tk) / 1000;
      } catch (e) {
        errors.push(`${c.id} ${k}: ${e.message}`);
        log(`  ${c.id} ${k}: FAILED ${e.message.split('\n')[0]}`);
        dead.add(k);
        continue;
      }
      samples[k].push(s);
      if (s.timedOut) dead.add(k); // capped: do not spend the cap again
      log(`  [${rep + 1}/${opt.reps}] ${c.id} ${k}: ${describeSample(k, s)}`);
    }
  }
  results.push(summarize(c, samples));
}

// Writing STL: the binary, ordered case of the largest selected size up to 1M (1M in a full
// run), written as binary and ASCII by the native writer (stltopo_stages --write), the wasm
// package (toStl) and three.js's STLExporter (on the STLLoader mesh), REPS times each; the
// medians, in MB/s of output (1 MB = 10^6 bytes).
const writeCase = [...selected].filter((c) => c.format === 'binary' && c.order === 'ordered' && !c.holes)
  .sort((a, b) => SIZES[a.size] - SIZES[b.size]).filter((c) => SIZES[c.size] <= SIZES['1M']).pop();
let writes = null;
if (writeCase) {
  const nat = run(BIN.stages, [writeCase.file, '--write', String(opt.reps)]);
  if (nat.status !== 0) throw new Error(`stltopo_stages --write: ${nat.stderr}`);
  const js = nodeChild('write', writeCase, { warm: opt.reps });
  writes = { case: writeCase.id, triangles: js.triangles, native: lastJsonLine(nat.stdout), wasm: js.wasm, threeExporter: js.threeExporter };
  const d = (w) => `${w.mbPerSecond.toFixed(0)} MB/s (${w.ms.toFixed(0)} ms, ${(w.bytes / 1e6).toFixed(1)} MB)`;
  for (const k of ['native', 'wasm', 'threeExporter']) log(`  write ${writeCase.id} ${k}: binary ${d(writes[k].binary)}, ascii ${d(writes[k].ascii)}`);
}

function describeSample(k, s) {
  if (s.timedOut) return `> ${s.capMs / 1000} s (time cap)`;
  if (k === 'native') return `first ${s.first.totalMs.toFixed(1)} ms, warm ${s.warm ? s.warm.totalMs.toFixed(1) : '-'} ms`;
  if (k === 'native-cli' || k === 'admesh') return `${s.wallMs.toFixed(1)} ms, ${(s.maxRssKiB / 1024).toFixed(1)} MiB`;
  return `first ${s.firstMs.toFixed(1)} ms, warm ${s.warmMs.length ? s.warmMs.map((x) => x.toFixed(1)).join('/') : '-'} ms`;
}

// ---------------------------------------------------------------------------
// Medians, per-triangle figures and ratios

function summarize(c, samples) {
  const bytes = fs.statSync(c.file).size;
  const out = { id: c.id, size: c.size, format: c.format, order: c.order, holes: c.holes, file: rel(c.file), bytes, triangles: null, contenders: {}, checks: {}, ratios: {} };
  const tri = () => out.triangles;
  const perTri = (bytesAbove) => (bytesAbove === null || !tri() ? null : round(bytesAbove / tri(), 1));
  const mps = (ms) => (ms && tri() ? round(tri() / ms / 1000, 3) : null); // million triangles / s
  const ok = (k) => (samples[k] || []).filter((s) => !s.timedOut);
  const med = (xs, f) => median(xs.map(f));

  if (ok('native').length) {
    const s = ok('native');
    out.triangles = s[0].triangles;
    const stages = (key) => {
      const xs = s.map((x) => x[key]).filter(Boolean);
      if (!xs.length) return null;
      return { readMs: round(med(xs, (x) => x.readMs)), topologyMs: round(med(xs, (x) => x.topologyMs)), reportMs: round(med(xs, (x) => x.reportMs)), totalMs: round(med(xs, (x) => x.totalMs)), cpuMs: round(med(xs, (x) => x.cpuMs)) };
    };
    const first = stages('first');
    const warm = stages('warm') || first;
    out.contenders.native = { reps: s.length, first, warm, timeMs: warm.totalMs, mTrianglesPerSecond: mps(warm.totalMs), vertices: s[0].vertices, holes: s[0].holes, boundaryEdges: s[0].boundaryEdges, edges: s[0].edges, shells: s[0].shells };
    const st = s.map((x) => x.streamed).filter(Boolean);
    if (st.length) out.contenders.native.fullTopologyStreamedBytesPerTriangle = perTri(med(st, (x) => (x.peakRssKiB - x.rssBeforeKiB) * 1024));
  }
  for (const k of ['native-cli', 'admesh']) {
    const s = ok(k);
    if (!s.length) continue;
    if (out.triangles === null) out.triangles = s[0].triangles;
    const wall = round(med(s, (x) => x.wallMs));
    const rss = med(s, (x) => x.maxRssKiB);
    const idleKiB = k === 'admesh' ? idle.admeshKiB : idle.cliKiB;
    out.contenders[k] = {
      reps: s.length, timeMs: wall, wallMs: wall, cpuMs: round(med(s, (x) => x.cpuMs)), mTrianglesPerSecond: mps(wall),
      peakRssKiB: rss, idleRssKiB: idleKiB, bytesPerTriangle: perTri((rss - idleKiB) * 1024),
    };
    if (k === 'native-cli') Object.assign(out.contenders[k], { vertices: s[0].vertices, holes: s[0].holes, boundaryEdges: s[0].boundaryEdges });
    else Object.assign(out.contenders[k], { disconnectedEdges: s[0].disconnectedEdges });
  }
  for (const k of ['wasm-read', 'wasm-full', 'wasm-view', 'three', 'three-halfedge']) {
    const all = samples[k] || [];
    if (!all.length) continue;
    const s = ok(k);
    if (!s.length) {
      out.contenders[k] = { reps: 0, timedOut: true, capMs: all[0].capMs, timeMs: null, lowerBoundMs: all[0].capMs };
      continue;
    }
    if (out.triangles === null) out.triangles = s[0].triangles;
    const first = round(med(s, (x) => x.firstMs));
    const warmPer = s.map((x) => median(x.warmMs));
    const warm = round(median(warmPer));
    const r = {
      reps: s.length, initMs: round(med(s, (x) => x.initMs)), firstMs: first, warmMs: warm, timeMs: warm ?? first,
      firstCpuMs: round(med(s, (x) => x.firstCpuMs)), warmCpuMs: round(median(s.map((x) => median(x.warmCpuMs || [])))),
      mTrianglesPerSecond: mps(warm ?? first),
      rssAboveIdleKiB: med(s, (x) => x.rssPeakKiB - x.rssIdleKiB),
      rssBytesPerTriangle: perTri(med(s, (x) => (x.rssPeakKiB - x.rssIdleKiB) * 1024)),
      vertices: s[0].vertices,
    };
    if (all.some((x) => x.timedOut)) r.someTimedOut = true;
    if (k.startsWith('wasm')) {
      r.heapBytes = Math.max(...s.map((x) => x.heapBytes));
      r.heapIdleBytes = s[0].heapIdleBytes;
      r.heapBytesPerTriangle = perTri(r.heapBytes);
      r.holes = s[0].holes;
      if (k === 'wasm-full') r.derivedHalfedgesMs = round(med(s, (x) => x.derivedHalfedgesMs));
    } else {
      const st = (pick) => {
        const xs = s.map(pick).filter(Boolean);
        if (!xs.length) return null;
        const o = {};
        for (const key of Object.keys(xs[0])) o[key] = round(med(xs, (x) => x[key]));
        return o;
      };
      r.firstStages = st((x) => x.firstStages);
      r.warmStages = st((x) => (x.warmStages && x.warmStages.length ? x.warmStages[x.warmStages.length - 1] : null));
      if (k === 'three-halfedge') {
        r.halfedges = s[0].halfedges;
        r.boundaryHalfedges = s[0].boundaryHalfedges;
      }
    }
    out.contenders[k] = r;
  }
  out.samples = samples; // every measurement, as the children reported it
  out.mbytesPerSecondNativeCli = out.contenders['native-cli'] ? round(bytes / 1e3 / out.contenders['native-cli'].wallMs, 1) : null;

  // Cross-checks: every contender saw the same mesh.
  const C = out.contenders;
  const ref = C.native || C['native-cli'];
  if (ref) {
    const agree = (name, a, b) => { if (a !== undefined && a !== null && b !== undefined && b !== null) out.checks[name] = a === b; };
    for (const k of ['native-cli', 'wasm-read', 'wasm-full', 'wasm-view', 'three', 'three-halfedge']) if (C[k]) agree(`${k} vertices`, C[k].vertices, ref.vertices);
    for (const k of ['native-cli', 'wasm-full', 'wasm-view']) if (C[k]) agree(`${k} holes`, C[k].holes, ref.holes);
    if (C.admesh) agree('admesh disconnected edges = boundary edges', C.admesh.disconnectedEdges, ref.boundaryEdges);
    if (C['three-halfedge']) agree('three-mesh-halfedge boundary half-edges = boundary edges', C['three-halfedge'].boundaryHalfedges, ref.boundaryEdges);
    for (const [name, v] of Object.entries(out.checks)) if (!v) errors.push(`${c.id}: check failed: ${name}`);
  }

  // Ratios (speed-ups are "how many times faster"; wasm/native is a slowdown factor).
  const t = (k) => (C[k] ? C[k].timeMs : null);
  const div = (a, b) => (a && b ? round(a / b, 2) : null);
  const R = out.ratios;
  R.wasmFullVsThree = div(t('three'), t('wasm-full'));
  R.wasmFullVsThreeFirstCall = C.three && C['wasm-full'] ? div(C.three.firstMs, C['wasm-full'].firstMs) : null;
  if (C['three-halfedge']) {
    const he = C['three-halfedge'];
    R.wasmFullVsThreeHalfedge = div(he.timeMs ?? he.lowerBoundMs, t('wasm-full'));
    if (he.timeMs === null) R.wasmFullVsThreeHalfedgeIsLowerBound = true;
  }
  R.wasmFullOverNative = C.native ? div(t('wasm-full'), C.native.warm.totalMs) : null;
  R.wasmViewOverNative = C.native ? div(t('wasm-view'), C.native.warm.totalMs) : null;
  R.wasmFullOverNativeCpu = C.native && C['wasm-full'] ? div(C['wasm-full'].warmCpuMs, C.native.warm.cpuMs) : null;
  R.wasmFullOverNativeFirstCall = C.native && C['wasm-full'] ? div(C['wasm-full'].firstMs, C.native.first.totalMs) : null;
  R.wasmReadOverNativeRead = C.native ? div(t('wasm-read'), C.native.warm.readMs) : null;
  R.wasmFirstOverWarm = C['wasm-full'] ? div(C['wasm-full'].firstMs, C['wasm-full'].warmMs) : null;
  R.nativeCliVsAdmesh = div(t('admesh'), t('native-cli'));
  R.nativeCliVsAdmeshCpu = C.admesh && C['native-cli'] ? div(C.admesh.cpuMs, C['native-cli'].cpuMs) : null;
  R.nativeInProcessVsAdmesh = C.native ? div(t('admesh'), C.native.warm.totalMs) : null;
  R.nativeCliBytesPerTriangle = C['native-cli'] ? C['native-cli'].bytesPerTriangle : null;
  R.fullTopologyStreamedBytesPerTriangle = C.native ? C.native.fullTopologyStreamedBytesPerTriangle ?? null : null;
  R.wasmHeapBytesPerTriangle = C['wasm-full'] ? C['wasm-full'].heapBytesPerTriangle : null;
  R.inputBytesPerTriangle = out.triangles ? round(bytes / out.triangles, 1) : null;
  return out;
}

// ---------------------------------------------------------------------------
// Targets (issue 7), evaluated at 1M triangles and up when the run has them, else at the
// largest size it has (then flagged: the targets are stated at 1M).

const sizeRank = (s) => SIZES[s];
function targetSet(filter) {
  const rs = results.filter(filter);
  if (!rs.length) return { rs, atSize: null };
  const big = rs.filter((r) => sizeRank(r.size) >= SIZES['1M']);
  if (big.length) return { rs: big, atSize: '1M+' };
  const maxSize = rs.reduce((m, r) => (sizeRank(r.size) > sizeRank(m) ? r.size : m), rs[0].size);
  return { rs: rs.filter((r) => r.size === maxSize), atSize: maxSize };
}
function target(name, goal, op, filter, value, { exactSize = null, note = null } = {}) {
  const { rs, atSize } = exactSize
    ? (() => { const x = results.filter((r) => filter(r) && r.size === exactSize); return x.length ? { rs: x, atSize: exactSize } : targetSet(filter); })()
    : targetSet(filter);
  const vals = rs.map((r) => ({ case: r.id, value: value(r) })).filter((v) => v.value !== null && v.value !== undefined);
  if (!vals.length) return { name, goal, op, met: null, values: [], atSize, note };
  const worst = op === '>=' ? Math.min(...vals.map((v) => v.value)) : Math.max(...vals.map((v) => v.value));
  const met = op === '>=' ? worst >= goal : worst <= goal;
  return { name, goal, op, met, worst, values: vals, atSize, note };
}
const bin = (r) => r.format === 'binary';
const targets = [
  target('wasm full pipeline vs three.js parse+mergeVertices (x faster)', 20, '>=', bin, (r) => r.ratios.wasmFullVsThree, { exactSize: '1M' }),
  target('wasm full pipeline vs three.js + three-mesh-halfedge (x faster)', 50, '>=', (r) => bin(r) && HALFEDGE_SIZES.includes(r.size), (r) => r.ratios.wasmFullVsThreeHalfedge, { exactSize: '1M' }),
  target('wasm full / native in-process, ordered (slowdown)', 1.2, '<=', (r) => bin(r) && r.order === 'ordered', (r) => r.ratios.wasmFullOverNative),
  target('wasm full / native in-process, shuffled (slowdown)', 1.2, '<=', (r) => bin(r) && r.order === 'shuffled', (r) => r.ratios.wasmFullOverNative),
  target('native whole-process vs admesh -e, ordered (x faster)', 2, '>=', (r) => bin(r) && r.order === 'ordered', (r) => r.ratios.nativeCliVsAdmesh),
  target('native whole-process vs admesh -e, shuffled (x faster)', 5, '>=', (r) => bin(r) && r.order === 'shuffled', (r) => r.ratios.nativeCliVsAdmesh),
  target('ASCII: native whole-process vs admesh -e (x faster)', 3, '>=', (r) => r.format === 'ascii', (r) => r.ratios.nativeCliVsAdmesh),
  target('peak RSS above idle, full topology (prev and face included), streamed, C++ API (bytes/triangle)', 110, '<=', bin, (r) => r.ratios.fullTopologyStreamedBytesPerTriangle),
  target('peak RSS above idle, `stltopo info --json` (report-only topology, input mapped and dropped as read) (bytes/triangle)', 110, '<=', bin, (r) => r.ratios.nativeCliBytesPerTriangle),
];

// ---------------------------------------------------------------------------
// Tables

const f = (x, d = 1) => (x === null || x === undefined ? '–' : Number(x).toFixed(d));
const ms = (x) => (x === null || x === undefined ? '–' : x >= 100 ? x.toFixed(0) : x >= 10 ? x.toFixed(1) : x.toFixed(2));
const mt = (n) => (n >= 1e6 ? `${(n / 1e6).toFixed(n % 1e6 ? 2 : 0)}M` : n >= 1e3 ? `${Math.round(n / 1e3)}k` : String(n));
function table(head, rows) {
  const lines = [`| ${head.join(' | ')} |`, `|${head.map((_, i) => (i === 0 ? ':--' : '--:')).join('|')}|`];
  for (const r of rows) lines.push(`| ${r.join(' | ')} |`);
  return lines.join('\n');
}
const C = (r, k) => r.contenders[k] || null;
const heCell = (r) => {
  const h = C(r, 'three-halfedge');
  if (!h) return 'n/a';
  return h.timeMs === null ? `> ${ms(h.lowerBoundMs)} (cap)` : ms(h.timeMs);
};

const md = [];
md.push(`## stltopo benchmark — ${env.date.slice(0, 10)}`);
md.push('');
md.push(`Machine: ${env.machine.cpu}, ${env.machine.cores} cores, ${env.machine.memoryGiB} GiB, ${env.machine.distro || env.machine.os}; ` +
  `Node ${env.versions.node}, ${env.versions.cxx}, ${env.versions.emcc || 'emcc ?'}, three ${env.versions.three}, ` +
  `three-mesh-halfedge ${env.versions['three-mesh-halfedge']}, admesh ${env.versions.admesh}. ` +
  `Medians of ${opt.reps} alternating repetitions (one child process per measurement, one at a time); in-process "warm" = median of the calls after the first ` +
  `in the same process (${opt.warm}; native at 100k and below: 5; fewer when a call takes over 10 s); whole-process figures at 100k and below: median of 3 back-to-back runs per repetition. ` +
  `Commit ${env.git.commit ? env.git.commit.slice(0, 10) : '?'}${env.git.dirtySources ? ' (+ uncommitted source changes)' : ''}. Load average at start ${env.machine.loadAverageAtStart.join(', ')}.` +
  (env.memoryFirstTouch.gib > 0 && !env.memoryFirstTouch.failed
    ? ` Memory first touch on this machine (${env.memoryFirstTouch.gib} GiB, one process): ${env.memoryFirstTouch.firstTouchGiBps} GiB/s, second pass ${env.memoryFirstTouch.secondPassGiBps} GiB/s; whole-process and first-call figures pay the first-touch rate for the memory they use.`
    : ''));
md.push('');
md.push('### Time (ms; lower is better)');
md.push('');
md.push(table(
  ['case', 'triangles', 'native in-process (warm)', 'native `info --json` (process)', 'wasm topology:false first / warm', 'wasm full first / warm', 'wasm full, view: true (warm)', 'three.js parse+merge', 'three.js + halfedge', '`admesh -e` (process)'],
  results.map((r) => [
    r.id, mt(r.triangles || 0),
    C(r, 'native') ? ms(C(r, 'native').warm.totalMs) : '–',
    C(r, 'native-cli') ? ms(C(r, 'native-cli').wallMs) : '–',
    C(r, 'wasm-read') ? `${ms(C(r, 'wasm-read').firstMs)} / ${ms(C(r, 'wasm-read').warmMs)}` : '–',
    C(r, 'wasm-full') ? `${ms(C(r, 'wasm-full').firstMs)} / ${ms(C(r, 'wasm-full').warmMs)}` : '–',
    C(r, 'wasm-view') ? ms(C(r, 'wasm-view').timeMs) : '–',
    C(r, 'three') ? ms(C(r, 'three').timeMs) : '–',
    heCell(r),
    C(r, 'admesh') ? ms(C(r, 'admesh').wallMs) : '–',
  ]),
));
md.push('');
md.push('### stltopo stages, native in-process (ms, warm; first call in parentheses) and throughput');
md.push('');
md.push(table(
  ['case', 'read (parse + weld)', 'topology (pairing + holes + vertex loops)', 'stats (report)', 'total', 'M tri/s in-process', 'M tri/s wasm full', 'M tri/s process', 'MB/s process', 'wasm full: first read of prev/face/vert in JS'],
  results.filter((r) => C(r, 'native')).map((r) => {
    const n = C(r, 'native');
    return [
      r.id, `${ms(n.warm.readMs)} (${ms(n.first.readMs)})`, `${ms(n.warm.topologyMs)} (${ms(n.first.topologyMs)})`,
      `${ms(n.warm.reportMs)} (${ms(n.first.reportMs)})`, `${ms(n.warm.totalMs)} (${ms(n.first.totalMs)})`,
      f(n.mTrianglesPerSecond, 2), C(r, 'wasm-full') ? f(C(r, 'wasm-full').mTrianglesPerSecond, 2) : '–',
      C(r, 'native-cli') ? f(C(r, 'native-cli').mTrianglesPerSecond, 2) : '–', f(r.mbytesPerSecondNativeCli, 0),
      C(r, 'wasm-full') && C(r, 'wasm-full').derivedHalfedgesMs != null ? ms(C(r, 'wasm-full').derivedHalfedgesMs) : '–',
    ];
  }),
));
md.push('');
md.push('### Peak memory (bytes per triangle above an idle process; input file: ~50 B/triangle binary)');
md.push('');
md.push(table(
  ['case', 'native full topology, streamed (C++ API)', 'native `info --json` RSS', 'wasm full: heap high-water', 'wasm full: Node RSS', 'wasm topology:false: heap', 'three.js RSS', 'three.js + halfedge RSS', 'admesh RSS'],
  results.map((r) => [
    r.id,
    C(r, 'native') && C(r, 'native').fullTopologyStreamedBytesPerTriangle != null ? f(C(r, 'native').fullTopologyStreamedBytesPerTriangle) : '–',
    C(r, 'native-cli') ? f(C(r, 'native-cli').bytesPerTriangle) : '–',
    C(r, 'wasm-full') ? f(C(r, 'wasm-full').heapBytesPerTriangle) : '–',
    C(r, 'wasm-full') ? f(C(r, 'wasm-full').rssBytesPerTriangle) : '–',
    C(r, 'wasm-read') ? f(C(r, 'wasm-read').heapBytesPerTriangle) : '–',
    C(r, 'three') ? f(C(r, 'three').rssBytesPerTriangle) : '–',
    C(r, 'three-halfedge') && C(r, 'three-halfedge').timeMs !== null ? f(C(r, 'three-halfedge').rssBytesPerTriangle) : '–',
    C(r, 'admesh') ? f(C(r, 'admesh').bytesPerTriangle) : '–',
  ]),
));
md.push('');
md.push('Native full topology: `stltopo_stages FILE --streamed-peak`, which reads FILE through a Reader in 1 MiB chunks and builds the ' +
  'full topology (prev and face included) and the report: its peak RSS minus its RSS before the read. `info --json` builds the report-only ' +
  'topology (no prev and face, TopologyOptions::prevAndFace = false), and so do wasm copies (wasm full). ' +
  'Native CLI and admesh: peak RSS (wait4) minus that of the same program on an 18-triangle file. wasm heap: ' +
  'the WebAssembly.Memory buffer size after the first call (linear memory never shrinks, so this is its ' +
  'high-water mark; the package exposes no allocator peak; it includes the initial 16 MiB), divided by the triangles. Node RSS: peak RSS of the ' +
  'child process minus its RSS before reading the file (it holds the whole input and the JS copies of the output).');
md.push('');
if (writes) {
  md.push(`### Writing STL (${writes.case}, ${writes.triangles} triangles; MB/s of output, median of ${opt.reps})`);
  md.push('');
  const w = (x) => `${f(x.mbPerSecond, 0)} MB/s (${f(x.ms, 0)} ms)`;
  md.push(table(['writer', 'binary', 'ASCII'], [
    ['stltopo native (writeStl into a counting sink)', w(writes.native.binary), w(writes.native.ascii)],
    ['stltopo wasm (Node, toStl)', w(writes.wasm.binary), w(writes.wasm.ascii)],
    ['three.js STLExporter.parse', w(writes.threeExporter.binary), w(writes.threeExporter.ascii)],
  ]));
  md.push('');
}
md.push('### Ratios');
md.push('');
md.push(table(
  ['case', 'wasm full vs three.js (x)', 'wasm full vs three+halfedge (x)', 'wasm full / native', '(CPU time)', 'wasm view / native', 'wasm read / native read', 'wasm first / warm', 'native process vs admesh (x, wall)', '(x, CPU time)', 'native in-process vs admesh (x)'],
  results.map((r) => {
    const R = r.ratios;
    return [
      r.id, f(R.wasmFullVsThree), R.wasmFullVsThreeHalfedge === undefined ? 'n/a' : `${R.wasmFullVsThreeHalfedgeIsLowerBound ? '> ' : ''}${f(R.wasmFullVsThreeHalfedge)}`,
      f(R.wasmFullOverNative, 2), f(R.wasmFullOverNativeCpu, 2), f(R.wasmViewOverNative, 2), f(R.wasmReadOverNativeRead, 2), f(R.wasmFirstOverWarm, 2), f(R.nativeCliVsAdmesh, 2), f(R.nativeCliVsAdmeshCpu, 2), f(R.nativeInProcessVsAdmesh, 2),
    ];
  }),
));
md.push('');
md.push('### Targets (issue 7)');
md.push('');
md.push(table(
  ['target', 'goal', 'worst', 'status', 'values'],
  targets.map((t) => [
    t.name, `${t.op} ${t.goal}`, f(t.worst, 2),
    t.met === null ? 'not measured' : `${t.met ? 'met' : 'MISSED'}${t.atSize && t.atSize !== '1M' && t.atSize !== '1M+' ? ` (at ${t.atSize} only)` : ''}`,
    t.values.map((v) => `${v.case} ${f(v.value, 2)}`).join('; '),
  ]),
));
// Edits per CPU second (EditableMesh), native and wasm: the same sequence of edits at each size
// (100k, and 1M unless --quick), so that the rates show whether an edit slows down as the mesh
// grows. Medians of opt.reps alternated runs.
const editSizes = opt.tiny ? ['tiny'] : opt.quick ? ['100k'] : ['100k', '1M'];
const editCount = opt.tiny ? 300 : 5000;
const edits = {};
for (let rep = 0; rep < opt.reps; ++rep) {
  for (const size of editSizes) {
    const file = meshFile(size);
    ensureMesh(file, SIZES[size], []);
    for (const [who, cmd, args] of [['native', BIN.edits, [file, String(editCount), '--json']],
      ['wasm', process.execPath, [path.join(root, 'bench/edits.mjs'), file, String(editCount), '--json']]]) {
      const r = run(cmd, args);
      if (r.status !== 0) {
        errors.push(`edits ${who} ${size}: ${r.stderr.trim().split('\n').pop()}`);
        continue;
      }
      for (const e of lastJsonLine(r.stdout).edits) ((edits[`${who} ${size}`] ??= {})[e.op] ??= []).push(e);
    }
  }
}
const editCols = Object.keys(edits);
if (editCols.length) {
  md.push('');
  md.push(`### Edits per CPU second (EditableMesh; ${editCount} of each kind on random elements; bench/edits.cpp, bench/edits.mjs)`);
  md.push('');
  const ops = Object.keys(edits[editCols[0]]);
  md.push(table(['edit', ...editCols], ops.map((op) => [op, ...editCols.map((k) => {
    const xs = edits[k][op] ?? [];
    return xs.length ? `${Math.round(median(xs.map((e) => e.perCpuSecond)) / 1000)}k` : 'n/a';
  })])));
}
const text = md.join('\n');
console.log(text);

const json = {
  benchmark: 'stltopo issue 7',
  writes,
  environment: { ...env, loadAverageAtEnd: os.loadavg().map((x) => round(x, 2)), durationSec: round((Date.now() - t0run) / 1000, 1) },
  idleRssKiB: idle,
  costSec: Object.fromEntries(Object.entries(cost).map(([k, v]) => [k, round(v, 1)])),
  method: {
    time: 'wall-clock medians over alternating repetitions (one child process per measurement, one at a time)',
    native: 'stltopo_stages: readStl + buildTopology + infoJson on the file bytes in memory; first call and warm calls in the same process',
    nativeCli: 'procstat (fork/exec/wait4) of `stltopo info --json FILE`: wall time from fork to exit; peak RSS minus the idle run; at 100k and below each repetition is the median of 3 runs',
    wasm: 'Node: loadStl(bytes, { topology }) from the package (dist/), arrays copied out (default); first call after instantiation, then warm calls',
    three: 'STLLoader.parse(ArrayBuffer) + deleteAttribute("normal") + BufferGeometryUtils.mergeVertices; + HalfedgeDS.setFromGeometry for three-halfedge',
    admesh: 'procstat of `admesh -e FILE`',
    wasmHeap: 'WebAssembly.Memory buffer byteLength after the first call (high-water mark of linear memory; includes the initial heap)',
  },
  cases: results,
  edits: Object.fromEntries(Object.entries(edits).map(([k, v]) => [k, Object.fromEntries(Object.entries(v).map(([op, xs]) => [op, {
    perCpuSecond: Math.round(median(xs.map((e) => e.perCpuSecond))), attempts: xs[0].attempts, done: xs[0].done }]))])),
  targets,
  errors,
};
if (opt.write) {
  fs.mkdirSync(path.dirname(opt.out), { recursive: true });
  fs.writeFileSync(opt.out + '.tmp', `${JSON.stringify(json, null, 2)}\n`);
  fs.renameSync(opt.out + '.tmp', opt.out);
  if (!opt.tiny && opt.out.endsWith('.json')) fs.writeFileSync(opt.out.replace(/\.json$/, '.md'), `${text}\n`);
  log(`\nwrote ${rel(opt.out)}${!opt.tiny && opt.out.endsWith('.json') ? ` and ${rel(opt.out.replace(/\.json$/, '.md'))}` : ''} (${json.environment.durationSec} s)`);
}
try { fs.unlinkSync(tmpOut); } catch { /* none */ }
if (errors.length) {
  log(`\n${errors.length} error(s):\n  ${errors.join('\n  ')}`);
  process.exit(1);
}
