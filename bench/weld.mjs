#!/usr/bin/env node
// The tolerance weld against the exact weld (issue 24, target: within 2x at 1M triangles):
// `stltopo_stages FILE --weld D REPS` on the 1M tori (grid order and shuffled), the read
// (the exact weld), the topology with the exact weld and with the tolerance weld
// interleaved in one process; the tolerance weld costs the difference of the two
// topologies. Writes bench/results/weld-latest.json (--out FILE elsewhere).
//   node bench/weld.mjs [--sizes 100k,1M] [--tolerance D] [--reps N] [--out FILE]
import fs from 'node:fs';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const BUILD = path.join(root, process.env.STLTOPO_BENCH_BUILD_DIR || 'build-bench');
const BIN = { stages: path.join(BUILD, 'bench/stltopo_stages'), genmesh: path.join(BUILD, 'bench/genmesh') };
const SIZES = { '100k': 100000, '1M': 1000000, '4M': 4000000 };
const opt = { sizes: ['1M'], tolerance: 0.001, reps: 7, out: path.join(root, 'bench/results/weld-latest.json') };
for (let i = 2; i < process.argv.length; ++i) {
  const a = process.argv[i];
  if (a === '--sizes') opt.sizes = process.argv[++i].split(',');
  else if (a === '--tolerance') opt.tolerance = Number(process.argv[++i]);
  else if (a === '--reps') opt.reps = Number(process.argv[++i]);
  else if (a === '--out') opt.out = path.resolve(process.argv[++i]);
  else { console.error(`weld.mjs: unknown argument ${a}`); process.exit(2); }
}

const results = [];
for (const size of opt.sizes) {
  for (const shuffle of [false, true]) {
    const file = path.join(root, 'bench/data', `torus-${size}${shuffle ? '-shuffled' : ''}.stl`);
    if (!fs.existsSync(file)) {
      fs.mkdirSync(path.dirname(file), { recursive: true });
      const g = spawnSync(BIN.genmesh, [String(SIZES[size]), `${file}.part`, ...(shuffle ? ['--shuffle'] : [])], { encoding: 'utf8' });
      if (g.status !== 0) throw new Error(`genmesh: ${g.stderr}`);
      fs.renameSync(`${file}.part`, file);
    }
    const r = spawnSync(BIN.stages, [file, '--weld', String(opt.tolerance), String(opt.reps)], { encoding: 'utf8' });
    if (r.status !== 0) throw new Error(`stltopo_stages --weld: ${r.stderr}`);
    results.push({ size, order: shuffle ? 'shuffled' : 'grid', ...JSON.parse(r.stdout) });
  }
}
const f = (x) => x.toFixed(1);
console.log(`\nThe tolerance weld (D = ${opt.tolerance}) against the exact weld, in-process medians of ${opt.reps}, ms:\n`);
console.log('| mesh | exact weld (read) | topology, exact | topology, tolerance | tolerance weld | tolerance / exact weld (target <= 2) |');
console.log('|:--|--:|--:|--:|--:|--:|');
for (const r of results) {
  console.log(`| ${r.size} ${r.order} | ${f(r.readMs)} | ${f(r.topologyMs)} | ${f(r.topologyToleranceMs)} | ${f(r.toleranceWeldMs)} | ${r.toleranceWeldOverExactWeld.toFixed(2)} |`);
}
fs.mkdirSync(path.dirname(opt.out), { recursive: true });
fs.writeFileSync(opt.out, `${JSON.stringify({ date: new Date().toISOString(), results }, null, 1)}\n`);
