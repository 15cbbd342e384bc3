// Browser test of the demo's Repair panel (web/demo/repair-panel.js), run by scripts/test-browser.sh
// after `vite build`, as demo.test.mjs is: real Chromium (Debian `chromium`) driven by playwright-core
// against `vite preview` of the built site. The reference is the package itself in Node: the same
// file loaded with loadStl, planned with the same options and exclusions, applied to an
// EditableMesh; the page must list that plan, show that log's figures, draw that result and
// download its bytes. Nothing here depends on which steps find items (the steps still being
// merged plan nothing until they are): every expectation comes from the Node plan.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { loadStl, EditableMesh, REPAIR_DEFAULTS, unionShells, toStl } from 'stltopo';
import Module from 'manifold-3d';
import { damagedTorus, indexedStl } from '../js/helpers.mjs';
import { root, artifacts, startSite, launchChromium, newPage as openPage, closePage, settle, pageStats } from './demo-page.mjs';

const REMOVE_UNCONNECTED = path.join(root, 'tests/judge/admesh/block/remove-unconnected-bad.stl'); // 3 shells, 2 tiny

let site;
let siteUrl;
let browser;

before(async () => {
  ({ site, siteUrl } = await startSite());
  browser = await launchChromium();
});

after(async () => {
  await browser?.close();
  await site?.close();
});

const newPage = () => openPage(browser, 900);

/** Opens the demo and loads `file` ({ name, buffer }) through the file input. */
async function openWith(page, file) {
  await page.goto(`${siteUrl}?sample=unit-sphere`);
  await settle(page, 0);
  const n = await page.evaluate(() => Number(document.body.dataset.loadCount));
  await page.setInputFiles('#file-input', { mimeType: 'model/stl', ...file });
  assert.equal(await settle(page, n), 'ready');
}

/** Runs one action of the Repair panel (a click, a change) and waits until it has finished. */
async function repairAction(page, act) {
  const seq = await page.evaluate(() => Number(document.body.dataset.repairSeq || 0));
  await act();
  await page.waitForFunction((s) => Number(document.body.dataset.repairSeq || 0) > s, seq, { timeout: 60_000 });
  const error = await page.evaluate(() => (document.querySelector('#repair-error').hidden ? null
    : document.querySelector('#repair-error').textContent));
  return error;
}

/** The page's report cells: { before: { key: text }, after: { key: text } }. */
async function reportCells(page) {
  return page.evaluate(() => ({
    before: Object.fromEntries([...document.querySelectorAll('[data-repair-before]')].map((e) => [e.dataset.repairBefore, e.textContent])),
    after: Object.fromEntries([...document.querySelectorAll('[data-repair-after]')].map((e) => [e.dataset.repairAfter, e.textContent])),
    changed: [...document.querySelectorAll('#repair-report tr.changed')].map((e) => e.dataset.repairFigure),
  }));
}

/** Figures as the panel prints them (null as a dash). */
const asText = (figures) => Object.fromEntries(Object.entries(figures).map(([k, v]) => [k, v === null ? '—' : String(v)]));

/** What the page shows of a plan: per step, done / skipped and each listed item. */
async function shownPlan(page) {
  return page.evaluate(() => [...document.querySelectorAll('[data-repair-plan-step]')].map((s) => ({
    step: s.dataset.repairPlanStep,
    done: Number(s.dataset.repairDone),
    skipped: Number(s.dataset.repairSkipped),
    items: [...s.querySelectorAll('li[data-repair-item]')].map((li) => ({
      action: li.querySelector('.action').textContent,
      skipped: li.classList.contains('skipped'),
      reason: li.querySelector('.reason')?.textContent ?? null,
      ticked: li.querySelector('input[data-repair-exclude]').checked,
    })),
  })));
}

function expectedPlan(plan) {
  return plan.steps.map((s) => ({
    step: s.step, done: s.done, skipped: s.skipped,
    items: s.items.slice(0, 200).map((it) => ({ action: it.action, skipped: it.skipped, reason: it.skipped ? it.reason : null, ticked: !it.skipped })),
  }));
}

test('Repair panel: plan, untick an item, preview, apply (the log\'s figures, the result drawn), download, undo back to the file', async () => {
  const t = damagedTorus(30, 12, 5);
  const bytes = indexedStl(t.positions, t.triangles, 'damaged torus');
  const page = await newPage();
  await openWith(page, { name: 'damaged-torus.stl', buffer: bytes });
  const loadedStats = await pageStats(page);

  // The reference: the same file, planned and applied in Node with the panel's defaults.
  const mesh = await loadStl(bytes);
  const ref = await EditableMesh.from(mesh);
  try {
    const options = { steps: [...REPAIR_DEFAULTS.steps] };
    const plan0 = ref.planRepair(options);
    const toggles = await page.evaluate(() => [...document.querySelectorAll('[data-repair-step-toggle]')]
      .filter((e) => e.checked).map((e) => e.dataset.repairStepToggle));
    assert.deepEqual(toggles, [...REPAIR_DEFAULTS.steps], 'the step checkboxes start from REPAIR_DEFAULTS.steps');

    // Plan: the page lists the Node plan, step by step and item by item; nothing changed.
    assert.equal(await repairAction(page, () => page.click('#repair-plan')), null);
    assert.equal(await page.evaluate(() => document.body.dataset.repair), 'planned');
    assert.deepEqual(await shownPlan(page), expectedPlan(plan0));
    let cells = await reportCells(page);
    assert.deepEqual(cells.before, asText(plan0.before));
    assert.deepEqual(cells.after, asText(plan0.after));
    assert.deepEqual(await pageStats(page), loadedStats, 'planning changed the model on screen');

    // Untick one item that the plan would do: planned again with it excluded, listed as skipped.
    const k = plan0.steps.findIndex((s) => s.items.some((it) => !it.skipped));
    assert.ok(k >= 0, 'the damaged torus has something to repair');
    const step = plan0.steps[k].step;
    const item = plan0.steps[k].items.findIndex((it) => !it.skipped);
    const exclude = [{ step, item }];
    const plan = ref.planRepair({ ...options, exclude });
    assert.equal(plan.steps[k].items[item].skipped, true, 'the Node plan skips the excluded item');
    const box = `li[data-repair-step="${step}"][data-repair-item="${item}"]`;
    assert.equal(await repairAction(page, () => page.click(`${box} input[data-repair-exclude]`)), null);
    assert.deepEqual(await shownPlan(page), expectedPlan(plan));
    assert.equal(await page.evaluate((sel) => document.querySelector(sel).classList.contains('skipped'), box), true);
    assert.equal(await page.isChecked(`${box} input[data-repair-exclude]`), false);
    assert.ok((await page.textContent(`${box} .reason`)).length > 0, 'the excluded item says why it is skipped');
    cells = await reportCells(page);
    assert.deepEqual(cells.after, asText(plan.after));

    // Preview: the items drawn over the model, the mesh unchanged; a click on an item frames it.
    const canvas = page.locator('#viewport canvas');
    const shot0 = await canvas.screenshot();
    assert.equal(await repairAction(page, () => page.click('#repair-preview')), null);
    const drawn = await page.evaluate(() => Number(document.body.dataset.repairPreview));
    assert.equal(drawn, plan.steps.reduce((n, s) => n + s.items.length, 0));
    await page.waitForTimeout(300);
    await page.screenshot({ path: path.join(artifacts, 'demo-repair-preview.png') });
    assert.notDeepEqual(await canvas.screenshot(), shot0, 'the preview drew nothing');
    assert.equal(await page.textContent('#repair-preview'), 'Hide preview');
    await page.click(`${box} .action`);
    assert.equal(await page.evaluate(() => document.body.dataset.repairFocus), `${step}:${item}`);
    assert.deepEqual(await pageStats(page), loadedStats, 'the preview changed the model');

    // Apply: the figures side by side are the log's, the model drawn is the result.
    assert.equal(await repairAction(page, () => page.click('#repair-apply')), null);
    const log = ref.applyRepair(plan);
    assert.equal(await page.evaluate(() => document.body.dataset.repair), 'applied');
    assert.equal(await page.evaluate(() => document.body.dataset.repairReport), 'applied');
    cells = await reportCells(page);
    assert.deepEqual(cells.before, asText(log.before));
    assert.deepEqual(cells.after, asText(log.after));
    assert.deepEqual(cells.changed.sort(), Object.keys(log.after).filter((key) => log.after[key] !== log.before[key]).sort());
    const shown = await pageStats(page);
    for (const key of ['triangles', 'vertices', 'edges', 'boundaryEdges', 'nonManifoldEdges', 'inconsistentEdges',
      'nonManifoldVertices', 'holes', 'seams', 'shells', 'eulerCharacteristic', 'watertight', 'manifold']) {
      assert.equal(shown[key], String(log.afterReport[key]), `the model on screen: ${key}`);
    }
    const rows = await page.evaluate(() => [...document.querySelectorAll('tr[data-repair-log-step]')].map((tr) => ({
      step: tr.dataset.repairLogStep,
      triangles: tr.querySelector('[data-log="triangles"]').dataset.value,
      vertices: tr.querySelector('[data-log="vertices"]').dataset.value,
      maxMoved: Number(tr.querySelector('[data-log="maxMoved"]').dataset.value),
    })));
    assert.deepEqual(rows, log.steps.map((s) => ({
      step: s.step,
      triangles: [s.removedTriangles.length, s.addedTriangles, s.changedTriangles.length].join(','),
      vertices: [s.removedVertices.length, s.addedVertices, s.changedVertices.length].join(','),
      maxMoved: s.maxMoved,
    })));
    assert.equal(await page.textContent('#repair-undo'), `Undo (${log.steps.length})`);
    await page.click('#frame-button');
    await page.waitForTimeout(600);
    await page.screenshot({ path: path.join(artifacts, 'demo-repair-applied.png') });

    // The edit mode starts from the repaired mesh, and the panel waits while it is on.
    await page.check('#edit-mode');
    await page.waitForFunction(() => document.body.dataset.editing === 'true');
    assert.equal((await pageStats(page)).triangles, String(log.after.triangles));
    assert.equal(await page.isDisabled('#repair-plan'), true);
    assert.equal(await page.isDisabled('#repair-undo'), true);
    await page.uncheck('#edit-mode');
    await page.waitForFunction(() => document.body.dataset.editing === 'false');
    assert.deepEqual(await pageStats(page), shown, 'after the edit mode, the repaired mesh is on screen again');
    assert.equal(await page.isDisabled('#repair-undo'), false);

    // Download STL: the repaired mesh, the bytes of the Node result.
    await page.selectOption('#download-format', 'binary');
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download-button')]);
    assert.equal(download.suggestedFilename(), 'damaged-torus-repaired.stl');
    const saved = path.join(artifacts, 'demo-repaired.stl');
    await download.saveAs(saved);
    assert.ok(readFileSync(saved).equals(Buffer.from(ref.toStl({ format: 'binary' }))), 'the download is not the repaired mesh');

    // Undo, one step at a time, back to the file as loaded.
    for (let left = log.steps.length; left > 0; --left) {
      assert.equal(await page.textContent('#repair-undo'), `Undo (${left})`);
      assert.equal(await repairAction(page, () => page.click('#repair-undo')), null);
      assert.match(await page.textContent('#repair-status'), new RegExp(`^Undid ${log.steps[left - 1].step}\\.`));
    }
    assert.equal(await page.isDisabled('#repair-undo'), true);
    assert.equal(await page.evaluate(() => document.body.dataset.repair), 'none');
    cells = await reportCells(page);
    assert.deepEqual(cells.after, asText(log.before), 'after undo, the figures are those of the file');
    assert.deepEqual(cells.changed, []);
    assert.equal(await page.evaluate(() => document.querySelectorAll('tr[data-repair-log-step].undone').length), log.steps.length);
    assert.deepEqual(await pageStats(page), loadedStats, 'after undo, the model on screen is the file as loaded');
    const [again] = await Promise.all([page.waitForEvent('download'), page.click('#download-button')]);
    assert.equal(again.suggestedFilename(), 'damaged-torus.stl', 'with nothing applied, Download STL saves the loaded mesh');
  } finally {
    ref.dispose();
  }
  await closePage(page);
});

test('Repair panel: a bad option shows the API error in the panel; small shells are removed when asked', async () => {
  const page = await newPage();
  await openWith(page, { name: 'remove-unconnected-bad.stl', buffer: readFileSync(REMOVE_UNCONNECTED) });
  const mesh = await loadStl(readFileSync(REMOVE_UNCONNECTED));

  // The step choice is read when planning: small-shells on.
  await page.check('[data-repair-step-toggle="small-shells"]');
  assert.equal(await repairAction(page, () => page.click('#repair-plan')), null);
  const options = { steps: [...REPAIR_DEFAULTS.steps, 'small-shells'] };
  const ref = await EditableMesh.from(mesh);
  try {
    const plan = ref.planRepair(options);
    assert.deepEqual(await shownPlan(page), expectedPlan(plan));

    // A negative tolerance: the package refuses it (invalid-argument), shown in the panel.
    await page.fill('#repair-stitch-tolerance', '-1');
    const error = await repairAction(page, () => page.dispatchEvent('#repair-stitch-tolerance', 'change'));
    assert.match(error ?? '', /stitchTolerance/);
    assert.equal(await page.textContent('[data-repair-error-code]'), 'invalid-argument');
    assert.equal(await page.isDisabled('#repair-apply'), true, 'no plan to apply after a refusal');

    // Fixed: planned again, applied; the figures are those of the Node result.
    await page.fill('#repair-stitch-tolerance', '0');
    assert.equal(await repairAction(page, () => page.dispatchEvent('#repair-stitch-tolerance', 'change')), null);
    assert.equal(await page.isHidden('#repair-error'), true);
    assert.equal(await repairAction(page, () => page.click('#repair-apply')), null);
    const log = ref.applyRepair(plan);
    assert.deepEqual((await reportCells(page)).after, asText(log.after));
    assert.equal((await pageStats(page)).shells, String(log.after.shells));
  } finally {
    ref.dispose();
  }
  await closePage(page);
});

/** Runs one action of the union part of the panel and waits until it has finished. */
async function unionAction(page, act) {
  const seq = await page.evaluate(() => Number(document.body.dataset.unionSeq || 0));
  await act();
  await page.waitForFunction((n) => Number(document.body.dataset.unionSeq || 0) > n, seq, { timeout: 60_000 });
}

test('Overlapping shells: the box sample\'s 10 bodies become one solid with Unite (manifold-3d in the page), downloaded as such; Undo union brings the file back', async () => {
  const page = await newPage();
  await page.goto(`${siteUrl}?sample=box-overlapping`);
  assert.equal(await settle(page, 0), 'ready');
  await page.waitForFunction(() => document.body.dataset.union === 'ready');
  assert.equal(await page.evaluate(() => document.body.dataset.unionGroups), '1');
  assert.equal((await pageStats(page)).shells, '10');
  assert.equal((await pageStats(page)).solid, 'false');
  assert.equal(await page.isDisabled('#union-undo'), true);

  // The reference: the same file united in Node with the same manifold-3d.
  const manifold = await Module();
  manifold.setup();
  const file = readFileSync(path.join(root, 'tests/fixtures/mikedh_trimesh/models/box.STL'));
  const ref = await unionShells(await loadStl(file, { shells: true, intersections: true }), { manifold });
  assert.equal(ref.mesh.stats.solid, true);

  await unionAction(page, () => page.click('#union-unite'));
  const stats = await pageStats(page);
  assert.equal(stats.shells, '1');
  assert.equal(stats.solid, 'true');
  assert.equal(stats.selfIntersections, '0');
  assert.equal(await page.evaluate(() => document.body.dataset.union), 'none');
  assert.equal(await page.evaluate(() => document.body.dataset.unionUndo), '1');
  assert.match(await page.textContent('#union-status'), /No closed shells overlap/);

  // The download is the union, byte for byte as the Node reference writes it.
  await page.selectOption('#download-format', 'binary');
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download-button')]);
  const saved = path.join(artifacts, 'box-united.stl');
  await download.saveAs(saved);
  assert.ok(readFileSync(saved).equals(Buffer.from(await toStl(ref.mesh, { format: 'binary' }))),
    'the download is not the united mesh');

  // Undo union: the file as loaded.
  await unionAction(page, () => page.click('#union-undo'));
  assert.equal((await pageStats(page)).shells, '10');
  await page.waitForFunction(() => document.body.dataset.union === 'ready');
  assert.equal(await page.isDisabled('#union-undo'), true);
  await closePage(page);
});
