// The consumer matrix: the packed package (npm pack) installed into one small app per
// bundler, built with that bundler's defaults, and run in Chromium (Debian chromium via
// playwright-core). Each app (app/main.js) loads a fixture on the main thread and through
// stltopo/worker; the stats must equal `build/stltopo info --json`, the build must print no
// warning, and the page's and the workers' consoles must stay free of errors and warnings.
// A TypeScript consumer type-checks the README's examples under strict with moduleResolution
// bundler, node16 and node.
//
// Each consumer's dependencies are installed once into STLTOPO_CONSUMERS_DIR (default
// ~/.cache/stltopo-consumers/<name>, outside the repository so that nothing resolves
// through its node_modules or its own package name) from the committed package-lock.json,
// and reinstalled only when package.json or the lock changes; the tarball is installed
// into each on every run. Run by scripts/test-consumers.sh.
// Env: STLTOPO_CONSUMERS=vite5,webpack5,... (a subset), STLTOPO_NATIVE_CLI, CHROMIUM_PATH.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn, execFileSync } from 'node:child_process';
import { createHash } from 'node:crypto';
import {
  cpSync, createReadStream, existsSync, mkdirSync, readFileSync, readdirSync, rmSync, statSync, writeFileSync,
} from 'node:fs';
import http from 'node:http';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, '../..');
const work = process.env.STLTOPO_CONSUMERS_DIR || path.join(os.homedir(), '.cache/stltopo-consumers');
const nativeCli = process.env.STLTOPO_NATIVE_CLI || path.join(root, 'build/stltopo');
const chromiumPath = process.env.CHROMIUM_PATH || '/usr/bin/chromium';
const FIXTURE = path.join(root, 'tests/fixtures/assimp_assimp/test/models/STL/Spider_binary.stl'); // holes, seams, flips
const npm = process.platform === 'win32' ? 'npm.cmd' : 'npm';
const JOBS = 2;

// Consumers that fail today, and how: a failing check of one of these is a todo, not a failure.
const KNOWN = {};

// name: the app folder; kind: 'build' (bundle, then serve dist/ statically), 'dev' (the
// bundler's dev server), 'static' (the app folder itself served as files).
const TARGETS = [
  { name: 'vite5 build', dir: 'vite5', kind: 'build' },
  { name: 'vite5 dev', dir: 'vite5', kind: 'dev' },
  // Without the README's config: the failures a user meets must be StlErrors that say why.
  { name: 'vite5 dev without optimizeDeps.exclude', dir: 'vite5', kind: 'dev', config: 'none' },
  { name: 'vite7 build', dir: 'vite7', kind: 'build' },
  { name: 'vite7 dev', dir: 'vite7', kind: 'dev' },
  { name: 'vite8 build', dir: 'vite8', kind: 'build' },
  { name: 'vite8 dev', dir: 'vite8', kind: 'dev' },
  { name: 'webpack5', dir: 'webpack5', kind: 'build' },
  { name: 'esbuild', dir: 'esbuild', kind: 'build' },
  { name: 'rollup', dir: 'rollup', kind: 'build' },
  { name: 'plain <script type="module">', dir: 'plain', kind: 'static' },
];
const TS_CONFIGS = ['bundler', 'node16', 'node'];
const only = process.env.STLTOPO_CONSUMERS ? process.env.STLTOPO_CONSUMERS.split(',') : null;
const targets = TARGETS.filter((t) => !only || only.includes(t.dir));
const withTs = !only || only.includes('ts');

// ---- processes, a small job pool, servers ----

function run(cmd, args, { cwd, env } = {}) {
  return new Promise((resolve) => {
    const p = spawn(cmd, args, { cwd, env: { ...process.env, ...env }, stdio: ['ignore', 'pipe', 'pipe'] });
    let out = '';
    p.stdout.on('data', (d) => { out += d; });
    p.stderr.on('data', (d) => { out += d; });
    p.on('close', (code) => resolve({ code, out }));
  });
}
async function mustRun(cmd, args, opts) {
  const r = await run(cmd, args, opts);
  if (r.code !== 0) throw new Error(`${cmd} ${args.join(' ')} (in ${opts.cwd}) exited ${r.code}:\n${r.out}`);
  return r.out;
}

let running = 0;
const waiting = [];
async function job(fn) {
  if (running >= JOBS) await new Promise((r) => waiting.push(r));
  ++running;
  try {
    return await fn();
  } finally {
    --running;
    if (waiting.length) waiting.shift()();
  }
}
const once = (fn) => {
  const memo = new Map();
  return (key) => {
    if (!memo.has(key)) memo.set(key, fn(key));
    return memo.get(key);
  };
};

const TYPES = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.wasm': 'application/wasm',
  '.json': 'application/json', '.css': 'text/css', '.stl': 'application/octet-stream',
};
function staticServer(dir, { cors = false } = {}) {
  const server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://x');
    let p = path.join(dir, decodeURIComponent(url.pathname));
    if (!p.startsWith(dir)) p = dir + '/.none';
    if (existsSync(p) && statSync(p).isDirectory()) p = path.join(p, 'index.html');
    const headers = cors ? { 'access-control-allow-origin': '*' } : {};
    if (!existsSync(p) || !statSync(p).isFile()) {
      res.writeHead(404, headers);
      res.end();
      return;
    }
    headers['content-type'] = TYPES[path.extname(p).toLowerCase()] || 'application/octet-stream';
    headers['content-length'] = statSync(p).size;
    res.writeHead(200, headers);
    createReadStream(p).pipe(res);
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve({
    url: `http://127.0.0.1:${server.address().port}`,
    close: () => new Promise((r) => { server.closeAllConnections(); server.close(r); }),
  })));
}
function freePort() {
  return new Promise((resolve) => {
    const s = net.createServer();
    s.listen(0, '127.0.0.1', () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

// ---- the package and the apps ----

let tarball;
let fixtureServer;
let browser;
let want; // the native CLI's JSON for FIXTURE, without "file"

const hashOf = (...files) => {
  const h = createHash('sha256');
  for (const f of files) h.update(existsSync(f) ? readFileSync(f) : '-');
  return h.digest('hex');
};

// Copies an app into the work folder and installs its dependencies (once per change of
// its package.json or lock), then the tarball.
const installApp = once(async (dir) => {
  const src = path.join(here, dir);
  const dst = path.join(work, dir);
  mkdirSync(dst, { recursive: true });
  for (const f of readdirSync(dst)) if (f !== 'node_modules') rmSync(path.join(dst, f), { recursive: true, force: true });
  mkdirSync(path.join(dst, 'src'));
  for (const f of readdirSync(src)) cpSync(path.join(src, f), path.join(dst, f), { recursive: true });
  if (dir !== 'ts') {
    cpSync(path.join(here, 'app/main.js'), path.join(dst, 'src/main.js'));
    if (!existsSync(path.join(src, 'index.html'))) cpSync(path.join(here, 'app/index.html'), path.join(dst, 'index.html'));
  }
  const stamp = path.join(dst, 'node_modules/.deps-stamp');
  const key = hashOf(path.join(src, 'package.json'), path.join(src, 'package-lock.json'));
  await job(async () => {
    if (!existsSync(stamp) || readFileSync(stamp, 'utf8') !== key) {
      await mustRun(npm, ['install', '--prefer-offline', '--no-audit', '--no-fund'], { cwd: dst });
      // The first install writes the lock that later runs install from: keep it in the tree.
      if (!existsSync(path.join(src, 'package-lock.json'))) cpSync(path.join(dst, 'package-lock.json'), path.join(src, 'package-lock.json'));
      mkdirSync(path.dirname(stamp), { recursive: true }); // an app without dependencies has none yet
      writeFileSync(stamp, hashOf(path.join(src, 'package.json'), path.join(src, 'package-lock.json')));
    }
    await mustRun(npm, ['install', '--no-save', '--prefer-offline', '--no-audit', '--no-fund', tarball], { cwd: dst });
  });
  return dst;
});

// webpack's performance hints (the .wasm is over its 244 KiB advice) are advice about the
// size, which the README states, not a problem with the package; every other warning counts.
const SIZE_HINT = /asset size limit|entrypoint size limit|exceed the recommended size limit|performance recommendations|compiled with \d+ warnings?/i;
const WARNING_LINE = { test: (l) => /warn|externalized|\(!\)/i.test(l) && !SIZE_HINT.test(l) };
const buildApp = once(async (dir) => {
  const dst = await installApp(dir);
  return job(async () => {
    rmSync(path.join(dst, 'dist'), { recursive: true, force: true });
    const r = await run(npm, ['run', '--silent', 'build'], { cwd: dst, env: { NO_COLOR: '1', FORCE_COLOR: '0' } });
    const log = r.out;
    if (r.code === 0 && !existsSync(path.join(dst, 'dist/index.html'))) {
      // Bundlers without an HTML step: the same page, loading the bundle next to it.
      const html = readFileSync(path.join(here, 'app/index.html'), 'utf8').replace('src="/src/main.js"', 'src="./main.js"');
      writeFileSync(path.join(dst, 'dist/index.html'), html);
    }
    return { ok: r.code === 0, log, warnings: log.split('\n').filter((l) => WARNING_LINE.test(l)), dist: path.join(dst, 'dist') };
  });
});

async function startDev(dst, config) {
  rmSync(path.join(dst, 'node_modules/.vite'), { recursive: true, force: true }); // a first start, as a user gets it
  const port = await freePort();
  const args = ['--host', '127.0.0.1', '--port', String(port), '--strictPort'];
  if (config === 'none') {
    writeFileSync(path.join(dst, 'vite.none.config.js'), 'export default {};\n');
    args.push('--config', 'vite.none.config.js');
  }
  const p = spawn(process.execPath, ['node_modules/vite/bin/vite.js', ...args],
    { cwd: dst, env: { ...process.env, NO_COLOR: '1', FORCE_COLOR: '0' }, stdio: ['ignore', 'pipe', 'pipe'] });
  let log = '';
  let timer;
  const ready = new Promise((resolve, reject) => {
    const onData = (d) => {
      log += d;
      if (/Local:/.test(log)) resolve();
    };
    p.stdout.on('data', onData);
    p.stderr.on('data', (d) => { log += d; });
    p.on('exit', (code) => reject(new Error(`vite dev exited ${code}:\n${log}`)));
    timer = setTimeout(() => reject(new Error(`vite dev did not start in 60 s:\n${log}`)), 60_000);
  });
  // A pending timer keeps the process alive: the file ended 60 s after the last dev start.
  await ready.finally(() => clearTimeout(timer));
  return {
    url: `http://127.0.0.1:${port}`,
    log: () => log,
    close: () => new Promise((r) => { p.once('exit', r); p.kill('SIGTERM'); }),
  };
}

// Opens the app and waits for window.__result; returns it with every console error and
// warning, page error and failed request seen on the way.
async function visit(url) {
  const context = await browser.newContext();
  const page = await context.newPage();
  const problems = [];
  const onConsole = (where) => (m) => {
    if (m.type() === 'error' || m.type() === 'warning') problems.push(`${where} console.${m.type()}: ${m.text()}`);
  };
  page.on('console', onConsole('page'));
  page.on('worker', (w) => w.on('console', onConsole('worker')));
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  page.on('response', (r) => { if (r.status() >= 400) problems.push(`HTTP ${r.status()} ${r.url()}`); });
  page.on('requestfailed', (r) => problems.push(`request failed: ${r.url()} ${r.failure()?.errorText}`));
  try {
    await page.goto(`${url}/?stl=${encodeURIComponent(`${fixtureServer.url}/fixture.stl`)}`);
    const result = await page.waitForFunction(() => window.__result, null, { timeout: 30_000 })
      .then((h) => h.jsonValue(), (e) => ({ error: `no result: ${e.message.split('\n')[0]}` }));
    await new Promise((r) => setTimeout(r, 100)); // late console messages
    return { result, problems };
  } finally {
    await context.close();
  }
}

function checkResult({ result, problems }, extra = []) {
  const failures = [...extra];
  if (result.error) failures.push(`the app failed: ${result.error}`);
  for (const where of result.error ? [] : ['main', 'worker']) {
    const r = result[where];
    if (r.error) failures.push(`${where}: ${r.error}${r.code ? ` (code ${r.code})` : ''}`);
    else if (!r.valid) failures.push(`${where}: validate() failed`);
    else {
      try { assert.deepEqual(r.stats, want); } catch { failures.push(`${where}: the stats differ from the native CLI JSON`); }
    }
  }
  if (!result.error && result.errorCode !== 'empty') failures.push(`empty input gave ${result.errorCode}, not StlError empty`);
  const full = result.full;
  if (!result.error && full && full.error) failures.push(`full module: ${full.error}${full.code ? ` (code ${full.code})` : ''}`);
  else if (!result.error && !(full && full.sameWritten && full.edited && full.shells)) failures.push(`full module: ${JSON.stringify(full)}`);
  failures.push(...problems.map((p) => `  ${p}`));
  return failures;
}

// Fails the test with what went wrong. A consumer in KNOWN is marked todo (its failure
// shows but does not fail the run), and fails when it passes: then KNOWN is out of date.
function report(t, name, failures, log) {
  const known = KNOWN[name];
  if (!failures.length) {
    if (known) assert.fail(`${name} passes now: remove it from KNOWN in tests/bundlers/run.mjs`);
    return;
  }
  if (known) t.todo(`known failure: ${known}`);
  assert.fail(`${name}:\n${failures.join('\n')}${log ? `\n--- log ---\n${log.trim().split('\n').slice(-40).join('\n')}` : ''}`);
}

before(async () => {
  if (!existsSync(chromiumPath)) throw new Error(`no chromium at ${chromiumPath} (scripts/deps.sh browser)`);
  if (!existsSync(nativeCli)) throw new Error(`no native CLI at ${nativeCli}`);
  mkdirSync(work, { recursive: true });
  want = JSON.parse(execFileSync(nativeCli, ['info', '--json', FIXTURE]).toString());
  delete want.file;
  const packDir = path.join(work, 'pack');
  rmSync(packDir, { recursive: true, force: true });
  mkdirSync(packDir);
  // dist/ is built by the caller (scripts/test-consumers.sh); prepack would only rebuild it.
  const out = execFileSync(npm, ['pack', '--json', '--ignore-scripts', '--pack-destination', packDir], { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
  tarball = path.join(packDir, JSON.parse(out.toString())[0].filename);
  const fixDir = path.join(work, 'fixture');
  mkdirSync(fixDir, { recursive: true });
  cpSync(FIXTURE, path.join(fixDir, 'fixture.stl'));
  fixtureServer = await staticServer(fixDir, { cors: true });
  const { chromium } = await import('playwright-core');
  browser = await chromium.launch({
    executablePath: chromiumPath,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--no-first-run'],
  });
  // Start every install and build now; the tests below await them in order.
  for (const t of targets) (t.kind === 'build' ? buildApp : installApp)(t.dir).catch(() => {});
  if (withTs) for (const mode of TS_CONFIGS) typeCheck(mode).catch(() => {});
});

after(async () => {
  if (browser) await browser.close();
  if (fixtureServer) await fixtureServer.close();
});

for (const t of targets) {
  test(`consumer: ${t.name}`, { timeout: 600_000 }, async (ctx) => {
    if (t.kind === 'build') {
      const b = await buildApp(t.dir);
      if (!b.ok) return report(ctx, t.name, ['the build failed'], b.log);
      const server = await staticServer(b.dist);
      try {
        const seen = await visit(server.url);
        report(ctx, t.name, checkResult(seen, b.warnings.map((w) => `build warning: ${w.trim()}`)), b.log);
      } finally {
        await server.close();
      }
    } else if (t.kind === 'dev') {
      const dst = await installApp(t.dir);
      const server = await startDev(dst, t.config);
      try {
        const seen = await visit(server.url);
        if (t.config === 'none') {
          const { main, worker } = seen.result;
          assert.equal(main.code, 'wasm-load', JSON.stringify(main));
          assert.match(main.error, /^StlError: wasm-load: http:\/\/127\.0\.0\.1:\d+\/node_modules\/\.vite\/deps\/stltopo-wasm\.wasm is not the WebAssembly module: HTTP 200 \(text\/html\), first bytes 3c 21 64 6f/);
          assert.equal(worker.code, 'wasm-load', JSON.stringify(worker));
          assert.match(worker.error, /^StlError: wasm-load: the worker did not start.*init\(\{ workerUrl \}\)/);
          return;
        }
        const warnings = server.log().split('\n').filter((l) => WARNING_LINE.test(l)).map((w) => `dev server warning: ${w.trim()}`);
        report(ctx, t.name, checkResult(seen, warnings), server.log());
      } finally {
        await server.close();
      }
    } else {
      const dst = await installApp(t.dir);
      const server = await staticServer(dst);
      try {
        report(ctx, t.name, checkResult(await visit(server.url)));
      } finally {
        await server.close();
      }
    }
  });
}

// The README's ```js blocks that import stltopo, each as a .ts module.
function readmeExamples() {
  const text = readFileSync(path.join(root, 'README.md'), 'utf8');
  return [...text.matchAll(/^```js\n([\s\S]*?)^```/gm)].map((m) => m[1]).filter((b) => /from 'stltopo/.test(b));
}

const tsExamples = once(async () => {
  const dst = await installApp('ts');
  const ex = path.join(dst, 'examples');
  rmSync(ex, { recursive: true, force: true });
  mkdirSync(ex);
  const blocks = readmeExamples();
  blocks.forEach((b, i) => writeFileSync(path.join(ex, `readme-${i + 1}.ts`), `${b}\nexport {};\n`));
  return { dst, count: blocks.length };
});
const typeCheck = once(async (mode) => {
  const { dst, count } = await tsExamples();
  const r = await job(() => run(process.execPath, ['node_modules/typescript/bin/tsc', '-p', `tsconfig.${mode}.json`], { cwd: dst }));
  return { count, ...r };
});

for (const mode of withTs ? TS_CONFIGS : []) {
  test(`consumer: TypeScript, strict, moduleResolution ${mode}`, { timeout: 600_000 }, async (ctx) => {
    const r = await typeCheck(mode);
    assert.ok(r.count > 0, 'the README has no ```js example that imports stltopo');
    report(ctx, `TypeScript ${mode}`, r.code === 0 ? [] : ['tsc failed'], r.out);
  });
}
