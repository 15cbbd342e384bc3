// Browser test of the demo page (web/demo), run by scripts/test-browser.sh after `vite build`.
// Real Chromium (Debian `chromium`) driven by playwright-core, against `vite preview` of the built
// site on a free port, plus a CORS file server for ?url=. The reference for every statistic is the
// native CLI: `build/stltopo info --json --intersections <file>` (the demo loads with intersections).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync, spawn } from 'node:child_process';
import { existsSync, readFileSync, copyFileSync, mkdtempSync, writeFileSync, rmSync } from 'node:fs';
import os from 'node:os';
import http from 'node:http';
import path from 'node:path';
import { root, artifacts, freePort, startSite, launchChromium, newPage as openPage, closePage, settle, pageStats }
  from './demo-page.mjs';
import { soupStl } from '../js/helpers.mjs';

const fixtures = path.join(root, 'tests/fixtures');
const cli = path.join(root, 'build/stltopo');

const fixture = (rel) => path.join(fixtures, rel);
const BUNNY = fixture('google_draco/testdata/STL/bunny.stl'); // 5 holes
const SHARED = fixture('mikedh_trimesh/models/shared.STL'); // non-manifold edge
const TRIAMID = fixture('wolph_numpy-stl/tests/stl_tests/triamid.stl'); // flipped faces
const SPHERE = fixture('mikedh_trimesh/models/unit_sphere.STL'); // closed
const SPHERE_HOLE = fixture('assimp_assimp/test/models/STL/sphereWithHole.stl'); // ASCII, 1 hole
const SPIDER = fixture('assimp_assimp/test/models/STL/Spider_binary.stl'); // holes, seams, flipped, degenerate
const WRENCH = fixture('amandaghassaei_stl-parser/test/stl/wrench.stl'); // non-manifold edges
const XYZ_CUBE = fixture('mikedh_trimesh/models/20mm-xyz-cube.stl'); // Magics colours
const TORUS = fixture('mikedh_trimesh/models/torus.STL'); // closed, genus 1

let site; // vite preview server
let siteUrl;
let files; // CORS static server over tests/fixtures
let filesUrl;
let browser;
const stalled = []; // responses of /stalled.stl, ended in after()

function cliStats(file) {
  return JSON.parse(execFileSync(cli, ['info', '--json', '--intersections', file], { encoding: 'utf8' }));
}

/** Parses a data-stat text back into a JSON value (strings stay strings). */
function parseStat(text) {
  try {
    return JSON.parse(text);
  } catch {
    return text;
  }
}

/** Deep equality where non-integer numbers may differ in the last bits (wasm vs native). */
function assertClose(actual, expected, where) {
  if (typeof expected === 'number' && typeof actual === 'number' && !Number.isInteger(expected)) {
    const tol = 1e-9 * Math.max(1, Math.abs(expected));
    assert.ok(Math.abs(actual - expected) <= tol, `${where}: ${actual} != ${expected}`);
  } else if (expected && typeof expected === 'object') {
    assert.equal(typeof actual, 'object', `${where}: ${JSON.stringify(actual)} is not an object`);
    assert.deepEqual(Object.keys(actual ?? {}).sort(), Object.keys(expected).sort(), `${where}: keys`);
    for (const k of Object.keys(expected)) assertClose(actual[k], expected[k], `${where}.${k}`);
  } else {
    assert.deepEqual(actual, expected, where);
  }
}

const newPage = () => openPage(browser, 860);

const loadCount = (page) => page.evaluate(() => Number(document.body.dataset.loadCount || 0));

async function openDemo(page, query = '') {
  await page.goto(`${siteUrl}${query}`);
  return settle(page, 0);
}


/** The page shows every CLI statistic with the CLI's value, and one list entry per hole. */
async function assertMatchesCli(page, file) {
  const expected = cliStats(file);
  const shown = await pageStats(page);
  assert.equal(shown.file, path.basename(file), 'file name');
  for (const [key, value] of Object.entries(expected)) {
    if (key === 'file') continue;
    assert.ok(key in shown, `no [data-stat="${key}"] on the page`);
    assertClose(parseStat(shown[key]), value, `${path.basename(file)} ${key}`);
  }
  const holes = await page.evaluate(() => [...document.querySelectorAll('[data-hole]')].map((e) => ({
    id: Number(e.dataset.hole), edges: Number(e.querySelector('[data-edges]').dataset.edges),
  })));
  assert.equal(holes.length, expected.holes, 'hole list length');
  assert.deepEqual(holes.sort((a, b) => a.id - b.id).map((h) => h.edges), expected.holeSizes, 'hole list edge counts');
  return expected;
}

async function loadThroughInput(page, file) {
  const n = await loadCount(page);
  await page.setInputFiles('#file-input', file);
  return settle(page, n);
}

before(async () => {
  assert.ok(existsSync(cli), `${cli} is missing: build the CLI first (cmake -S . -B build && cmake --build build)`);
  assert.ok(existsSync(path.join(root, 'web/demo/dist/index.html')), 'web/demo/dist is missing: run npm run build:demo');
  ({ site, siteUrl } = await startSite());

  files = http.createServer((req, res) => {
    const rel = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    res.setHeader('Access-Control-Allow-Origin', '*');
    if (rel === '/stalled.stl') {
      // A binary STL that promises 1000 triangles, sends 10 and then stalls: the load stays in
      // progress until it is cancelled.
      const head = Buffer.alloc(84 + 10 * 50);
      head.writeUInt32LE(1000, 80);
      res.setHeader('Content-Length', 84 + 1000 * 50);
      res.write(head);
      stalled.push(res);
      return;
    }
    const file = path.join(fixtures, rel);
    if (!file.startsWith(fixtures + path.sep) || !existsSync(file)) {
      res.statusCode = 404;
      res.end('not found');
      return;
    }
    const data = readFileSync(file);
    res.setHeader('Content-Length', data.length);
    res.end(data);
  });
  await new Promise((resolve) => files.listen(0, '127.0.0.1', resolve));
  filesUrl = `http://127.0.0.1:${files.address().port}`;

  browser = await launchChromium();
});

after(async () => {
  await browser?.close();
  await site?.close();
  for (const res of stalled) res.destroy();
  await new Promise((resolve) => (files ? files.close(resolve) : resolve()));
});

test('starts with the bunny sample, its 5 holes listed and drawn (screenshot)', async () => {
  const page = await newPage();
  assert.equal(await openDemo(page), 'ready');
  const expected = await assertMatchesCli(page, BUNNY);
  assert.equal(expected.holes, 5);
  await page.waitForTimeout(300); // let the view settle on its framed camera
  await page.screenshot({ path: path.join(artifacts, 'demo-holes.png') });

  // Clicking a hole highlights its entry and moves the camera onto it.
  const before = await page.screenshot();
  await page.click('[data-hole="3"]');
  assert.equal(await page.getAttribute('[data-hole="3"]', 'class'), 'active');
  await page.waitForTimeout(700);
  await page.screenshot({ path: path.join(artifacts, 'demo-hole-focus.png') });
  assert.notDeepEqual(await page.screenshot(), before, 'the view did not change');
  await closePage(page);
});

test('file input: closed, open and broken fixtures show the CLI statistics', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=shared');
  for (const file of [SHARED, TRIAMID, SPHERE, SPHERE_HOLE, SPIDER, WRENCH, XYZ_CUBE, TORUS]) {
    assert.equal(await loadThroughInput(page, file), 'ready', path.basename(file));
    await assertMatchesCli(page, file);
  }
  // A broken mesh with its problem edges drawn, for a look.
  await loadThroughInput(page, SPIDER);
  await page.screenshot({ path: path.join(artifacts, 'demo-broken.png') });
  await closePage(page);
});

test('a mesh over the preview limit is drawn coarser, says so, and keeps every figure of the whole mesh', async () => {
  // The limit is 2M triangles; ?previewTriangles= lowers it so that a fixture takes the path
  // a 40M-triangle scan takes (npm run bench:big opens one).
  const page = await newPage();
  await openDemo(page, '?sample=shared&previewTriangles=1000');
  assert.equal(await page.evaluate(() => document.querySelector('#scale-note').hidden), true, 'no note for the sample');
  assert.equal(await loadThroughInput(page, SPIDER), 'ready');
  await assertMatchesCli(page, SPIDER);
  const note = await page.evaluate(() => (document.querySelector('#scale-note').hidden ? null : document.querySelector('#scale-note').textContent));
  const n = cliStats(SPIDER).triangles;
  assert.ok(n > 1000, `${path.basename(SPIDER)} has ${n} triangles`);
  const stride = Math.ceil(n / 1000);
  assert.match(note ?? '', new RegExp(`draws 1 triangle in ${stride} \\(${Math.ceil(n / stride).toLocaleString('en-US')} of ${n.toLocaleString('en-US')}\\)`));
  await page.screenshot({ path: path.join(artifacts, 'demo-coarse.png') });
  await loadThroughInput(page, TRIAMID);
  assert.equal(await page.evaluate(() => document.querySelector('#scale-note').hidden), true, 'a small mesh clears the note');
  await closePage(page);
});

test('many defects: the overlays past their limits are drawn plainer, the page says so, and the figures are whole', async () => {
  // A triangle soup (no corner shared: a hole a triangle) of 1,500 triangles: 4,500 hole edges
  // and 1,500 small holes, under the defaults (20,000 edges, 2,000 rings); ?fatLines= and
  // ?rings= lower them so that it takes the path a soup of millions takes.
  const dir = mkdtempSync(path.join(os.tmpdir(), 'stltopo-demo-'));
  const soup = path.join(dir, 'soup.stl');
  writeFileSync(soup, soupStl(1500));
  const page = await newPage();
  await openDemo(page, '?sample=shared');
  assert.equal(await loadThroughInput(page, soup), 'ready');
  assert.equal(await page.evaluate(() => document.querySelector('#scale-note').hidden), true, 'no note under the defaults');
  await openDemo(page, '?sample=shared&fatLines=1000&rings=1000');
  assert.equal(await loadThroughInput(page, soup), 'ready');
  await assertMatchesCli(page, soup);
  const note = await page.evaluate(() => (document.querySelector('#scale-note').hidden ? null : document.querySelector('#scale-note').textContent));
  assert.match(note ?? '', /the view draws the 4,500 hole edges as 1-pixel lines, and no rings on the 1,500 small holes \(past 1,000 edges of a kind, or 1,000 small holes\)/);
  // The plain lines are drawn: the view with the holes differs from the view without.
  const canvas = page.locator('#viewport canvas');
  const withHoles = await canvas.screenshot();
  await page.click('[data-layer="holes"]');
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  assert.notDeepEqual(await canvas.screenshot(), withHoles, 'the holes layer drew nothing');
  await page.click('[data-layer="holes"]');
  await page.screenshot({ path: path.join(artifacts, 'demo-plain-overlays.png') });
  await loadThroughInput(page, SPHERE_HOLE);
  assert.equal(await page.evaluate(() => document.querySelector('#scale-note').hidden), true, 'a mesh of few defects clears the note');
  await closePage(page);
  rmSync(dir, { recursive: true, force: true });
});

test('edit mode: remove a triangle, fill the hole, flip the shell, download and read it back', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=shared');
  assert.equal(await loadThroughInput(page, SPHERE), 'ready');
  const before = cliStats(SPHERE);
  await page.check('#edit-mode');
  await page.waitForFunction(() => document.body.dataset.editing === 'true');
  const box = await page.locator('#viewport canvas').boundingBox();
  const centre = [box.x + box.width / 2, box.y + box.height / 2];
  const edits = () => page.evaluate(() => Number(document.body.dataset.edits));
  const stat = async (key) => parseStat((await pageStats(page))[key]);

  // A click removes the triangle under it: one hole of 3 edges in the list.
  await page.mouse.click(...centre);
  await page.waitForFunction(() => document.body.dataset.edits === '1');
  assert.equal(await stat('holes'), 1);
  assert.equal(await stat('triangles'), before.triangles - 1);
  const holes = await page.evaluate(() => [...document.querySelectorAll('[data-hole]')].map((e) => Number(e.querySelector('[data-edges]').dataset.edges)));
  assert.deepEqual(holes, [3]);

  // Select it and fill it (ear clipping): closed again.
  await page.click('[data-hole="0"]');
  await page.click('#fill-ear');
  await page.waitForFunction(() => document.body.dataset.edits === '2', null, { timeout: 5000 }).catch(async (e) => {
    throw new Error(`${e.message}; status: ${await page.textContent('#edit-status')}; errors: ${page.errors.map((x) => x.stack).join(' | ')}`);
  });
  assert.equal(await stat('holes'), 0);
  assert.equal(await stat('watertight'), true);
  assert.equal(await stat('triangles'), before.triangles);

  // Flip the shell: still closed, the volume changes sign.
  await page.check('input[name="edit-tool"][value="shell"]');
  await page.mouse.click(...centre);
  await page.waitForFunction(() => document.body.dataset.edits === '3');
  assert.ok((await stat('volume')) < 0, 'the flipped sphere has a negative volume');
  assert.equal(await stat('watertight'), true);

  // Download, and read the file back with the native CLI: the page's statistics.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#edit-download')]);
  const saved = path.join(artifacts, 'demo-edited.stl');
  await download.saveAs(saved);
  const back = cliStats(saved);
  const shown = await pageStats(page);
  for (const key of ['triangles', 'vertices', 'edges', 'holes', 'watertight', 'manifold', 'shells', 'eulerCharacteristic']) {
    assert.deepEqual(back[key], parseStat(shown[key]), key);
  }
  assertClose(back.volume, parseStat(shown.volume), 'volume');
  assert.ok(back.volume < 0);
  await closePage(page);
});

test('shells and defects: the lists match the CLI, a click isolates a shell or frames a defect (screenshots)', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=unit-sphere');
  // Spider: 18 shells, holes, seams, flipped faces, non-manifold vertices, degenerate triangles.
  assert.equal(await loadThroughInput(page, SPIDER), 'ready');
  const want = JSON.parse(execFileSync(cli, ['info', '--json', '--intersections', '--shells', '--defects', SPIDER], { encoding: 'utf8' }));
  const shells = await page.evaluate(() => [...document.querySelectorAll('[data-shell]')].map((e) => Number(e.dataset.shell)));
  assert.deepEqual(shells, want.shellList.map((s) => s.id));
  const counts = await page.evaluate(() => Object.fromEntries(
    [...document.querySelectorAll('[data-defect-count]')].map((e) => [e.dataset.defectCount, Number(e.textContent)])));
  for (const [kind, list] of Object.entries(want.defects)) {
    if (list.count) assert.equal(counts[kind], list.count, kind);
    else assert.ok(!(kind in counts), `${kind} listed without defects`);
  }
  // A shell: isolated, its figures in the stats panel.
  const pick = want.shellList.findIndex((s) => !s.closed);
  await page.click(`[data-shell="${pick}"]`);
  await page.waitForTimeout(600);
  const shown = await page.evaluate(() => Object.fromEntries(
    [...document.querySelectorAll('[data-shell-stat]')].map((e) => [e.dataset.shellStat, e.textContent])));
  for (const key of ['triangles', 'vertices', 'edges', 'closed', 'manifold', 'orientation', 'holes', 'seams', 'volume']) {
    assertClose(parseStat(shown[key]), want.shellList[pick][key], `shell ${pick} ${key}`);
  }
  assert.equal(await page.evaluate((id) => document.querySelector(`[data-shell="${id}"]`).classList.contains('active'), pick), true);
  await page.screenshot({ path: path.join(artifacts, 'demo-shell.png') });
  // Clicking it again shows every shell again.
  await page.click(`[data-shell="${pick}"]`);
  assert.equal(await page.evaluate(() => document.querySelector('#shell-stats')), null);
  // A defect of each kind that has one: framed and highlighted.
  for (const kind of Object.keys(want.defects).filter((k) => want.defects[k].count > 0)) {
    await page.click(`[data-defect-kind="${kind}"][data-defect-index="0"]`);
    assert.equal(await page.evaluate(() => document.body.dataset.focusedDefect), `${kind}:0`);
    assert.equal(await page.evaluate((k) => document.querySelector(`[data-defect-kind="${k}"][data-defect-index="0"]`)
      .classList.contains('active'), kind), true);
  }
  await page.waitForTimeout(600);
  await page.screenshot({ path: path.join(artifacts, 'demo-defect.png') });
  // Two cubes sharing an edge: one shell, not closed, outward.
  assert.equal(await loadThroughInput(page, SHARED), 'ready');
  assert.equal(await page.evaluate(() => document.querySelectorAll('[data-shell]').length), 1);
  assert.match(await page.evaluate(() => document.querySelector('[data-shell="0"] .orientation').textContent), /^not closed · outward/);
  await page.close();
});

test('an inward shell gets its own colour and count', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=unit-sphere');
  // Two cubes, the second one inside out (generated here: 24 triangles).
  const tris = [];
  const quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
  for (const [ox, flip] of [[0, false], [3, true]]) {
    const v = (i) => [ox + (i & 1), (i >> 1) & 1, (i >> 2) & 1];
    for (const [a, b, c, d] of quads) for (const t of [[a, b, c], [a, c, d]]) tris.push((flip ? [t[0], t[2], t[1]] : t).map(v));
  }
  const buf = Buffer.alloc(84 + 50 * tris.length);
  buf.writeUInt32LE(tris.length, 80);
  tris.forEach((t, i) => t.flat().forEach((x, k) => buf.writeFloatLE(x, 84 + 50 * i + 12 + 4 * k)));
  const n = await loadCount(page);
  await page.setInputFiles('#file-input', { name: 'inside-out.stl', mimeType: 'model/stl', buffer: buf });
  assert.equal(await settle(page, n), 'ready');
  const rows = await page.evaluate(() => [...document.querySelectorAll('[data-shell] .orientation')].map((e) => e.className));
  assert.deepEqual(rows, ['orientation outward', 'orientation inward']);
  assert.equal(await page.evaluate(() => document.querySelector('[data-count="inwardShells"]').textContent), '1');
  await page.close();
});

test('a soup of 2,500 triangles: the hole list shows 2,000 and says how many more', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=unit-sphere');
  const nTris = 2500;
  const buf = Buffer.alloc(84 + 50 * nTris);
  buf.writeUInt32LE(nTris, 80);
  for (let t = 0; t < nTris; t++) {
    [[t, 0, 0], [t + 0.5, 1, 0], [t, 0, 1]].flat().forEach((x, k) => buf.writeFloatLE(x, 84 + 50 * t + 12 + 4 * k));
  }
  const n = await loadCount(page);
  await page.setInputFiles('#file-input', { name: 'soup.stl', mimeType: 'model/stl', buffer: buf });
  assert.equal(await settle(page, n), 'ready');
  const list = await page.evaluate(() => ({
    holes: document.querySelectorAll('#hole-list [data-hole]').length,
    more: document.querySelector('#hole-list li.more')?.textContent,
    count: document.querySelector('[data-count="holes"]').textContent,
  }));
  assert.deepEqual(list, { holes: 2000, more: '… and 500 more', count: '2500' });
  await closePage(page);
});

test('drag and drop of a file onto the page', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=unit-sphere');
  const n = await loadCount(page);
  await page.evaluate(async ({ b64, name }) => {
    const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
    const dataTransfer = new DataTransfer();
    dataTransfer.items.add(new File([bytes], name, { type: 'model/stl' }));
    const target = document.querySelector('#viewport canvas');
    for (const type of ['dragenter', 'dragover', 'drop']) {
      target.dispatchEvent(new DragEvent(type, { dataTransfer, bubbles: true, cancelable: true }));
    }
  }, { b64: readFileSync(SPHERE_HOLE).toString('base64'), name: path.basename(SPHERE_HOLE) });
  assert.equal(await settle(page, n), 'ready');
  await assertMatchesCli(page, SPHERE_HOLE);
  assert.equal(await page.isHidden('#drop-overlay'), true, 'drop overlay stays up');
  await closePage(page);
});

test('?url= loads a file from another origin', async () => {
  const page = await newPage();
  const url = `${filesUrl}/assimp_assimp/test/models/STL/Spider_binary.stl`;
  assert.equal(await openDemo(page, `?url=${encodeURIComponent(url)}`), 'ready');
  await assertMatchesCli(page, SPIDER);
  await closePage(page);
});

test('Download STL writes the loaded mesh (binary and ASCII) and the file reads back with the same stats', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=shared');
  for (const file of [SPIDER, XYZ_CUBE, SPHERE_HOLE]) {
    assert.equal(await loadThroughInput(page, file), 'ready', path.basename(file));
    const source = cliStats(file);
    for (const format of ['binary', 'ascii']) {
      await page.selectOption('#download-format', format);
      const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download-button')]);
      const saved = path.join(artifacts, `download-${format}-${path.basename(file)}`);
      await download.saveAs(saved);
      const back = cliStats(saved);
      assert.equal(back.format, format, `${path.basename(file)} ${format}`);
      // Everything but what the format decides: its name, the stored normals (written from
      // the winding), and colours in ASCII.
      const { file: _a, format: _b, normalMismatches: _c, ...want } = source;
      const { file: _d, format: _e, normalMismatches: _f, ...got } = back;
      if (format === 'ascii') {
        want.colors = 'none';
        want.solids = want.solids.map((s) => ({ ...s, name: s.name.replace(/[\x00-\x08\x0a\x0d-\x1f].*$/s, '').replace(/[ \t\v\f]+$/, '') }));
      }
      assert.deepEqual(got, want, `${path.basename(file)} ${format}`);
    }
  }
  await closePage(page);
});

test('a bad file shows its code and message, and the next file loads', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=triamid');

  // A binary STL whose header promises 100 triangles but holds 2.
  const truncated = Buffer.alloc(84 + 2 * 50);
  truncated.write('binary, cut short', 0);
  truncated.writeUInt32LE(100, 80);
  const n = await loadCount(page);
  await page.setInputFiles('#file-input', { name: 'cut.stl', mimeType: 'model/stl', buffer: truncated });
  assert.equal(await settle(page, n), 'error');
  assert.equal(await page.isVisible('#error'), true);
  assert.equal(await page.textContent('[data-error-code]'), 'truncated');
  assert.match(await page.textContent('#error'), /truncated/);
  assert.match(await page.textContent('#error-message'), /100/);

  // The reference error of the CLI for a real truncated fixture is shown the same way.
  const broken = fixture('assimp_assimp/_history/a8a1ca98/test/models/STL/3DSMaxExport.STL');
  assert.equal(await loadThroughInput(page, broken), 'error');
  let cliError;
  try {
    execFileSync(cli, ['info', '--json', broken], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] });
  } catch (e) {
    cliError = JSON.parse(e.stdout).error;
  }
  assert.equal(await page.textContent('[data-error-code]'), cliError.code);
  assert.equal(await page.textContent('#error-message'), cliError.message);

  // An empty file, then a missing URL.
  assert.equal(await loadThroughInput(page, { name: 'empty.stl', mimeType: 'model/stl', buffer: Buffer.alloc(0) }), 'error');
  assert.equal(await page.textContent('[data-error-code]'), 'empty');

  // The page keeps working: a good file loads and the error goes away.
  assert.equal(await loadThroughInput(page, SHARED), 'ready');
  assert.equal(await page.isHidden('#error'), true);
  await assertMatchesCli(page, SHARED);

  // A sample from the menu loads after an error too.
  await loadThroughInput(page, { name: 'empty.stl', mimeType: 'model/stl', buffer: Buffer.alloc(0) });
  const m = await loadCount(page);
  await page.selectOption('#sample-select', 'torus');
  assert.equal(await settle(page, m), 'ready');
  await assertMatchesCli(page, TORUS);
  await closePage(page);
});

test('cancel stops a load in progress and keeps the model on screen', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=triamid');
  const n = await loadCount(page);
  await page.fill('#url-input', `${filesUrl}/stalled.stl`);
  await page.click('#url-form button[type="submit"]');
  await page.waitForFunction((c) => Number(document.body.dataset.loadCount) > c, n);
  assert.equal(await page.evaluate(() => document.body.dataset.state), 'loading');
  await page.waitForSelector('#progress:not([hidden])');
  await page.click('#cancel-button');
  assert.equal(await settle(page, n), 'ready');
  assert.equal(await page.isHidden('#progress'), true);
  assert.equal(await page.isHidden('#error'), true);
  assert.equal((await pageStats(page)).file, 'triamid.stl');
  // And the next load works.
  assert.equal(await loadThroughInput(page, SHARED), 'ready');
  await assertMatchesCli(page, SHARED);
  await closePage(page);
});

test('a 1M-triangle file loads in the worker without freezing the page', async () => {
  const page = await newPage();
  await openDemo(page, '?sample=triamid');
  // Record main-thread long tasks, and when the page turns ready, while the generated
  // 1M-triangle torus (50 MB binary STL) loads.
  await page.evaluate(() => {
    window.longTasks = [];
    new PerformanceObserver((list) => window.longTasks.push(...list.getEntries()))
      .observe({ type: 'longtask' });
    new MutationObserver(() => {
      if (document.body.dataset.state === 'ready') window.readyAt ??= performance.now();
    }).observe(document.body, { attributes: true, attributeFilter: ['data-state'] });
  });
  const n = await loadCount(page);
  const t0 = Date.now();
  await page.selectOption('#sample-select', 'torus-1m');
  assert.equal(await settle(page, n, 120_000), 'ready');
  const wall = Date.now() - t0;
  await page.waitForTimeout(1500); // the first draw, for the report below
  const shown = await pageStats(page);
  assert.equal(shown.triangles, '1007392');
  assert.equal(shown.holes, '8');
  assert.equal(shown.watertight, 'false');
  const r = await page.evaluate(() => ({
    beforeReady: Math.max(0, ...window.longTasks.filter((e) => e.startTime < window.readyAt).map((e) => e.duration)),
    afterReady: Math.max(0, ...window.longTasks.filter((e) => e.startTime >= window.readyAt).map((e) => e.duration)),
    loadTime: document.querySelector('#load-time').textContent,
    detail: document.querySelector('#load-time').title,
    memory: document.querySelector('#memory').textContent,
    threads: document.querySelector('[data-metric="threads"]').textContent,
    cores: navigator.hardwareConcurrency,
    isolated: crossOriginIsolated,
  }));
  // vite preview sends COOP/COEP (web/demo/vite.config.js): the page is cross-origin isolated,
  // so the worker's load ran in the threaded module on every core, and the Model panel says so.
  assert.equal(r.isolated, true, 'the demo page is cross-origin isolated');
  assert.ok(r.cores > 1, `navigator.hardwareConcurrency ${r.cores}`);
  assert.equal(r.threads, String(r.cores), 'the Model panel shows the threads of the load');
  console.log(`# 1M triangles: load time ${r.loadTime} on ${r.threads} threads (${r.detail}; wall ${wall} ms incl. generating the file in a worker), ` +
    `arrays ${r.memory}; longest main-thread task while loading ${Math.round(r.beforeReady)} ms, ` +
    `first draw ${Math.round(r.afterReady)} ms (software GL in headless Chromium)`);
  // Generating the file and parsing it run in workers; the main thread only builds the view.
  // Compared with the worker's own parse time rather than a fixed bound, so that a loaded
  // machine (which slows both alike) does not fail it: were the parse on the main thread,
  // one task would last at least as long as the parse.
  const m = /in the worker: ([0-9.]+) (ms|s);/.exec(r.detail);
  const parseMs = m ? Number(m[1]) * (m[2] === 's' ? 1000 : 1) : NaN;
  assert.ok(parseMs > 0, `no worker parse time in "${r.detail}"`);
  assert.ok(r.beforeReady < parseMs,
    `the main thread was blocked for ${Math.round(r.beforeReady)} ms while loading (worker parse ${parseMs} ms)`);
  await closePage(page);
});

test('npm start (scripts/start.sh) serves the page with the sample loaded', async () => {
  const port = await freePort();
  const server = spawn('bash', ['scripts/start.sh'], {
    cwd: root, env: { ...process.env, PORT: String(port) }, detached: true, stdio: ['ignore', 'pipe', 'pipe'],
  });
  let log = '';
  server.stdout.on('data', (d) => (log += d));
  server.stderr.on('data', (d) => (log += d));
  try {
    const url = `http://localhost:${port}/`;
    const deadline = Date.now() + 60_000;
    for (;;) {
      const ok = await fetch(url).then((r) => r.ok, () => false);
      if (ok) break;
      assert.ok(Date.now() < deadline && server.exitCode === null, `start.sh did not serve ${url}:\n${log}`);
      await new Promise((r) => setTimeout(r, 250));
    }
    const page = await newPage();
    await page.goto(url);
    assert.equal(await settle(page, 0), 'ready');
    assert.equal((await pageStats(page)).holes, '5');
    await closePage(page);
  } finally {
    process.kill(-server.pid, 'SIGTERM');
  }
});

after(() => {
  // A good screenshot for the README, when the holes one was taken.
  const shot = path.join(artifacts, 'demo-holes.png');
  if (process.env.STLTOPO_UPDATE_DOCS_SCREENSHOT && existsSync(shot)) copyFileSync(shot, path.join(root, 'docs/demo.png'));
});
