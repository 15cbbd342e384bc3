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
//   wasm-full-kept, three-kept  wasm-full and three in a Node whose allocator keeps the memory it
//                 frees (contenders.mjs, KEPT_ENV; the 1M binary cases): the copies
//                 without fresh pages
//   three         three.js STLLoader.parse + deleteAttribute('normal') + mergeVertices
//   three-halfedge  the same + three-mesh-halfedge HalfedgeDS.setFromGeometry (binary,
//                 up to 1M triangles, one call per process, killed at --halfedge-cap)
//   admesh        admesh -e FILE, whole process
// Output: markdown tables on stdout (also bench/results/latest.md) and every figure and
// ratio in bench/results/latest.json (--out). Meshes are generated into bench/data/.
//
// The parts: bench-options.mjs (options, paths), bench-util.mjs (log, errors, medians, child
// processes), contenders.mjs (meshes, one measurement per contender), report.mjs (environment,
// medians and ratios, targets, tables, JSON). This file is the driver: the cases, the
// alternating repetitions, the writers, the edits, and the output.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { root, rel, SIZES, ASCII_SIZES, opt, BIN, DATA } from './bench-options.mjs';
import { log, errors, round, run, lastJsonLine, tmpOut } from './bench-util.mjs';
import { meshFile, ensureMesh, contendersFor, cliArgs, admeshArgs, measure, nodeChild, idleRss, describeSample } from './contenders.mjs';
import { collectEnvironment, summarize, evaluateTargets, reportTables, appendEditsTable, resultJson } from './report.mjs';

// ---------------------------------------------------------------------------
// Cases

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

const env = collectEnvironment();

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
  results.push(summarize(c, samples, idle));
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

const targets = evaluateTargets(results);

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

const md = reportTables({ env, results, writes, targets });
appendEditsTable(md, edits, editCount);
const text = md.join('\n');
console.log(text);

const json = resultJson({ writes, env, t0run, idle, cost, results, edits, targets });
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
