// 1M-triangle timing, wasm vs native, in one run (not a test; run by hand):
//   node tests/js/bench-1m.mjs [path/to/native/stltopo]
// Generates a 1,002,528-triangle binary STL (an open 708x708 grid, 50 MB) in a
// temp dir, then times, best of 5 (warm):
//   native CLI   : build/stltopo info --json FILE          (process wall time)
//   npm CLI      : node bin/stltopo.mjs info --json FILE    (process wall time)
//   loadStlFile  : in-process read + weld + topology + copy-out (wasm)
//   loadStl(buf) : the same from a buffer already in memory (wasm)
import { writeFileSync, mkdtempSync, rmSync, readFileSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { loadStl, loadStlFile } from 'stltopo';
import { gridStl, root, nativeCli } from './helpers.mjs';

const native = process.argv[2] || nativeCli;
const dir = mkdtempSync(path.join(tmpdir(), 'stltopo-bench-'));
const file = path.join(dir, 'grid-1m.stl');
writeFileSync(file, gridStl(708));
const bytes = readFileSync(file);

async function best(fn, n = 5) {
  let min = Infinity;
  for (let i = 0; i < n; ++i) {
    const t0 = performance.now();
    await fn();
    min = Math.min(min, performance.now() - t0);
  }
  return min;
}

try {
  const rows = [];
  const nativeOut = execFileSync(native, ['info', '--json', file]);
  rows.push(['native CLI (process)', await best(() => execFileSync(native, ['info', '--json', file]))]);
  const npmOut = execFileSync(process.execPath, [path.join(root, 'bin/stltopo.mjs'), 'info', '--json', file]);
  rows.push(['npm CLI, wasm (process)', await best(() => execFileSync(process.execPath, [path.join(root, 'bin/stltopo.mjs'), 'info', '--json', file]))]);
  rows.push(['loadStlFile, wasm (in-process)', await best(() => loadStlFile(file))]);
  rows.push(['loadStl(buffer), wasm (in-process)', await best(() => loadStl(bytes))]);
  rows.push(['loadStl(buffer, {topology:false})', await best(() => loadStl(bytes, { topology: false }))]);
  rows.push(['node startup (node -e 0)', await best(() => execFileSync(process.execPath, ['-e', '0']))]);
  console.log(`1,002,528 triangles (${(bytes.length / 1e6).toFixed(1)} MB binary); same JSON: ${nativeOut.equals(npmOut)}`);
  for (const [name, ms] of rows) console.log(`${name.padEnd(38)} ${ms.toFixed(0).padStart(6)} ms`);
} finally {
  rmSync(dir, { recursive: true, force: true });
}
