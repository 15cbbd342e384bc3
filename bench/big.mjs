#!/usr/bin/env node
// How large a file loads (issue 24): scan-sized binary tori loaded every way a user can, each
// in its own process, one after the other:
//   native       `stltopo info --json` (procstat: wall time, peak RSS)
//   node         loadStlFile() in Node, arrays copied out of wasm (the default)
//   node-view    loadStlFile(f, { view: true }): the arrays stay in the wasm heap
//   node-worker  loadStlFile(f, { worker: true }): a worker thread, arrays transferred
//   chromium     the package in Chromium: loadStl(fetch(url), { worker: true })
//   demo         the demo page (web/demo/dist) in Chromium, the file through its file input
// A load either gives the mesh or fails with a clear error (out-of-memory past the heap); the
// table says which, with the time, the first read of the half-edge arrays, the wasm heap and
// the peak RSS. `npm run bench:big` (scripts/bench-big.sh) builds what it needs first.
//   node bench/big.mjs [--sizes 20M,40M] [--modes native,node,...] [--out FILE]
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { spawn, spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const BUILD = path.join(root, process.env.STLTOPO_BENCH_BUILD_DIR || 'build-bench');
const BIN = { cli: path.join(BUILD, 'stltopo'), genmesh: path.join(BUILD, 'bench/genmesh'), procstat: path.join(BUILD, 'bench/procstat') };
const DATA = path.join(root, 'bench/data');
const MODES = ['native', 'node', 'node-view', 'node-worker', 'chromium', 'demo'];
const opt = { sizes: ['40M'], modes: MODES, out: path.join(root, 'bench/results/big-latest.json') };
for (let i = 2; i < process.argv.length; ++i) {
  const a = process.argv[i];
  if (a === '--sizes') opt.sizes = process.argv[++i].split(',');
  else if (a === '--modes') opt.modes = process.argv[++i].split(',');
  else if (a === '--out') opt.out = path.resolve(process.argv[++i]);
  else { console.error(`big.mjs: unknown argument ${a}`); process.exit(2); }
}
for (const m of opt.modes) if (!MODES.includes(m)) { console.error(`big.mjs: unknown mode ${m}`); process.exit(2); }
const triangles = (s) => {
  const m = /^(\d+(?:\.\d+)?)([kM]?)$/.exec(s);
  if (!m) { console.error(`big.mjs: bad size ${s}`); process.exit(2); }
  return Math.round(Number(m[1]) * (m[2] === 'M' ? 1e6 : m[2] === 'k' ? 1e3 : 1));
};
const log = (s) => process.stderr.write(`big: ${s}\n`);

function ensureMesh(size) {
  const file = path.join(DATA, `torus-${size}.stl`);
  if (fs.existsSync(file)) return file;
  fs.mkdirSync(DATA, { recursive: true });
  log(`generating ${path.relative(root, file)}`);
  const r = spawnSync(BIN.genmesh, [String(triangles(size)), `${file}.part`], { encoding: 'utf8' });
  if (r.status !== 0) throw new Error(`genmesh failed: ${r.stderr}`);
  fs.renameSync(`${file}.part`, file);
  return file;
}

const lastJson = (text) => {
  const line = text.trim().split('\n').filter((l) => l.startsWith('{')).pop();
  return line ? JSON.parse(line) : null;
};

// The package page for 'chromium': dist/ behind an import map, and the file as /big.stl.
const PAGE = `<!doctype html><meta charset="utf-8"><script type="importmap">{ "imports": {
  "stltopo": "/dist/index.js", "stltopo/worker": "/dist/worker.js" } }</script>
<script type="module">import * as worker from 'stltopo/worker'; window.worker = worker; window.ready = true;</script>`;
async function packageServer(file) {
  const types = { '.js': 'text/javascript', '.wasm': 'application/wasm' };
  const server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://x');
    if (url.pathname === '/') { res.writeHead(200, { 'content-type': 'text/html' }); res.end(PAGE); return; }
    const p = url.pathname === '/big.stl' ? file : path.join(root, decodeURIComponent(url.pathname));
    if ((url.pathname !== '/big.stl' && !p.startsWith(path.join(root, 'dist/'))) || !fs.existsSync(p)) { res.writeHead(404); res.end(); return; }
    res.writeHead(200, { 'content-type': types[path.extname(p)] || 'application/octet-stream', 'content-length': fs.statSync(p).size });
    fs.createReadStream(p).pipe(res);
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  return { url: `http://127.0.0.1:${server.address().port}/`, close: () => server.close() };
}
async function demoServer() {
  const { preview } = await import('vite');
  const site = await preview({ configFile: path.join(root, 'web/demo/vite.config.js'), preview: { port: 0, host: '127.0.0.1' }, logLevel: 'warn' });
  return { url: `${site.resolvedUrls.local[0]}?sample=shared`, close: () => site.close() };
}

async function measure(mode, file) {
  if (mode === 'native') {
    const r = spawnSync(BIN.procstat, ['--', BIN.cli, 'info', '--json', file], { encoding: 'utf8' });
    const p = lastJson(r.stdout);
    return { ok: p && p.status === 0, ms: p && p.wallMs, maxRssMiB: p && Math.round(p.maxRssKiB / 1024) };
  }
  let server = null;
  if (mode === 'chromium') server = await packageServer(file);
  if (mode === 'demo') server = await demoServer();
  try {
    const args = ['--expose-gc', path.join(root, 'bench/big-child.mjs'), mode, file, ...(server ? [server.url] : [])];
    // Not spawnSync: this process serves the page meanwhile.
    const r = await new Promise((resolve) => {
      const child = spawn(process.execPath, args, { cwd: root, stdio: ['ignore', 'pipe', 'pipe'] });
      let stdout = '';
      let stderr = '';
      child.stdout.on('data', (d) => { stdout += d; });
      child.stderr.on('data', (d) => { stderr += d; });
      child.on('close', (status) => resolve({ status, stdout, stderr }));
    });
    return lastJson(r.stdout) || { ok: false, error: `exit ${r.status}: ${r.stderr.trim().split('\n').slice(0, 3).join(' / ')}` };
  } finally {
    if (server) await server.close();
  }
}

const results = [];
for (const size of opt.sizes) {
  const file = ensureMesh(size);
  for (const mode of opt.modes) {
    log(`${size} ${mode}`);
    const r = { size, triangles: triangles(size), fileBytes: fs.statSync(file).size, mode, ...(await measure(mode, file)) };
    log(JSON.stringify(r));
    results.push(r);
  }
}

const sec = (ms) => (ms === undefined || ms === null ? '–' : (ms / 1000).toFixed(1));
const lines = ['| file | way | loads | time s | first read of half-edges s | wasm heap MiB | peak RSS MiB | validate() / note |', '|:--|:--|:--|--:|--:|--:|--:|:--|'];
for (const r of results) {
  const heap = r.heapBytes ? Math.round(r.heapBytes / (1 << 20)) : '–';
  const what = r.ok ? (r.validate || r.note || '') : (r.error || '');
  lines.push(`| ${r.size} (${(r.fileBytes / 1e9).toFixed(2)} GB) | ${r.mode} | ${r.ok ? 'yes' : 'no'} | ${sec(r.ms)} | ${sec(r.firstReadMs)} | ${heap} | ${r.maxRssMiB ?? '–'} | ${what.replace(/\|/g, '/')} |`);
}
process.stdout.write(`${lines.join('\n')}\n`);
fs.mkdirSync(path.dirname(opt.out), { recursive: true });
fs.writeFileSync(opt.out, `${JSON.stringify({ date: new Date().toISOString(), results }, null, 1)}\n`);
log(`wrote ${path.relative(root, opt.out)}`);
