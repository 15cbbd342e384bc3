// The demo's Repair panel (issue 23): the steps and their main options, "Plan" (planRepair on an
// EditableMesh copy of the model on screen: nothing changes), one checkbox per item (unticked
// items are re-planned as `exclude`d), "Preview" (what the plan touches, drawn over the model),
// "Apply" (applyRepair: the model is redrawn from the result; the figures before and after side
// by side, and the change log of each step), "Undo" (one step at a time). While a repair is
// applied, the page's "Download STL" saves the repaired mesh (repairedStl(), used by load.js).
//
// Test hooks: body[data-repair] is "none" | "planned" | "applied"; body[data-repair-seq] counts
// the actions that finished (plan, preview, apply, undo, errors included); body[data-repair-busy]
// is "true" while one runs. Step toggles are input[data-repair-step-toggle="<step>"]; each plan
// step is [data-repair-plan-step="<step>"] with [data-repair-done] / [data-repair-skipped]; each
// item li[data-repair-step][data-repair-item] (class "skipped" when skipped; its checkbox is
// input[data-repair-exclude]; its reason .reason). The report's cells are
// [data-repair-before="<key>"] and [data-repair-after="<key>"] (rows whose value changed have
// class "changed"), body[data-repair-report] says what the After column is ("plan": the plan's
// prediction, "applied": the mesh now). The log's rows are tr[data-repair-log-step] with cells
// [data-log="<key>"]. body[data-repair-preview] is the number of items drawn, body[data-repair-focus]
// "<step>:<item>" after a click on an item. An API error shows its code in [data-repair-error-code].
import { EditableMesh, REPAIR_STEPS, REPAIR_DEFAULTS } from 'stltopo';
import { fromIndexed } from 'stltopo/worker';
import { $, viewer } from './page.js';
import { showMesh } from './panels.js';
import { setLoaded as setEditSource } from './edit-panel.js';
import { setUnionSource } from './union-panel.js';

const kMaxItems = 200; // items listed per step (the counts say how many there are)
const kMaxPreviewItems = 20000; // items drawn per step
const kMaxPreviewTriangles = 200000; // triangles drawn per step

const stepLabels = {
  duplicates: 'Remove duplicate triangles',
  'zero-area': 'Remove degenerate and zero-area triangles',
  stitch: 'Stitch cracks',
  'split-nonmanifold': 'Split non-manifold vertices and edges',
  'fill-holes': 'Fill holes',
  orient: 'Orient',
  'small-shells': 'Remove small shells',
};
const stepColors = {
  duplicates: '#ff5ad1',
  'zero-area': '#ffd000',
  stitch: '#00e5ff',
  'split-nonmanifold': '#ff7a1a',
  'fill-holes': '#3ddc84',
  orient: '#8f7bff',
  'small-shells': '#ff4040',
};
const kSkippedColor = '#8b97a6';

// The figures of a plan or log (RepairFigures), in their JSON order, with labels. Counts that
// mean trouble when not zero, flags that mean trouble when false.
const figureLabels = [['triangles', 'Triangles'], ['vertices', 'Vertices'], ['degenerateTriangles', 'Degenerate triangles'],
  ['zeroAreaTriangles', 'Zero-area triangles'], ['duplicateTriangles', 'Duplicate triangles'], ['edges', 'Edges'],
  ['boundaryEdges', 'Boundary edges'], ['nonManifoldEdges', 'Non-manifold edges'], ['inconsistentEdges', 'Inconsistent edges'],
  ['nonManifoldVertices', 'Non-manifold vertices'], ['holes', 'Holes'], ['seams', 'Seams'], ['shells', 'Shells'],
  ['eulerCharacteristic', 'Euler characteristic'], ['watertight', 'Watertight'], ['manifold', 'Manifold'],
  ['selfIntersections', 'Self-intersecting pairs'], ['solid', 'Solid']];

let source = null; // { mesh, name } as loaded (the model the repair starts from)
let em = null; // the EditableMesh the plans are made for and applied to
let plan = null; // the plan on screen
let planOptions = null; // the options it was made with (without exclude)
let exclude = []; // [{ step, item }] unticked items of the plan on screen
let planning = false; // a plan was asked for since the last apply or undo: option changes plan again
// What is applied, for the report and the log: the figures of the mesh before the first apply,
// and one entry per step of each apply ({ step, after: the figures after it, log: its log step,
// undone, failed }); undo takes back the last entry neither undone nor failed.
let history = null;
let previewCount = 0;
let seq = 0;

const body = document.body;
body.dataset.repair = 'none';

// ---------------------------------------------------------------------------------------------
// Controls

function buildControls() {
  const root = $('#repair-steps');
  for (const step of REPAIR_STEPS) {
    const label = document.createElement('label');
    label.title = stepLabels[step] ?? step;
    const input = document.createElement('input');
    input.type = 'checkbox';
    input.dataset.repairStepToggle = step;
    input.checked = REPAIR_DEFAULTS.steps.includes(step);
    label.append(input, ` ${step}`);
    root.append(label);
  }
  $('#repair-stitch-tolerance').value = String(REPAIR_DEFAULTS.stitchTolerance);
  $('#repair-max-hole-edges').value = String(REPAIR_DEFAULTS.maxHoleEdges);
  $('#repair-min-shell-triangles').value = String(REPAIR_DEFAULTS.minShellTriangles);
  $('#repair-fill-refine').checked = REPAIR_DEFAULTS.fill.includes('refine');
  $('#repair-fill-fair').checked = REPAIR_DEFAULTS.fill.includes('fair');
  $('#repair-remove-walls').checked = REPAIR_DEFAULTS.removeWalls;
  // A changed option makes the plan on screen stale: its items (and so the exclusions) change.
  const changed = () => {
    exclude = [];
    if (planning) makePlan();
  };
  for (const el of document.querySelectorAll('#repair-steps input, .repair-options input')) el.addEventListener('change', changed);
}

/** The options the controls say (numbers as typed: the package refuses bad ones). */
function readOptions() {
  const num = (sel) => {
    const text = $(sel).value.trim();
    return text === '' ? NaN : Number(text);
  };
  return {
    steps: REPAIR_STEPS.filter((s) => document.querySelector(`[data-repair-step-toggle="${s}"]`).checked),
    removeWalls: $('#repair-remove-walls').checked,
    stitchTolerance: num('#repair-stitch-tolerance'),
    maxHoleEdges: num('#repair-max-hole-edges'),
    minShellTriangles: num('#repair-min-shell-triangles'),
    fill: [...($('#repair-fill-refine').checked ? ['refine'] : []), ...($('#repair-fill-fair').checked ? ['fair'] : [])],
  };
}

function say(text) {
  $('#repair-status').textContent = text;
}

function showError(error) {
  const code = error?.code ?? error?.name ?? 'error';
  const el = document.querySelector('[data-repair-error-code]');
  el.textContent = code;
  el.dataset.repairErrorCode = code;
  $('#repair-error-message').textContent = error?.message ?? String(error);
  $('#repair-error').hidden = false;
}

function hideError() {
  $('#repair-error').hidden = true;
}

const editing = () => body.dataset.editing === 'true';

function updateButtons() {
  const busy = body.dataset.repairBusy === 'true';
  const off = busy || !source || editing();
  $('#repair-plan').disabled = off;
  $('#repair-preview').disabled = off || !plan;
  $('#repair-apply').disabled = off || !plan;
  const n = em ? em.undoableSteps : 0;
  $('#repair-undo').disabled = off || n === 0;
  $('#repair-undo').textContent = n ? `Undo (${n})` : 'Undo';
  $('#repair-preview').textContent = previewCount ? 'Hide preview' : 'Preview';
}

/** Lets the page paint (the status line) before a long step on this thread. */
function nextFrame() {
  return new Promise((resolve) => {
    requestAnimationFrame(() => resolve());
    setTimeout(resolve, 100);
  });
}

let generation = 0; // counts the models: an action that outlives its model is dropped
let pending = null; // the action asked for while another ran (the latest wins: a re-plan sees every change)
/**
 * Runs one action of the panel: one at a time, its API errors shown in the panel. The plan, the
 * apply and the undo run on the page's thread (as the edit mode does); the status line says so.
 */
async function run(what, action) {
  if (body.dataset.repairBusy === 'true') {
    pending = () => run(what, action);
    return;
  }
  body.dataset.repairBusy = 'true';
  updateButtons();
  hideError();
  say(`${what}…`);
  const g = generation;
  try {
    await nextFrame();
    if (g === generation) await action();
  } catch (error) {
    if (g === generation) {
      say(`${what} failed.`);
      showError(error);
    }
  } finally {
    body.dataset.repairBusy = 'false';
    body.dataset.repairSeq = String(++seq);
    updateButtons();
  }
  const next = pending;
  pending = null;
  if (next) await next();
}

// ---------------------------------------------------------------------------------------------
// Plan

function makePlan() {
  return run('Plan', async () => {
    if (!source) return;
    const wasPreview = previewCount > 0;
    setPreview(false);
    planning = true;
    plan = null;
    renderPlan();
    $('#repair-report').hidden = true;
    if (!em) em = await EditableMesh.from(source.mesh);
    planOptions = readOptions();
    plan = em.planRepair({ ...planOptions, exclude });
    body.dataset.repair = 'planned';
    renderPlan();
    renderReport(plan.before, plan.after, 'plan');
    const done = plan.steps.reduce((n, s) => n + s.done, 0);
    const skipped = plan.steps.reduce((n, s) => n + s.skipped, 0);
    say(`Planned: ${plural(done, 'change')}${skipped ? `, ${skipped} skipped` : ''}. Nothing has changed yet.`);
    if (wasPreview) await drawPreview(); // the preview follows the new plan
  });
}

const plural = (n, word) => `${n} ${word}${n === 1 ? '' : 's'}`;

function figureText(v) {
  if (v === null || v === undefined) return '—';
  return String(v);
}

/** A one-line summary of the figures after a step. */
function figureSummary(f) {
  const parts = [plural(f.triangles, 'triangle')];
  for (const [key, word] of [['holes', 'hole'], ['boundaryEdges', 'boundary edge'], ['nonManifoldEdges', 'non-manifold edge'],
    ['inconsistentEdges', 'inconsistent edge'], ['duplicateTriangles', 'duplicate'], ['degenerateTriangles', 'degenerate'], ['zeroAreaTriangles', 'zero-area']]) {
    if (f[key]) parts.push(plural(f[key], word));
  }
  if (f.watertight && f.manifold) parts.push('watertight, manifold');
  return parts.join(' · ');
}

function renderPlan() {
  const root = $('#repair-plan-list');
  root.textContent = '';
  if (!plan) return;
  const excluded = new Set(exclude.map((x) => `${x.step}:${x.item}`));
  for (const [k, step] of plan.steps.entries()) {
    const box = document.createElement('details');
    box.className = 'repair-step';
    box.dataset.repairPlanStep = step.step;
    box.dataset.repairDone = String(step.done);
    box.dataset.repairSkipped = String(step.skipped);
    box.open = step.items.length > 0;
    const summary = document.createElement('summary');
    summary.innerHTML = `<i class="swatch" style="--c:${stepColors[step.step] ?? '#fff'}"></i> `;
    summary.append(`${stepLabels[step.step] ?? step.step}: ${step.done} to do${step.skipped ? `, ${step.skipped} skipped` : ''} `);
    const figures = document.createElement('span');
    figures.className = 'figures';
    figures.textContent = `→ ${figureSummary(step.after)}`;
    summary.append(figures);
    box.append(summary);
    if (step.note) {
      const note = document.createElement('p');
      note.className = 'note';
      note.textContent = step.note;
      box.append(note);
    }
    if (step.items.length) {
      const ol = document.createElement('ol');
      for (let i = 0; i < Math.min(step.items.length, kMaxItems); i++) ol.append(itemEntry(k, step, i, excluded));
      if (step.items.length > kMaxItems) {
        const more = document.createElement('li');
        more.className = 'more';
        more.textContent = `… and ${step.items.length - kMaxItems} more`;
        ol.append(more);
      }
      box.append(ol);
    }
    root.append(box);
  }
  if (!plan.steps.length) root.textContent = 'No step chosen.';
  if (plan.remaining) {
    const p = document.createElement('p');
    p.className = 'repair-remaining';
    p.textContent = plan.remaining;
    root.append(p);
  }
}

function itemEntry(k, step, i, excluded) {
  const item = step.items[i];
  const li = document.createElement('li');
  li.dataset.repairStep = step.step;
  li.dataset.repairItem = String(i);
  li.classList.toggle('skipped', item.skipped);
  const userExcluded = excluded.has(`${step.step}:${i}`);
  const input = document.createElement('input');
  input.type = 'checkbox';
  input.dataset.repairExclude = '';
  input.checked = !item.skipped;
  // An item skipped for its own reason cannot be ticked; one the user unticked can.
  input.disabled = item.skipped && !userExcluded;
  input.title = input.disabled ? 'Skipped by the step' : 'Untick to leave this one out (the plan is made again)';
  input.addEventListener('click', (e) => e.stopPropagation());
  input.addEventListener('change', () => toggleItem(k, step.step, i, input.checked));
  const action = document.createElement('span');
  action.className = 'action';
  action.textContent = item.action;
  li.append(input, action);
  if (item.skipped && item.reason) {
    const reason = document.createElement('span');
    reason.className = 'reason';
    reason.textContent = item.reason;
    li.append(reason);
  }
  li.title = 'Frame it';
  li.addEventListener('click', () => {
    document.querySelectorAll('.repair-step li.active').forEach((e) => e.classList.remove('active'));
    li.classList.add('active');
    body.dataset.repairFocus = `${step.step}:${i}`;
    viewer.focusPreviewBox(item.bbox, item.skipped ? kSkippedColor : stepColors[step.step] ?? '#fff');
  });
  return li;
}

/**
 * Ticks or unticks item i of step k, then plans again. Exclusions of later steps are dropped:
 * their lists are of the mesh as those steps find it, which this choice changes.
 */
function toggleItem(k, step, i, on) {
  const later = new Set(plan.steps.slice(k + 1).map((s) => s.step));
  exclude = exclude.filter((x) => !later.has(x.step) && !(x.step === step && x.item === i));
  if (!on) exclude.push({ step, item: i });
  return makePlan();
}

// ---------------------------------------------------------------------------------------------
// Preview

/**
 * The mesh as step k of the plan finds it ({ positions, triangles, loops: id -> vertices }):
 * the editable mesh itself when no earlier step changes anything, else a scratch copy with the
 * earlier steps applied (the steps are deterministic, so it is the mesh the plan's ids are of).
 */
async function stateBefore(k) {
  const earlier = plan.steps.slice(0, k);
  let m = em;
  let scratch = null;
  if (earlier.some((s) => s.done > 0)) {
    scratch = await EditableMesh.from({ positions: em.positions, triangles: em.triangles });
    const names = earlier.map((s) => s.step);
    const p = scratch.planRepair({ ...planOptions, steps: names, exclude: exclude.filter((x) => names.includes(x.step)) });
    scratch.applyRepair(p);
    m = scratch;
  }
  try {
    const loops = new Map();
    for (const l of [...m.holes, ...m.seams]) loops.set(l.id, l.vertices);
    return { positions: m.positions, triangles: m.triangles, loops };
  } finally {
    scratch?.dispose();
  }
}

async function previewParts() {
  const parts = [];
  let count = 0;
  for (const [k, step] of plan.steps.entries()) {
    if (!step.items.length) continue;
    const color = stepColors[step.step] ?? '#ffffff';
    const { positions: P, triangles: T, loops } = await stateBefore(k);
    const done = { color, triangles: [], boxes: [], segments: [], points: [] };
    const skipped = { color: kSkippedColor, boxes: [], width: 1.5 };
    let nTriangles = 0;
    for (const item of step.items.slice(0, kMaxPreviewItems)) {
      ++count;
      if (item.skipped) {
        skipped.boxes.push(item.bbox);
        continue;
      }
      done.boxes.push(item.bbox);
      for (const t of item.triangles) {
        if (++nTriangles > kMaxPreviewTriangles || 3 * t + 2 >= T.length) break;
        for (let c = 0; c < 3; c++) {
          const v = T[3 * t + c];
          done.triangles.push(P[3 * v], P[3 * v + 1], P[3 * v + 2]);
        }
      }
      for (const id of item.loops) {
        const vs = loops.get(id);
        if (!vs) continue;
        for (let j = 0; j < vs.length; j++) {
          const a = vs[j], b = vs[(j + 1) % vs.length];
          done.segments.push(P[3 * a], P[3 * a + 1], P[3 * a + 2], P[3 * b], P[3 * b + 1], P[3 * b + 2]);
        }
      }
      // Items without triangles (a vertex merge, a split) are ringed at their vertices.
      if (!item.triangles.length && !item.loops.length && item.vertices.length <= 8) {
        for (const v of item.vertices) if (3 * v + 2 < P.length) done.points.push(P[3 * v], P[3 * v + 1], P[3 * v + 2]);
      }
    }
    parts.push(done, skipped);
  }
  return { parts, count };
}

function setPreview(on, count = 0) {
  if (!on) viewer.clearPreview();
  previewCount = on ? count : 0;
  body.dataset.repairPreview = String(previewCount);
}

function togglePreview() {
  return run('Preview', async () => {
    if (previewCount || !plan) {
      setPreview(false);
      say('Preview off.');
      return;
    }
    await drawPreview();
    say(previewCount ? `Preview: ${plural(previewCount, 'item')} drawn over the model (skipped ones in grey). Click an item to frame it.`
      : 'Preview: the plan changes nothing.');
  });
}

async function drawPreview() {
  const { parts, count } = await previewParts();
  viewer.setPreview(parts);
  setPreview(true, count);
}

// ---------------------------------------------------------------------------------------------
// Apply, undo, the report and the log

function apply() {
  return run('Apply', async () => {
    if (!plan) return;
    const t0 = performance.now();
    setPreview(false);
    const applied = plan;
    const undoable = em.undoableSteps;
    let log;
    try {
      log = em.applyRepair(applied);
    } catch (error) {
      // Refused, or failed without a log: whatever steps did complete are drawn (and undoable).
      if (em.undoableSteps !== undoable) {
        history = null;
        plan = null;
        planning = false;
        renderPlan();
        renderLog();
        $('#repair-report').hidden = true;
        await redraw(t0);
      }
      throw error;
    }
    if (!history || history.entries.every((e) => e.undone || e.failed)) history = { before: log.before, entries: [] };
    history.entries = history.entries.filter((e) => !e.undone && !e.failed);
    log.steps.forEach((s, i) => {
      // A step that failed left the mesh as it was before it: shown in the log, not undoable.
      const failed = s.status !== 'ok';
      const last = i === log.steps.length - 1;
      history.entries.push({ step: s.step, after: last ? log.after : applied.steps[i].after, log: s, undone: false, failed });
    });
    plan = null;
    planning = false;
    exclude = [];
    renderPlan();
    if (!(await redraw(t0))) return;
    body.dataset.repair = 'applied';
    renderReport(history.before, log.after, 'applied');
    renderLog();
    const failed = log.steps.find((s) => s.status !== 'ok');
    say(failed ? `Stopped at ${failed.step}: ${failed.status}${failed.message ? ` (${failed.message})` : ''}; the steps before it are applied.`
      : `Applied ${plural(log.steps.length, 'step')}. Undo takes them back one at a time; Download STL saves the repaired mesh.`);
  });
}

function undo() {
  return run('Undo', async () => {
    if (!em || em.undoableSteps === 0) return;
    const t0 = performance.now();
    setPreview(false);
    const name = em.undo();
    const live = (e) => !e.undone && !e.failed;
    const entry = history?.entries.findLast(live);
    if (entry) entry.undone = true;
    plan = null;
    planning = false;
    exclude = [];
    renderPlan();
    if (!(await redraw(t0))) return;
    const current = history?.entries.findLast(live);
    body.dataset.repair = em.undoableSteps ? 'applied' : 'none';
    if (history) renderReport(history.before, current ? current.after : history.before, 'applied');
    renderLog();
    say(`Undid ${name}.${em.undoableSteps ? '' : ' The mesh is as loaded.'}`);
  });
}

/**
 * Draws the mesh the editable mesh holds (the loaded one itself when nothing is applied); the
 * model panel's time is that of the change and the rebuild (t0: when the action started).
 */
async function redraw(t0) {
  const g = generation;
  let mesh = source.mesh;
  if (em.undoableSteps > 0) {
    const colors = em.colors;
    mesh = await fromIndexed(em.positions, em.triangles, {
      weld: 'none', shells: true, intersections: true,
      ...(colors ? { colors, colorValid: em.colorValid } : {}),
    });
  }
  if (g !== generation) return false; // another model was loaded meanwhile
  const parseMs = performance.now() - t0;
  const sceneMs = viewer.setMesh(mesh, { keepView: true });
  showMesh(mesh, { name: source.name, credit: em.undoableSteps ? 'Repaired in the page (stltopo repair).' : '',
    parseMs, sceneMs, totalMs: performance.now() - t0 });
  setEditSource({ mesh, name: source.name });
  setUnionSource({ mesh, name: source.name }, { keepUndo: true }); // a union then starts from the repaired mesh
  return true;
}

function renderReport(before, after, what) {
  const root = $('#repair-report');
  root.textContent = '';
  body.dataset.repairReport = what;
  const table = document.createElement('table');
  const caption = document.createElement('caption');
  caption.textContent = what === 'plan' ? 'Figures: now and as planned' : 'Figures: as loaded and now';
  table.append(caption);
  const head = document.createElement('tr');
  head.innerHTML = `<th></th><th>Before</th><th>${what === 'plan' ? 'Planned' : 'After'}</th>`;
  table.append(head);
  for (const [key, label] of figureLabels) {
    if (!(key in before) && !(key in after)) continue;
    const tr = document.createElement('tr');
    tr.dataset.repairFigure = key;
    // A figure the step did not compute (null: the geometry of a step before the last) is not a change.
    tr.classList.toggle('changed', after[key] !== null && before[key] !== after[key]);
    const name = document.createElement('td');
    name.textContent = label;
    const b = document.createElement('td');
    b.dataset.repairBefore = key;
    b.textContent = figureText(before[key]);
    const a = document.createElement('td');
    a.dataset.repairAfter = key;
    a.textContent = figureText(after[key]);
    tr.append(name, b, a);
    table.append(tr);
  }
  root.append(table);
  root.hidden = false;
}

const fmt = (x) => (x === 0 ? '0' : +x.toPrecision(4));

function renderLog() {
  const root = $('#repair-log');
  root.textContent = '';
  if (!history || !history.entries.length) {
    root.hidden = true;
    return;
  }
  const table = document.createElement('table');
  const caption = document.createElement('caption');
  caption.textContent = 'Change log (triangles, vertices: removed / added / changed)';
  table.append(caption);
  const head = document.createElement('tr');
  head.innerHTML = '<th>Step</th><th title="done / skipped">Items</th><th>Triangles</th><th>Vertices</th>' +
    '<th title="largest distance a vertex moved">Moved</th><th title="area removed / added">Area − / +</th>';
  table.append(head);
  for (const e of history.entries) {
    const s = e.log;
    const tr = document.createElement('tr');
    tr.dataset.repairLogStep = s.step;
    tr.classList.toggle('undone', e.undone);
    tr.classList.toggle('failed', e.failed);
    tr.title = e.undone ? 'undone' : e.failed ? `failed: ${s.message ?? s.status}` : 'applied';
    const cell = (text, key, value) => {
      const td = document.createElement('td');
      td.textContent = text;
      if (key) td.dataset.log = key;
      if (value !== undefined) td.dataset.value = String(value);
      return td;
    };
    const tri = `−${s.removedTriangles.length} / +${s.addedTriangles} / ~${s.changedTriangles.length}`;
    const ver = `−${s.removedVertices.length} / +${s.addedVertices} / ~${s.changedVertices.length}`;
    tr.append(cell(`${s.step}${s.status === 'ok' ? '' : ` (${s.status})`}`, 'step'), cell(`${s.done} / ${s.skipped}`, 'items'),
      cell(tri, 'triangles', [s.removedTriangles.length, s.addedTriangles, s.changedTriangles.length].join(',')),
      cell(ver, 'vertices', [s.removedVertices.length, s.addedVertices, s.changedVertices.length].join(',')),
      cell(String(fmt(s.maxMoved)), 'maxMoved', s.maxMoved),
      cell(`${fmt(s.areaRemoved)} / ${fmt(s.areaAdded)}`, 'area', `${s.areaRemoved},${s.areaAdded}`));
    table.append(tr);
  }
  root.append(table);
  root.hidden = false;
}

// ---------------------------------------------------------------------------------------------
// The page's side

/** The loaded mesh (load.js): a new model drops the plan and what was applied to the old one. */
export function setRepairSource(value) {
  ++generation;
  pending = null;
  em?.dispose();
  em = null;
  source = value;
  plan = null;
  planning = false;
  exclude = [];
  history = null;
  previewCount = 0;
  body.dataset.repair = 'none';
  body.dataset.repairPreview = '0';
  delete body.dataset.repairFocus;
  delete body.dataset.repairReport;
  $('#repair-plan-list').textContent = '';
  $('#repair-report').hidden = true;
  $('#repair-log').hidden = true;
  hideError();
  say('');
  updateButtons();
}

/** The repaired mesh as STL bytes when a repair is applied, else null ("Download STL"). */
export function repairedStl(format) {
  if (!em || em.undoableSteps === 0) return null;
  return em.toStl({ format });
}

buildControls();
$('#repair-plan').addEventListener('click', makePlan);
$('#repair-preview').addEventListener('click', togglePreview);
$('#repair-apply').addEventListener('click', apply);
$('#repair-undo').addEventListener('click', undo);
// The edit mode works on its own copy: the panel waits while it is on.
new MutationObserver(() => {
  if (editing()) setPreview(false); // the edit mode draws its own mesh
  updateButtons();
  if (editing()) say('Turn off Edit to plan a repair.');
  else if ($('#repair-status').textContent === 'Turn off Edit to plan a repair.') say('');
}).observe(body, { attributes: true, attributeFilter: ['data-editing'] });
updateButtons();
