// The benchmark's options (bench/run.mjs --help), the paths of what it runs, and the checks
// that they exist (a missing build stops the run before anything is measured).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
export const rel = (p) => path.relative(root, p);

// ---------------------------------------------------------------------------
// Options

export const SIZES = { tiny: 3000, '100k': 100000, '1M': 1000000, '4M': 4000000 };
export const ASCII_SIZES = ['tiny', '100k', '1M'];
export const HALFEDGE_SIZES = ['tiny', '100k', '1M'];
export const ALL_CONTENDERS = ['native', 'native-cli', 'wasm-read', 'wasm-full', 'wasm-view', 'wasm-full-kept', 'three', 'three-kept', 'three-halfedge', 'admesh'];
// The "-kept" contenders run in a Node whose allocator keeps the memory it frees
// (contenders.mjs, KEPT_ENV); they are measured on the 1M binary cases only (and the tiny
// ones, for the smoke run of `npm test`).
export const KEPT_CONTENDERS = ['wasm-full-kept', 'three-kept'];

function usage(code) {
  (code ? console.error : console.log)(`usage: node bench/run.mjs [options]
  --quick              the 100k cases only, without wasm-view and the -kept contenders, one warm three.js
                       call (under a minute)
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

export const opt = {
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
  // --quick leaves out wasm-view and the -kept contenders (not contenders of the issue) to stay
  // under a minute.
  opt.contenders ??= opt.quick ? ALL_CONTENDERS.filter((k) => k !== 'wasm-view' && !KEPT_CONTENDERS.includes(k)) : ALL_CONTENDERS;
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
export const BIN = {
  genmesh: path.join(BUILD, 'bench/genmesh'),
  stages: path.join(BUILD, 'bench/stltopo_stages'),
  procstat: path.join(BUILD, 'bench/procstat'),
  edits: path.join(BUILD, 'bench/stltopo_edits'),
  cli: path.join(BUILD, 'stltopo'),
  admesh: process.env.ADMESH || 'admesh',
};
export const DATA = path.join(root, 'bench/data');
export const CHILD = path.join(root, 'bench/child.mjs');
export const NODE_FLAGS = ['--expose-gc', '--max-old-space-size=16384'];

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
