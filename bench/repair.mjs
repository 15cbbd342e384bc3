#!/usr/bin/env node
// The repair benchmark (issue 23): the whole default repair of a torus with 8 holes and 1%
// flipped faces, against a plain load of the same file, natively (in-process, with the time
// of each step: bench/repair.cpp) and in wasm (the package in Node: loadStl, then planRepair
// and applyRepair on an EditableMesh, after a repair of the same file that compiles the
// code: see WASM_CHILD). "whole" is plan + EditableMesh init + apply (the
// repair of a loaded mesh), wholeOverLoad its ratio to the load (the figure);
// applyOverLoad is apply alone. Natively, "init" is 0 as in the package, whose
// EditableMesh.from() defers the editor that applyRepair then makes of the plan's result
// (stltopo_repair_bench's default); the CLI's way is under native.cli. Medians; the
// contenders alternate run by run. Each native process repairs 3 times and reports its
// medians (its first load and repair pay for fresh pages, as the wasm child's warm-ups do
// before it measures).
//   node bench/repair.mjs [--sizes 100k,1M] [--reps N] [--out FILE]
// Needs build-bench (scripts/bench.sh builds genmesh and stltopo_repair_bench) and dist/.
import fs from 'node:fs';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const BUILD = path.join(root, process.env.STLTOPO_BENCH_BUILD_DIR || 'build-bench');
const BIN = { genmesh: path.join(BUILD, 'bench/genmesh'), native: path.join(BUILD, 'bench/stltopo_repair_bench') };
const SIZES = { '100k': 100000, '1M': 1000000, '4M': 4000000 };
const opt = { sizes: ['100k', '1M'], reps: 3, out: path.join(root, 'bench/results/repair-latest.json') };
for (let i = 2; i < process.argv.length; ++i) {
  const a = process.argv[i];
  if (a === '--sizes') opt.sizes = process.argv[++i].split(',');
  else if (a === '--reps') opt.reps = Number(process.argv[++i]);
  else if (a === '--out') opt.out = path.resolve(process.argv[++i]);
  else { console.error(`repair.mjs: unknown argument ${a}`); process.exit(2); }
}
const DATA = path.join(root, 'bench/data');
fs.mkdirSync(DATA, { recursive: true });
const median = (v) => [...v].sort((a, b) => a - b)[Math.floor(v.length / 2)];

// One wasm run in a child process (a fresh heap each time): load, plan, apply, in seconds.
const WASM_CHILD = `
import { readFileSync } from 'node:fs';
import { loadStl, planRepair, EditableMesh } from 'stltopo';
const bytes = readFileSync(process.argv[2]);
const intersections = process.argv[3] === '1';
const t = () => performance.now() / 1000;
await loadStl(bytes); // warm: the module's compilation is not the load's
// Nor is it the repair's: a repair of the same file first, as for the load (planRepair's first
// call loads the full module, and V8 runs a function in its baseline code until it has been
// called often enough for the optimized code, and a loop keeps the code it started in: a
// warm-up on a small mesh left the 1M plan at 0.65-1.9 s from run to run, against 0.5-0.53 s
// after a warm-up on the file itself, on the 2-core VM).
{
  const warm = await loadStl(bytes);
  const p = await planRepair(warm, { intersections });
  const e = await EditableMesh.from(warm);
  e.applyRepair(p);
  e.dispose();
}
// After it, loadStl runs in the full module (the repair's): warm the load there too.
await loadStl(bytes);
let t0 = t();
const mesh = await loadStl(bytes);
const load = t() - t0;
t0 = t();
const plan = await planRepair(mesh, { intersections });
const planS = t() - t0;
t0 = t();
const em = await EditableMesh.from(mesh);
const init = t() - t0;
t0 = t();
const log = em.applyRepair(plan);
const apply = t() - t0;
console.log(JSON.stringify({ load, plan: planS, init, apply, whole: planS + init + apply, holesAfter: log.after.holes, inconsistentAfter: log.after.inconsistentEdges }));
em.dispose();
`;
const childFile = path.join(root, 'bench/.repair-child.mjs');
fs.writeFileSync(childFile, WASM_CHILD);

function run(cmd, args) {
  const r = spawnSync(cmd, args, { encoding: 'utf8', cwd: root, maxBuffer: 1 << 26 });
  if (r.status !== 0) throw new Error(`${cmd} ${args.join(' ')}: ${r.stderr}`);
  return JSON.parse(r.stdout.trim().split('\n').pop());
}

const results = { date: new Date().toISOString(), reps: opt.reps, cases: [] };
try {
  for (const size of opt.sizes) {
    const n = SIZES[size];
    const file = path.join(DATA, `torus-${size}-holes8-flip1.stl`);
    if (!fs.existsSync(file)) spawnSync(BIN.genmesh, [String(n), file, '--hole-count', '8', '--flip-percent', '1'], { stdio: 'ignore' });
    for (const intersections of [false, true]) {
      const native = [], wasm = [], native2 = [], nativeCli = [];
      const flags = intersections ? [] : ['--no-intersections'];
      for (let r = 0; r < opt.reps; ++r) {
        native.push(run(BIN.native, [file, '--reps', '3', ...flags]));
        nativeCli.push(run(BIN.native, [file, '--reps', '3', '--cli', ...flags]));
        wasm.push(run(process.execPath, [childFile, file, intersections ? '1' : '0']));
        // RepairOptions::threads = 2 (the load and init on 2 threads too), alternated with the rest.
        native2.push(run(BIN.native, [file, '--reps', '3', '--threads', '2', ...flags]));
      }
      const steps = {}, planSteps = {};
      for (const k of Object.keys(native[0].steps)) steps[k] = median(native.map((x) => x.steps[k]));
      for (const k of Object.keys(native[0].planSteps)) planSteps[k] = median(native.map((x) => x.planSteps[k]));
      const med = (runs, k) => median(runs.map((x) => x[k]));
      const c = {
        size, triangles: native[0].triangles, intersections,
        native: { load: med(native, 'load'), plan: med(native, 'plan'), init: med(native, 'init'),
          apply: med(native, 'apply'), whole: med(native, 'whole'), steps, planSteps },
        wasm: { load: med(wasm, 'load'), plan: med(wasm, 'plan'), init: med(wasm, 'init'), apply: med(wasm, 'apply'),
          whole: med(wasm, 'whole') },
        native2Threads: { load: med(native2, 'load'), plan: med(native2, 'plan'), init: med(native2, 'init'),
          apply: med(native2, 'apply'), whole: med(native2, 'whole') },
        holesBefore: native[0].holesBefore, holesAfter: native[0].holesAfter, inconsistentAfter: native[0].inconsistentAfter,
      };
      c.native.applyOverLoad = c.native.apply / c.native.load;
      c.wasm.applyOverLoad = c.wasm.apply / c.wasm.load;
      c.native.wholeOverLoad = c.native.whole / c.native.load;
      // A C++ caller that reads the file and repairs it into an EditableMesh builds no topology
      // but the plan's (as the CLI): its repair beyond a plain load.
      c.native.read = med(native, 'read');
      c.native.wholeAfterRead = median(native.map((x) => x.whole - (x.load - x.read)));
      c.native.wholeAfterReadOverLoad = c.native.wholeAfterRead / c.native.load;
      // The CLI's way: plan, then applyRepair(mesh, plan, out, log) into the Mesh it writes,
      // which takes the plan's result without an EditableMesh (bench/repair.cpp, --cli). The
      // CLI builds no topology but the plan's: its "whole" is read + plan + apply - load
      // (bench/repair.cpp), its repair beyond a plain load; "total" is read + plan + apply,
      // from the file's bytes to the repaired mesh (a load and the repair).
      c.native.cli = { read: med(nativeCli, 'read'), plan: med(nativeCli, 'plan'), apply: med(nativeCli, 'apply'),
        whole: med(nativeCli, 'whole'), load: med(nativeCli, 'load') };
      c.native.cli.total = median(nativeCli.map((x) => x.read + x.plan + x.apply));
      c.native.cli.wholeOverLoad = c.native.cli.whole / c.native.cli.load;
      c.native.cli.totalOverLoad = c.native.cli.total / c.native.cli.load;
      c.wasm.wholeOverLoad = c.wasm.whole / c.wasm.load;
      c.native2Threads.wholeOverLoad = c.native2Threads.whole / c.native2Threads.load;
      // Against the one-thread load: what a user gains by asking for threads.
      c.native2Threads.wholeOverOneThreadLoad = c.native2Threads.whole / c.native.load;
      c.native2Threads.speedup = c.native.whole / c.native2Threads.whole;
      results.cases.push(c);
      const f = (x) => x.toFixed(3);
      const x = (v) => `${v.toFixed(1)}x`;
      console.log(`repair ${size}${intersections ? ' (with the intersection pass)' : ''}: native load ${f(c.native.load)} s, plan ${f(c.native.plan)} s, `
        + `init ${f(c.native.init)} s, apply ${f(c.native.apply)} s, whole ${f(c.native.whole)} s (${x(c.native.wholeOverLoad)} load; apply alone `
        + `${x(c.native.applyOverLoad)}; from a read mesh ${x(c.native.wholeAfterReadOverLoad)} load; the CLI's way ${f(c.native.cli.whole)} s beyond its load, ${x(c.native.cli.wholeOverLoad)} load, and from the bytes ${x(c.native.cli.totalOverLoad)} load); wasm load ${f(c.wasm.load)} s, plan ${f(c.wasm.plan)} s, init ${f(c.wasm.init)} s, `
        + `apply ${f(c.wasm.apply)} s, whole ${f(c.wasm.whole)} s (${x(c.wasm.wholeOverLoad)} load; apply alone ${x(c.wasm.applyOverLoad)}); `
        + 'native steps in apply: ' + Object.entries(steps).map(([k, v]) => `${k} ${f(v)}`).join(', ')
        + '; in plan: ' + Object.entries(planSteps).map(([k, v]) => `${k} ${f(v)}`).join(', ')
        + `; native on 2 threads: whole ${f(c.native2Threads.whole)} s (${x(c.native2Threads.wholeOverOneThreadLoad)} a one-thread load, `
        + `${c.native2Threads.speedup.toFixed(2)}x faster than one thread)`);
    }
  }
} finally {
  fs.rmSync(childFile, { force: true });
}
fs.mkdirSync(path.dirname(opt.out), { recursive: true });
fs.writeFileSync(opt.out, `${JSON.stringify(results, null, 2)}\n`);
