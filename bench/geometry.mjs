#!/usr/bin/env node
// The exact-geometry benchmark (issue 21): what `info --intersections` costs over plain
// `info`, natively and in wasm (the npm CLI), against CGAL's own self_intersections on the
// same meshes, and the extra peak memory per triangle. Whole processes, one at a time, the
// repetitions alternating between the contenders; medians.
//   node bench/geometry.mjs [--sizes 100k,1M] [--reps N] [--out FILE]
// Needs build-bench (scripts/bench.sh builds it: procstat, genmesh, stltopo_cli and, with
// CGAL, stltopo_cgal_pmp) and dist/ (the npm CLI).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const BUILD = path.join(root, process.env.STLTOPO_BENCH_BUILD_DIR || 'build-bench');
const BIN = {
  cli: path.join(BUILD, 'stltopo'),
  procstat: path.join(BUILD, 'bench/procstat'),
  genmesh: path.join(BUILD, 'bench/genmesh'),
  stages: path.join(BUILD, 'bench/stltopo_stages'),
  // The same harness compiled to wasm (bindings/CMakeLists.txt, stltopo_stages_wasm; scripts/bench.sh
  // builds it): the pass in process in wasm, against stltopo_stages natively.
  stagesWasm: path.join(root, process.env.STLTOPO_WASM_BUILD_DIR || 'build-wasm', 'bindings/stltopo-stages.cjs'),
  // bench/CMakeLists.txt builds it into bench/judge, unless the tests (STLTOPO_BUILD_TESTS)
  // defined the target first, in tests/judge.
  cgal: ['bench/judge', 'tests/judge'].map((d) => path.join(BUILD, d, 'stltopo_cgal_pmp')).find((f) => fs.existsSync(f))
    || path.join(BUILD, 'bench/judge/stltopo_cgal_pmp'),
};
const SIZES = { '100k': 100000, '1M': 1000000, '4M': 4000000 };
const opt = { sizes: ['100k', '1M'], reps: 3, out: path.join(root, 'bench/results/geometry-latest.json') };
for (let i = 2; i < process.argv.length; ++i) {
  const a = process.argv[i];
  if (a === '--sizes') opt.sizes = process.argv[++i].split(',');
  else if (a === '--reps') opt.reps = Number(process.argv[++i]);
  else if (a === '--out') opt.out = path.resolve(process.argv[++i]);
  else { console.error(`geometry.mjs: unknown argument ${a}`); process.exit(2); }
}
const DATA = path.join(root, 'bench/data');
fs.mkdirSync(DATA, { recursive: true });

function procstat(args) {
  const out = path.join(DATA, '.geometry-stdout');
  const r = spawnSync(BIN.procstat, ['--stdout', out, '--timeout', '600', '--', ...args], { encoding: 'utf8' });
  if (r.status !== 0) throw new Error(`procstat: ${r.stderr}`);
  const p = JSON.parse(r.stdout.trim());
  p.stdout = fs.readFileSync(out, 'utf8');
  return p;
}
const median = (xs) => { const s = [...xs].sort((a, b) => a - b); return s.length ? s[(s.length - 1) >> 1] : null; };

const cases = [];
for (const size of opt.sizes) {
  for (const shuffle of [false, true]) {
    const file = path.join(DATA, `torus-${size}${shuffle ? '-shuffled' : ''}.stl`);
    if (!fs.existsSync(file)) spawnSync(BIN.genmesh, [String(SIZES[size]), file, ...(shuffle ? ['--shuffle'] : [])]);
    cases.push({ id: `torus ${size}${shuffle ? ' shuffled' : ''}`, file, triangles: SIZES[size] });
  }
}
const haveCgal = fs.existsSync(BIN.cgal);
const node = process.execPath;
const CORES = os.availableParallelism ? os.availableParallelism() : os.cpus().length;
const npmCli = path.join(root, 'bin/stltopo.mjs');
const contenders = {
  info: (f) => [BIN.cli, 'info', '--json', '--threads', '1', f],
  intersections: (f) => [BIN.cli, 'info', '--json', '--intersections', '--threads', '1', f],
  // The same on the machine's cores (--threads 0): the read, the topology, the report's
  // checks and the intersection pass split (README, Threads).
  ...(CORES > 1 ? {
    'info threads': (f) => [BIN.cli, 'info', '--json', '--threads', '0', f],
    'intersections threads': (f) => [BIN.cli, 'info', '--json', '--intersections', '--threads', '0', f],
  } : {}),
  'npm info': (f) => [node, npmCli, 'info', '--json', f],
  'npm intersections': (f) => [node, npmCli, 'info', '--json', '--intersections', f],
  // With --shells on both sides, the npm CLI runs the full module for both (plain info runs the
  // core module, whose topology is not chunked: bench/PROFILE.md, *Chunked loops*), so their
  // difference is the pass itself (the hierarchy, the certificates, the join, the nesting).
  shells: (f) => [BIN.cli, 'info', '--json', '--shells', '--threads', '1', f],
  'intersections shells': (f) => [BIN.cli, 'info', '--json', '--shells', '--intersections', '--threads', '1', f],
  'npm shells': (f) => [node, npmCli, 'info', '--json', '--shells', f],
  'npm intersections shells': (f) => [node, npmCli, 'info', '--json', '--shells', '--intersections', f],
  // CGAL's search three times in its process: the first call, and the median of the other two
  // (warmSeconds), to set against stltopo's first and warm calls alike.
  ...(haveCgal ? { cgal: (f) => [BIN.cgal, f, '--reps', '3'] } : {}),
};
const results = [];
for (const c of cases) {
  const runs = Object.fromEntries(Object.keys(contenders).map((k) => [k, []]));
  for (let rep = 0; rep < opt.reps; ++rep) {
    for (const [k, args] of Object.entries(contenders)) {
      const p = procstat(args(c.file));
      const row = { wallMs: p.wallMs, maxRssKiB: p.maxRssKiB };
      if (k === 'cgal') {
        const head = JSON.parse(p.stdout.split('\n')[0]);
        row.searchMs = head.seconds * 1000;
        row.warmSearchMs = head.warmSeconds !== undefined ? head.warmSeconds * 1000 : null;
        row.pairs = head.pairs;
      } else if (k.includes('intersections')) {
        row.pairs = JSON.parse(p.stdout).selfIntersections;
      }
      runs[k].push(row);
    }
  }
  const m = (k, f = 'wallMs') => median(runs[k]?.map((r) => r[f]) ?? []);
  // What a pass costs as whole processes: the median over the repetitions of (with - without),
  // the two run one after the other in each repetition, so that a drift of the machine between
  // repetitions cancels (a difference of the two medians went below zero on this VM). When the
  // median difference is not above zero the processes' noise hides the pass: null (the tables
  // print "–"), and the pair is listed in noisyDifferences.
  const noisy = [];
  const diff = (withPass, without) => {
    const d = median(runs[withPass].map((r, i) => r.wallMs - runs[without][i].wallMs));
    if (d > 0) return d;
    noisy.push(`${withPass} - ${without}`);
    return null;
  };
  const ratio = (a, b) => (a && b ? a / b : null);
  const passNative = diff('intersections', 'info');
  const passWasm = diff('npm intersections', 'npm info');
  const passOverShellsNative = diff('intersections shells', 'shells');
  const passOverShellsWasm = diff('npm intersections shells', 'npm shells');
  const threaded = CORES > 1;
  const passThreads = threaded ? diff('intersections threads', 'info threads') : null;
  // The pass alone in process, as CGAL's figure is its search alone: stltopo_stages times
  // findIntersections on one thread (median of opt.reps after a warm-up; CGAL's is one call).
  // The wasm build of the same harness alternates with it (3 runs each, or opt.reps when more;
  // the median of their medians): the wasm/native figure of the pass with nothing else around it.
  const stageArgs = [c.file, '--intersections', '1', String(Math.max(3, opt.reps))];
  const harnesses = {  // [program, its arguments], when it is built
    native: fs.existsSync(BIN.stages) ? [BIN.stages, stageArgs] : null,
    wasm: fs.existsSync(BIN.stagesWasm) ? [process.execPath, ['--no-experimental-fetch', BIN.stagesWasm, ...stageArgs]] : null,
  };
  const inProcess = { native: [], wasm: [] };
  const firstCalls = [];  // native: each process's first call, which pays fresh pages as CGAL's one call does
  for (let rep = 0; rep < Math.max(3, opt.reps); ++rep) {
    for (const [k, h] of Object.entries(harnesses)) {
      if (!h) continue;
      const st = spawnSync(h[0], h[1], { encoding: 'utf8' });
      if (st.status !== 0) continue;
      const out = JSON.parse(st.stdout.trim().split('\n').pop());
      inProcess[k].push(out.passOneThreadMs);
      if (k === 'native' && out.passFirstMs) firstCalls.push(out.passFirstMs);
    }
  }
  const passInProcess = median(inProcess.native), passInProcessWasm = median(inProcess.wasm);
  const passFirst = median(firstCalls);
  const r = {
    case: c.id, triangles: c.triangles,
    infoMs: m('info'), intersectionsMs: m('intersections'), ratioToInfo: m('intersections') / m('info'),
    passNativeMs: passNative, passWasmMs: passWasm, wasmToNative: ratio(passWasm, passNative),
    passOverShellsNativeMs: passOverShellsNative, passOverShellsWasmMs: passOverShellsWasm,
    wasmToNativeOverShells: ratio(passOverShellsWasm, passOverShellsNative),
    noisyDifferences: noisy,
    extraBytesPerTriangle: ((m('intersections', 'maxRssKiB') - m('info', 'maxRssKiB')) * 1024) / c.triangles,
    pairs: runs.intersections[0].pairs,
    cgalSearchMs: haveCgal ? m('cgal', 'searchMs') : null, cgalWallMs: haveCgal ? m('cgal') : null,
    cgalPairs: haveCgal ? runs.cgal[0].pairs : null,
    cgalToStltopoPass: haveCgal ? ratio(m('cgal', 'searchMs'), passNative) : null,
    passInProcessMs: passInProcess,
    passInProcessWasmMs: passInProcessWasm,
    wasmToNativeInProcess: ratio(passInProcessWasm, passInProcess),
    cgalWarmSearchMs: haveCgal ? m('cgal', 'warmSearchMs') : null,
    // warm against warm (both in process, after a first call), and first call against first call
    cgalToStltopoPassInProcess: haveCgal && passInProcess ? m('cgal', 'warmSearchMs') / passInProcess : null,
    passFirstCallMs: passFirst,
    cgalToStltopoPassFirstCall: haveCgal && passFirst ? m('cgal', 'searchMs') / passFirst : null,
    threads: threaded ? CORES : null,
    infoThreadsMs: threaded ? m('info threads') : null,
    intersectionsThreadsMs: threaded ? m('intersections threads') : null,
    // info --intersections on the cores against plain info on one thread and on the cores.
    ratioThreadsToInfo: threaded ? m('intersections threads') / m('info') : null,
    ratioThreadsToInfoThreads: threaded ? m('intersections threads') / m('info threads') : null,
    passThreadsMs: passThreads,
    cgalToStltopoPassThreads: haveCgal && threaded ? ratio(m('cgal', 'searchMs'), passThreads) : null,
  };
  results.push(r);
  console.error(JSON.stringify(r));
}
fs.mkdirSync(path.dirname(opt.out), { recursive: true });
fs.writeFileSync(opt.out, JSON.stringify({ date: new Date().toISOString(), reps: opt.reps, results }, null, 1));
const f1 = (x) => (x === null || Number.isNaN(x) ? '–' : x.toFixed(1));
const f2 = (x) => (x === null || Number.isNaN(x) ? '–' : x.toFixed(2));
console.log('| case | info ms | info --intersections ms | ratio | pass native ms | pass wasm ms | wasm/native | extra B/tri | CGAL search ms | CGAL/stltopo pass | pass in process ms | CGAL/pass in process (warm) | first call ms | CGAL/first call (first calls) |');
console.log('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|');
const table2 = [];
for (const r of results) {
  console.log(`| ${r.case} | ${f1(r.infoMs)} | ${f1(r.intersectionsMs)} | ${f2(r.ratioToInfo)} | ${f1(r.passNativeMs)} | ${f1(r.passWasmMs)} | ` +
    `${f2(r.wasmToNative)} | ${f1(r.extraBytesPerTriangle)} | ${f1(r.cgalSearchMs)} | ${f2(r.cgalToStltopoPass)} | ` +
    `${f1(r.passInProcessMs)} | ${f2(r.cgalToStltopoPassInProcess)} | ${f1(r.passFirstCallMs)} | ${f2(r.cgalToStltopoPassFirstCall)} |`);
  if (r.threads) {
    table2.push(`| ${r.case} | ${r.threads} | ${f1(r.infoThreadsMs)} | ${f1(r.intersectionsThreadsMs)} | ${f2(r.ratioThreadsToInfo)} | ` +
      `${f2(r.ratioThreadsToInfoThreads)} | ${f1(r.passThreadsMs)} | ${f2(r.cgalToStltopoPassThreads)} |`);
  }
}
console.log('\n| case | pass in process, native ms | wasm ms | wasm/native |');
console.log('|---|---|---|---|');
for (const r of results) {
  console.log(`| ${r.case} | ${f1(r.passInProcessMs)} | ${f1(r.passInProcessWasmMs)} | ${f2(r.wasmToNativeInProcess)} |`);
}
console.log('\n| case | pass over --shells, native ms | wasm ms | wasm/native |');
console.log('|---|---|---|---|');
for (const r of results) {
  console.log(`| ${r.case} | ${f1(r.passOverShellsNativeMs)} | ${f1(r.passOverShellsWasmMs)} | ${f2(r.wasmToNativeOverShells)} |`);
}
if (table2.length) {
  console.log('\n| case | threads | info ms | info --intersections ms | / info (1 thread) | / info (same threads) | pass ms | CGAL/stltopo pass |');
  console.log('|---|---|---|---|---|---|---|---|');
  for (const row of table2) console.log(row);
}
const hidden = results.filter((r) => r.noisyDifferences.length);
if (hidden.length) {
  console.log('\nNot above the noise (the median difference of the pair was not above zero; "–" above):');
  for (const r of hidden) console.log(`- ${r.case}: ${r.noisyDifferences.join('; ')}`);
}
