// Threads in a real browser (Debian chromium via playwright-core), the package served as
// plain ES modules (no bundler): a page served with COOP same-origin + COEP require-corp is
// cross-origin isolated, so loads default to navigator.hardwareConcurrency threads through
// the threaded module (stltopo-wasm-mt / stltopo-full-mt, pool workers and all), on the page
// and in stltopo/worker, with the same results as `threads: 1`; the same page served without
// the headers falls back to the single-threaded modules and never fetches the threaded files.
// Skipped when chromium is not installed (scripts/deps.sh browser).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, createReadStream, statSync } from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { root, fixtures } from './helpers.mjs';

const chromiumPath = process.env.CHROMIUM_PATH || '/usr/bin/chromium';
const skip = !existsSync(chromiumPath) && `no chromium at ${chromiumPath}`;

const TYPES = { '.js': 'text/javascript', '.wasm': 'application/wasm', '.stl': 'application/octet-stream' };
const PAGE = `<!doctype html><meta charset="utf-8"><title>stltopo threads test</title>
<script type="importmap">{ "imports": { "stltopo": "/dist/index.js", "stltopo/worker": "/dist/worker.js" } }</script>
<script type="module">
  import * as stltopo from 'stltopo';
  import * as worker from 'stltopo/worker';
  window.pkg = { stltopo, worker };
  window.ready = true;
</script>`;

const ISOLATION = { 'cross-origin-opener-policy': 'same-origin', 'cross-origin-embedder-policy': 'require-corp' };
let server;
let base;
const served = [];
let browser;

before(async () => {
  if (skip) return;
  server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://x');
    served.push(url.pathname);
    // /broken/: an isolated page whose server sends the pool workers' script without COEP,
    // which the browser then blocks.
    const kind = /^\/(isolated|plain|broken)\//.exec(url.pathname)?.[1] ?? 'plain';
    const isolated = kind !== 'plain';
    const rest = url.pathname.replace(/^\/(isolated|plain|broken)\//, '/');
    const headers = isolated && !(kind === 'broken' && rest.endsWith('.worker.js')) ? { ...ISOLATION } : {};
    if (rest === '/') {
      const csp = "script-src 'self' 'unsafe-inline' 'wasm-unsafe-eval'; worker-src 'self'";
      res.writeHead(200, { ...headers, 'content-type': 'text/html', 'content-security-policy': csp });
      res.end(PAGE.replaceAll('"/dist/', `"/${kind}/dist/`));
      return;
    }
    const p = path.join(root, decodeURIComponent(rest));
    const allowed = ['dist/', 'tests/fixtures/'].some((d) => p.startsWith(path.join(root, d)));
    if (!allowed || !existsSync(p) || !statSync(p).isFile()) {
      res.writeHead(404);
      res.end();
      return;
    }
    res.writeHead(200, { ...headers, 'content-type': TYPES[path.extname(p).toLowerCase()] || 'application/octet-stream', 'content-length': statSync(p).size });
    createReadStream(p).pipe(res);
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  base = `http://127.0.0.1:${server.address().port}`;
  const { chromium } = await import('playwright-core');
  browser = await chromium.launch({ executablePath: chromiumPath, args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run'] });
});

after(async () => {
  if (browser) await browser.close();
  if (server) server.close();
});

async function openPage(kind) {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(`${base}/${kind}/`);
  await page.waitForFunction(() => window.ready === true, null, { timeout: 30_000 });
  return { page, errors };
}

const FILES = fixtures().filter((f) => /\.stl$/i.test(f)).map((f) => `/${path.relative(root, f).split(path.sep).join('/')}`);

// In the page: each file loaded with the default threads and with threads: 1, on the page
// (entry `which`: 'stltopo' or 'worker') with `options` (default: shells and the exact
// geometry, the full module; {} is the core's); returns per file
// the threads used and whether every array and the report matched.
async function compareInPage(page, kind, which, options = { intersections: true }, files = FILES) {
  return page.evaluate(async ({ files, prefix, which, options }) => {
    const { loadStl } = window.pkg[which];
    const digest = (m) => {
      const parts = [JSON.stringify(m.stats), JSON.stringify(m.shells), JSON.stringify(m.holes), JSON.stringify(m.solids)];
      const arrays = (o) => Object.entries(o || {}).filter(([, v]) => ArrayBuffer.isView(v));
      for (const obj of [m, m.halfedges, m.problems, m.loops, m.defects, m.intersections]) {
        for (const [k, v] of arrays(obj)) parts.push(k, Array.from(new Uint8Array(v.buffer, v.byteOffset, v.byteLength)).join(','));
      }
      if (m.halfedges) for (const k of ['prev', 'face', 'vert']) parts.push(k, m.halfedges[k].join(','));
      return parts.join('|');
    };
    const out = [];
    for (const f of files) {
      const bytes = new Uint8Array(await (await fetch(prefix + f)).arrayBuffer());
      const run = async (threads) => {
        try {
          const m = await loadStl(bytes.slice(), { ...options, ...(threads ? { threads } : {}) });
          return { threads: m.threads, d: digest(m) };
        } catch (e) {
          return { threads: 0, d: `${e.code}: ${e.message}` };
        }
      };
      const dflt = await run(null);
      const one = await run(1);
      out.push({ f, threads: dflt.threads, one: one.threads, same: dflt.d === one.d, error: dflt.threads === 0 });
    }
    return { isolated: crossOriginIsolated, cores: navigator.hardwareConcurrency, out };
  }, { files, prefix: `/${kind}`, which, options });
}

test('threads in Chromium: a cross-origin isolated page loads through the threaded module, same results', { skip }, async () => {
  const { page, errors } = await openPage('isolated');
  try {
    const plain = await compareInPage(page, 'isolated', 'stltopo', {}); // the core module
    const r = await compareInPage(page, 'isolated', 'stltopo'); // shells and geometry: the full one
    r.out.push(...plain.out);
    assert.equal(r.isolated, true, 'crossOriginIsolated');
    assert.ok(r.cores > 1, `navigator.hardwareConcurrency ${r.cores}`);
    const loaded = r.out.filter((x) => !x.error);
    assert.ok(loaded.length > 30, `${loaded.length} files loaded`);
    for (const x of r.out) {
      assert.ok(x.same, `${x.f}: the default (threaded) load differs from threads: 1`);
      if (!x.error) {
        assert.equal(x.threads, r.cores, `${x.f}: threads used`);
        assert.equal(x.one, 1);
      }
    }
    for (const f of ['stltopo-wasm-mt.js', 'stltopo-wasm-mt.wasm', 'stltopo-wasm-mt.worker.js', 'stltopo-full-mt.wasm']) {
      assert.ok(served.includes(`/isolated/dist/${f}`), `${f} was fetched (${served.filter((p) => /-mt/.test(p))})`);
    }
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});

test('threads in Chromium: stltopo/worker uses the threaded module in its worker, same results', { skip }, async () => {
  const { page, errors } = await openPage('isolated');
  try {
    const r = await compareInPage(page, 'isolated', 'worker', { intersections: true }, FILES.slice(0, 20));
    for (const x of r.out) {
      assert.ok(x.same, `${x.f}: differs`);
      if (!x.error) assert.equal(x.threads, r.cores, `${x.f}: threads used in the worker`);
    }
    // A larger file: a 200k-triangle grid through the worker, views of a threaded load.
    const big = await page.evaluate(async () => {
      const { loadStl } = window.pkg.stltopo;
      const n = 300;
      const nt = 2 * n * n;
      const buf = new ArrayBuffer(84 + 50 * nt);
      const dv = new DataView(buf);
      dv.setUint32(80, nt, true);
      let o = 84;
      const put = (x, y) => { dv.setFloat32(o, x, true); dv.setFloat32(o + 4, y, true); dv.setFloat32(o + 8, (x * y) % 7, true); o += 12; };
      for (let i = 0; i < n; ++i) {
        for (let j = 0; j < n; ++j) {
          o += 12; put(i, j); put(i + 1, j); put(i + 1, j + 1); o += 2;
          o += 12; put(i, j); put(i + 1, j + 1); put(i, j + 1); o += 2;
        }
      }
      const bytes = new Uint8Array(buf);
      const a = await loadStl(bytes, { view: true });
      const b = await window.pkg.worker.loadStl(bytes.slice(), { threads: 1 });
      const same = a.halfedges.next.every((v, i) => v === b.halfedges.next[i]) && JSON.stringify(a.stats) === JSON.stringify(b.stats)
        && a.triangles.every((v, i) => v === b.triangles[i]);
      const r = { threads: a.threads, same, valid: a.validate().ok };
      a.dispose();
      return r;
    });
    assert.ok(big.threads > 1);
    assert.ok(big.same, 'a threaded view load equals a one-thread worker load');
    assert.equal(big.valid, true);
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});

test('threads in Chromium: without COOP/COEP the page falls back to the single-threaded module', { skip }, async () => {
  const before = served.length;
  const { page, errors } = await openPage('plain');
  try {
    const r = await compareInPage(page, 'plain', 'stltopo', { intersections: true }, FILES.slice(0, 20));
    assert.equal(r.isolated, false);
    for (const x of r.out) {
      assert.ok(x.same, `${x.f}: differs`);
      if (!x.error) assert.equal(x.threads, 1, `${x.f}: one thread`);
    }
    // Asked for threads, still one: no SharedArrayBuffer here.
    const t = await page.evaluate(async () => (await window.pkg.stltopo.loadStl(new Uint8Array(84), { threads: 4 })).threads);
    assert.equal(t, 1);
    assert.ok(!served.slice(before).some((p) => /-mt\./.test(p)), 'no threaded file was fetched');
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});

test('threads in Chromium: a pool worker the browser blocks gives a one-thread load, not a hang', { skip }, async () => {
  const { page, errors } = await openPage('broken');
  try {
    const r = await page.evaluate(async (file) => {
      const { loadStl } = window.pkg.stltopo;
      const bytes = new Uint8Array(await (await fetch(file)).arrayBuffer());
      const m = await loadStl(bytes);
      const again = await loadStl(bytes, { threads: 2 });
      return { isolated: crossOriginIsolated, threads: m.threads, again: again.threads, triangles: m.nTriangles };
    }, `/broken${FILES[0]}`);
    assert.equal(r.isolated, true);
    assert.equal(r.threads, 1, 'fell back to the single-threaded module');
    assert.equal(r.again, 1, 'and stays there');
    assert.ok(r.triangles > 0);
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});
