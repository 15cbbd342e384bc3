// One measurement of bench/big.mjs, in its own process: loads FILE one way and prints one
// JSON line { ok, ms, firstReadMs, triangles, heapBytes, maxRssMiB, validate, error }.
//   node bench/big-child.mjs node|node-view|node-worker FILE
//   node bench/big-child.mjs chromium|demo FILE URL   (URL: the page serving FILE as /big.stl,
//                                                       or the demo site)
import { loadStlFile } from 'stltopo';
import { api } from '../dist/instance.node.js';

const [mode, file, url] = process.argv.slice(2);
const out = (r) => {
  if (mode.startsWith('node')) r.maxRssMiB = Math.round(process.resourceUsage().maxRSS / 1024); // not the browser's
  process.stdout.write(`${JSON.stringify(r)}\n`);
  process.exit(0); // a worker thread would keep Node alive
};

// Reads the last element of every half-edge array: for copies, the first read of the derived
// `prev`, `face` and `vert` rebuilds them in JS (issue 24, item 3).
function firstRead(m) {
  const t = performance.now();
  let s = 0;
  for (const k of ['next', 'prev', 'vert', 'face']) {
    const a = m.halfedges[k];
    s += a[a.length - 1];
  }
  return { firstReadMs: Math.round(performance.now() - t), checksum: s };
}

async function inNode() {
  const o = { node: {}, 'node-view': { view: true }, 'node-worker': { worker: true } }[mode];
  const t0 = performance.now();
  let m;
  try {
    m = await loadStlFile(file, o);
  } catch (e) {
    return out({ ok: false, ms: Math.round(performance.now() - t0), error: e.message });
  }
  const ms = Math.round(performance.now() - t0);
  const r = { ok: true, ms, triangles: m.nTriangles, holes: m.stats.holes, ...firstRead(m) };
  if (mode !== 'node-worker') r.heapBytes = (await api.internal.heap()).size;
  r.validate = m.validate().ok ? 'ok' : m.validate().code;
  out(r);
}

async function inChromium() {
  const { chromium } = await import('playwright-core');
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM_PATH || '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run'],
  });
  try {
    const page = await browser.newPage({ viewport: { width: 1400, height: 860 } });
    if (mode === 'chromium') {
      await page.goto(url);
      await page.waitForFunction(() => window.ready === true, null, { timeout: 60_000 });
      const r = await page.evaluate(async () => {
        const t0 = performance.now();
        try {
          const m = await window.worker.loadStl(await fetch('/big.stl'), { worker: true });
          const ms = Math.round(performance.now() - t0);
          const t1 = performance.now();
          let s = 0;
          for (const k of ['next', 'prev', 'vert', 'face']) s += m.halfedges[k][m.halfedges[k].length - 1];
          const v = m.validate();
          return { ok: true, ms, firstReadMs: Math.round(performance.now() - t1), checksum: s, triangles: m.nTriangles,
            holes: m.stats.holes, validate: v.ok ? 'ok' : v.code };
        } catch (e) {
          return { ok: false, ms: Math.round(performance.now() - t0), error: e.message };
        }
      });
      return out(r);
    }
    // The demo: the file through its file input, as a user opens it.
    await page.goto(url);
    await page.waitForFunction(() => document.body.dataset.state === 'ready', null, { timeout: 120_000 });
    const t0 = Date.now();
    await page.setInputFiles('#file-input', file);
    await page.waitForFunction(() => document.body.dataset.loadCount === '2' && document.body.dataset.state !== 'loading',
      null, { timeout: 30 * 60_000, polling: 1000 });
    const r = await page.evaluate(() => ({
      state: document.body.dataset.state,
      loadTime: document.querySelector('#load-time').textContent,
      triangles: document.querySelector('[data-stat="triangles"]')?.textContent,
      note: document.querySelector('#scale-note').hidden ? '' : document.querySelector('#scale-note').textContent,
      error: document.querySelector('#error').hidden ? '' : document.querySelector('#error').textContent.replace(/\s+/g, ' ').trim(),
    }));
    if (process.env.STLTOPO_BIG_SCREENSHOT) await page.screenshot({ path: process.env.STLTOPO_BIG_SCREENSHOT });
    return out({ ok: r.state === 'ready', ms: Date.now() - t0, ...r });
  } finally {
    await browser.close();
  }
}

if (mode === 'chromium' || mode === 'demo') await inChromium();
else if (mode.startsWith('node')) await inNode();
else {
  console.error(`big-child.mjs: unknown mode ${mode}`);
  process.exit(2);
}
