// The contenders: the generated meshes they read, and one measurement of each (a child
// process per measurement; bench/child.mjs for the Node ones).
import fs from 'node:fs';
import path from 'node:path';
import { root, rel, SIZES, HALFEDGE_SIZES, KEPT_CONTENDERS, opt, BIN, DATA, CHILD, NODE_FLAGS } from './bench-options.mjs';
import { log, median, run, lastJsonLine, procstat } from './bench-util.mjs';

// ---------------------------------------------------------------------------
// Meshes

export function meshFile(size, { shuffle = false, holes = false, ascii = false } = {}) {
  const name = `torus-${size}${ascii ? '-ascii' : ''}${shuffle ? '-shuffled' : ''}${holes ? '-holes' : ''}.stl`;
  return path.join(DATA, name);
}

export function ensureMesh(file, triangles, flags) {
  const src = path.join(root, 'bench/genmesh.cpp');
  if (fs.existsSync(file) && fs.statSync(file).mtimeMs >= fs.statSync(src).mtimeMs) return;
  log(`generating ${rel(file)}`);
  const r = run(BIN.genmesh, [String(triangles), file + '.part', ...flags]);
  if (r.status !== 0) throw new Error(`genmesh failed: ${r.stderr}`);
  fs.renameSync(file + '.part', file);
}

export function contendersFor(c) {
  return opt.contenders.filter((k) => (k !== 'three-halfedge' || (c.format === 'binary' && HALFEDGE_SIZES.includes(c.size))) &&
    (!KEPT_CONTENDERS.includes(k) || (c.format === 'binary' && (c.size === '1M' || c.size === 'tiny'))));
}

// The environment of the "-kept" contenders: glibc's malloc serves every block from its heap
// (no mmap) and never returns freed memory to the kernel, so that the arrays of one call reuse
// the pages of the call before instead of faulting in fresh ones. The native CLI does the same
// for itself with mallopt (tools/cli.cpp); Node cannot, so a Node user sets these tunables.
// On these VMs fresh memory costs a host fault a 4 kB page (bench/PROFILE.md, *Stop 55*).
export const KEPT_ENV = { GLIBC_TUNABLES: 'glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=4294967295' };

// ---------------------------------------------------------------------------
// One measurement per contender

// The CLI with `--threads N` (1: one thread; 0: the machine's cores, the CLI's default since
// stop 41; null: no flag, the default).
export const cliArgs = (file, threads = null) => [BIN.cli, 'info', '--json', ...(threads !== null ? ['--threads', String(threads)] : []), file];
export const admeshArgs = (file) => [BIN.admesh, '-e', file];

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

export const measure = {
  native(c) {
    const r = run(BIN.stages, [c.file, String(1 + (small(c) ? Math.max(opt.warm, 5) : opt.warm)), '--json', '--threads', '1']);
    if (r.status !== 0) throw new Error(`stltopo_stages: ${r.stderr}`);
    // The full topology (prev and face included) with the input streamed in 1 MiB chunks,
    // in a process of its own: its peak RSS above the RSS before the read.
    const p = run(BIN.stages, [c.file, '--streamed-peak']);
    if (p.status !== 0) throw new Error(`stltopo_stages --streamed-peak: ${p.stderr}`);
    return { ...lastJsonLine(r.stdout), streamed: lastJsonLine(p.stdout) };
  },
  'native-cli'(c) {
    const p = procstatMedian(c, cliArgs(c.file, 1));  // one thread, as the figures before stop 41
    if (p.status !== 0) throw new Error(`stltopo info exited ${p.status} (signal ${p.signal})`);
    const j = lastJsonLine(p.stdout);
    // The same on every core, --threads 0 (issue 24: the threads' speed-up over one thread).
    const all = procstatMedian(c, cliArgs(c.file, 0));
    if (all.status !== 0) throw new Error(`stltopo info --threads 0 exited ${all.status} (signal ${all.signal})`);
    return { wallMs: p.wallMs, cpuMs: p.userMs + p.sysMs, maxRssKiB: p.maxRssKiB, triangles: j.triangles, vertices: j.vertices, holes: j.holes, boundaryEdges: j.boundaryEdges,
      allThreads: { wallMs: all.wallMs, cpuMs: all.userMs + all.sysMs } };
  },
  admesh(c) {
    const p = procstatMedian(c, admeshArgs(c.file));
    if (p.status !== 0) throw new Error(`admesh exited ${p.status} (signal ${p.signal})`);
    return { wallMs: p.wallMs, cpuMs: p.userMs + p.sysMs, maxRssKiB: p.maxRssKiB, ...parseAdmesh(p.stdout) };
  },
  'wasm-read': (c) => nodeChild('wasm-read', c),
  'wasm-full': (c) => nodeChild('wasm-full', c),
  'wasm-view': (c) => nodeChild('wasm-view', c),
  // (a budget of 20 s for its warm calls: the first of them may still find the first call's
  // pages in use, as V8 frees an ArrayBuffer's memory a while after the collection that found
  // it dead)
  'wasm-full-kept': (c) => nodeChild('wasm-full', c, { env: KEPT_ENV, budgetMs: 20000 }),
  three: (c) => nodeChild('three', c, { warm: opt.quick ? 1 : opt.warm }),
  'three-kept': (c) => nodeChild('three', c, { warm: opt.warm, env: KEPT_ENV }),
  'three-halfedge': (c) => nodeChild('three-halfedge', c, { warm: 0, capSec: opt.halfedgeCap }),
};

export function nodeChild(mode, c, { warm = opt.warm, capSec = opt.childCap, env, budgetMs = 10000 } = {}) {
  if (opt.tiny) budgetMs = 2000;
  const r = run(process.execPath, [...NODE_FLAGS, CHILD, mode, c.file, String(warm), String(budgetMs)], { timeoutSec: capSec, env });
  if (r.timedOut) return { timedOut: true, capMs: capSec * 1000 };
  if (r.status !== 0) throw new Error(`${mode} child exited ${r.status} (${r.signal || ''}): ${r.stderr.slice(-600)}`);
  return lastJsonLine(r.stdout);
}

// Idle processes: the baseline of "peak RSS above an idle process".
export function idleRss(args) {
  const xs = [];
  for (let i = 0; i < 3; ++i) xs.push(procstat(args).maxRssKiB);
  return median(xs);
}

export function describeSample(k, s) {
  if (s.timedOut) return `> ${s.capMs / 1000} s (time cap)`;
  if (k === 'native') return `first ${s.first.totalMs.toFixed(1)} ms, warm ${s.warm ? s.warm.totalMs.toFixed(1) : '-'} ms`;
  if (k === 'native-cli') return `${s.wallMs.toFixed(1)} ms, ${(s.maxRssKiB / 1024).toFixed(1)} MiB; --threads 0: ${s.allThreads.wallMs.toFixed(1)} ms`;
  if (k === 'admesh') return `${s.wallMs.toFixed(1)} ms, ${(s.maxRssKiB / 1024).toFixed(1)} MiB`;
  return `first ${s.firstMs.toFixed(1)} ms, warm ${s.warmMs.length ? s.warmMs.map((x) => x.toFixed(1)).join('/') : '-'} ms`;
}
