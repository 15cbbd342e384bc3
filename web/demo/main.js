// The demo page: loading (samples, file picker, drag and drop, ?url=), the worker-side parse with
// progress and cancel, and the panels. The 3D side lives in viewer.js.
//
// Test hooks (kept stable): document.body.dataset.state is "loading" | "ready" | "error";
// every statistic is an element [data-stat="<stltopo info --json key>"] whose text is the value;
// each hole list entry carries data-hole="<hole id>"; each shell entry data-shell="<shell id>"
// (the selected one has class "active" and its figures are [data-shell-stat="<shellList key>"]);
// each defect entry data-defect-kind="<kind>" data-defect-index="<i>" (the framed one is active,
// and body[data-focused-defect] says "<kind>:<i>"); the error code is in [data-error-code].
import { loadStl, toStl, DEFECT_KINDS, GEOMETRY_DEFECT_KINDS } from 'stltopo/worker';
import { Viewer, holeColor, colors } from './viewer.js';
import { samples, defaultSampleId } from './samples.js';
import { createEditor } from './edit.js';

const $ = (selector) => document.querySelector(selector);
const viewer = new Viewer($('#viewport'));
if (import.meta.env?.DEV) window.stltopoDemo = { viewer }; // for poking around in devtools

// Stats panel layout: [group, [[JSON key, label], ...]]. Keys the package reports beyond these
// land in "Other", so every key of `stltopo info --json` has its element.
const statGroups = [
  ['File', [['format', 'Format'], ['solids', 'Solids'], ['triangles', 'Triangles'], ['vertices', 'Vertices'],
    ['colors', 'Colours'], ['degenerateTriangles', 'Degenerate triangles'], ['zeroAreaTriangles', 'Zero-area triangles'],
    ['duplicateTriangles', 'Duplicate triangles'], ['normalMismatches', 'Normal mismatches'],
    ['warnings', 'Warnings']]],
  ['Topology', [['watertight', 'Watertight'], ['manifold', 'Manifold'], ['edges', 'Edges'],
    ['boundaryEdges', 'Boundary edges'], ['nonManifoldEdges', 'Non-manifold edges'],
    ['inconsistentEdges', 'Inconsistent edges'], ['nonManifoldVertices', 'Non-manifold vertices'],
    ['holes', 'Holes'], ['seams', 'Seams'], ['holeSizes', 'Hole sizes (edges)'], ['shells', 'Shells'],
    ['eulerCharacteristic', 'Euler characteristic'], ['genus', 'Genus']]],
  ['Geometry', [['solid', 'Solid'], ['selfIntersections', 'Self-intersecting pairs'],
    ['intersectionKinds', 'Crossing / touching / coplanar'], ['intersectingTriangles', 'Intersecting triangles'],
    ['intersectionsComplete', 'Intersection pass complete'], ['bbox', 'Bounding box'], ['area', 'Surface area'],
    ['volume', 'Volume']]],
];
// Counts that mean trouble when they are not zero, and flags that mean trouble when false.
const badWhenNonZero = new Set(['degenerateTriangles', 'normalMismatches', 'boundaryEdges', 'nonManifoldEdges',
  'inconsistentEdges', 'nonManifoldVertices', 'holes', 'seams', 'zeroAreaTriangles', 'duplicateTriangles',
  'selfIntersections', 'intersectingTriangles']);
const badWhenFalse = new Set(['watertight', 'manifold', 'solid', 'intersectionsComplete']);

let current = null; // { seq, controller, name } of the load in flight
let loaded = null; // { mesh, name } on screen (the edit mode starts from it)
let loadSeq = 0;
let hasModel = false;

function setState(state) {
  document.body.dataset.state = state;
}

// ---------------------------------------------------------------------------------------------
// Loading

/**
 * Loads one source and shows it. `source` is a File/Blob, an ArrayBuffer, or { url }.
 * A newer load cancels an older one; errors land in the error box and the page stays usable.
 */
async function load(source, { name, credit = '' } = {}) {
  current?.controller.abort();
  const seq = ++loadSeq;
  const controller = new AbortController();
  current = { seq, controller, name, userCancelled: false };
  setState('loading');
  document.body.dataset.loadCount = String(seq);
  hideError();
  showProgress(name, NaN, 0);
  const t0 = performance.now();
  try {
    let input = source;
    let total = source.size ?? source.byteLength;
    if (source.url) {
      const response = await fetch(source.url, { signal: controller.signal });
      if (!response.ok) {
        throw Object.assign(new Error(`the server answered ${response.status} ${response.statusText} for ${source.url}`), { code: 'http' });
      }
      total = Number(response.headers.get('content-length')) || NaN;
      input = response;
    }
    const mesh = await loadStl(input, {
      topology: true,
      shells: true,
      intersections: true, // exact self-intersections, nesting and the solid badge (issue 21)
      signal: controller.signal,
      onProgress: (fraction, bytesRead) => {
        if (seq === loadSeq) showProgress(name, Number.isFinite(fraction) ? fraction : bytesRead / total, bytesRead);
      },
    });
    if (seq !== loadSeq) return;
    const tParsed = performance.now();
    showProgress(name, 1, total, 'building the view…');
    await nextFrame();
    if (seq !== loadSeq) return;
    await stopEditing();
    const sceneMs = viewer.setMesh(mesh);
    hasModel = true;
    shown = { mesh, name };
    $('#download').hidden = false;
    loaded = { mesh, name };
    showMesh(mesh, { name, credit, parseMs: tParsed - t0, sceneMs, totalMs: performance.now() - t0 });
    hideProgress();
    current = null;
    setState('ready');
  } catch (error) {
    if (seq !== loadSeq) return;
    hideProgress();
    const cancelled = current?.userCancelled;
    current = null;
    if (cancelled && hasModel) {
      setState('ready'); // the previous model is still on screen
      return;
    }
    showError(name, error);
    viewer.clear();
    clearPanels();
    hasModel = false;
    shown = null;
    $('#download').hidden = true;
    setState('error');
  }
}

// The mesh on screen, for "Download STL": written as STL in the worker (the mesh came from
// one), then handed to the browser as a download.
let shown = null;
$('#download-button').addEventListener('click', async () => {
  if (!shown) return;
  const button = $('#download-button');
  const format = $('#download-format').value;
  button.disabled = true;
  try {
    const blob = await toStl(shown.mesh, { format });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `${shown.name.replace(/\.stl$/i, '')}${format === 'ascii' ? '-ascii' : ''}.stl`;
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 60_000);
  } catch (error) {
    showError(shown.name, error);
  } finally {
    button.disabled = false;
  }
});

/** Lets the page paint (progress text) before a long step; does not hang in a hidden tab. */
function nextFrame() {
  return new Promise((resolve) => {
    requestAnimationFrame(() => resolve());
    setTimeout(resolve, 100);
  });
}

async function loadSample(id) {
  const sample = samples.find((s) => s.id === id) ?? samples[0];
  $('#sample-select').value = sample.id;
  if (sample.generate) {
    setState('loading');
    showProgress(sample.label, NaN, 0, 'generating…');
    const seq = loadSeq;
    let buffer;
    try {
      buffer = await generate(sample.generate);
    } catch (error) {
      if (seq === loadSeq) {
        hideProgress();
        showError(sample.label, error);
        setState('error');
      }
      return undefined;
    }
    if (seq !== loadSeq) return undefined; // another load started meanwhile
    const name = `${sample.id}.stl`;
    return load(new File([buffer], name), { name, credit: 'Generated in the page by web/demo/generate.js.' });
  }
  return load({ url: new URL(`samples/${sample.file}`, document.baseURI).href },
    { name: sample.file, credit: `Sample from ${sample.credit}.` });
}

/** Runs a generator of generate.js in a worker (the 1M-triangle one takes a while). */
function generate(name) {
  return new Promise((resolve, reject) => {
    const worker = new Worker(new URL('./generate-worker.js', import.meta.url), { type: 'module' });
    worker.onmessage = ({ data }) => {
      worker.terminate();
      if (data.error) reject(new Error(data.error));
      else resolve(data.buffer);
    };
    worker.onerror = (event) => {
      worker.terminate();
      reject(new Error(`generator worker: ${event.message}`));
    };
    worker.postMessage({ name });
  });
}

function loadUrl(url) {
  let name = url;
  try {
    name = decodeURIComponent(new URL(url, document.baseURI).pathname.split('/').pop()) || url;
  } catch { /* keep the raw text as the name */ }
  return load({ url }, { name, credit: `Loaded from ${url}` });
}

// ---------------------------------------------------------------------------------------------
// Progress and errors

const formatBytes = (n) => (!Number.isFinite(n) ? '' : n < 1e3 ? `${n} B` : n < 1e6 ? `${(n / 1e3).toFixed(1)} kB` : `${(n / 1e6).toFixed(1)} MB`);

function showProgress(name, fraction, bytes, note) {
  $('#progress').hidden = false;
  $('#progress-name').textContent = name ?? '';
  const bar = $('#progress-bar');
  if (Number.isFinite(fraction)) bar.value = Math.max(0, Math.min(1, fraction));
  else bar.removeAttribute('value'); // indeterminate
  $('#progress-text').textContent = note ?? [Number.isFinite(fraction) ? `${Math.round(fraction * 100)}%` : '', formatBytes(bytes)].filter(Boolean).join(' · ');
}

function hideProgress() {
  $('#progress').hidden = true;
}

function showError(name, error) {
  const code = error?.code ?? error?.name ?? 'error';
  $('#error-file').textContent = name ?? 'the file';
  $('#error-code').textContent = code;
  $('#error-code').dataset.errorCode = code;
  $('#error-message').textContent = error?.message ?? String(error);
  $('#error').hidden = false;
}

function hideError() {
  $('#error').hidden = true;
}

// ---------------------------------------------------------------------------------------------
// Panels

/** Text of a statistic: exactly the JSON value (numbers as JS prints them, arrays as JSON). */
function statText(value) {
  if (value === null || value === undefined) return 'null';
  if (typeof value === 'object') return JSON.stringify(value);
  return String(value);
}

function friendlyBbox(bbox) {
  const min = bbox?.min ?? (Array.isArray(bbox) ? bbox.slice(0, 3) : null);
  const max = bbox?.max ?? (Array.isArray(bbox) ? bbox.slice(3, 6) : null);
  if (!min || !max || min.length !== 3) return '';
  return `size ${[0, 1, 2].map((i) => +(max[i] - min[i]).toPrecision(4)).join(' × ')}`;
}

function friendlySolids(solids) {
  if (!Array.isArray(solids)) return '';
  const names = solids.map((s) => (s.name ? `“${s.name}”` : 'unnamed')).slice(0, 3).join(', ');
  return `${solids.length} solid${solids.length === 1 ? '' : 's'}: ${names}${solids.length > 3 ? ', …' : ''}`;
}

function renderStats(stats, name) {
  const root = $('#stats');
  root.textContent = '';
  const known = new Set(statGroups.flatMap(([, keys]) => keys.map(([k]) => k)));
  const other = Object.keys(stats).filter((k) => !known.has(k) && k !== 'file').map((k) => [k, k]);
  for (const [title, keys] of [...statGroups, ...(other.length ? [['Other', other]] : [])]) {
    const group = document.createElement('div');
    group.className = 'stats-group';
    group.innerHTML = `<h3>${title}</h3>`;
    const dl = document.createElement('dl');
    for (const [key, label] of keys) {
      if (!(key in stats)) continue;
      const value = stats[key];
      const dt = document.createElement('dt');
      dt.textContent = label;
      const dd = document.createElement('dd');
      const span = document.createElement('span');
      span.dataset.stat = key;
      span.textContent = statText(value);
      dd.append(span);
      if (typeof value === 'object' && value !== null) dd.className = 'long';
      if ((badWhenNonZero.has(key) && value > 0) || (badWhenFalse.has(key) && value === false)) dd.classList.add('bad');
      if (badWhenFalse.has(key) && value === true) dd.classList.add('good');
      const friendly = key === 'bbox' ? friendlyBbox(value) : key === 'solids' ? friendlySolids(value) : '';
      if (friendly) {
        const f = document.createElement('span');
        f.className = 'friendly';
        f.textContent = friendly;
        dd.append(f);
      }
      dl.append(dt, dd);
    }
    group.append(dl);
    root.append(group);
  }
  const file = document.querySelector('[data-stat="file"]');
  file.textContent = name;
}

// Shells: the list (triangles, closed, orientation, volume); a click isolates and frames one,
// and the stats panel shows its figures.
let selectedShell = null;
const shellStatKeys = [['triangles', 'Triangles'], ['vertices', 'Vertices'], ['edges', 'Edges'],
  ['closed', 'Closed'], ['manifold', 'Manifold'], ['consistent', 'Consistent'], ['orientation', 'Orientation'],
  ['boundaryEdges', 'Boundary edges'], ['nonManifoldEdges', 'Non-manifold edges'],
  ['inconsistentEdges', 'Inconsistent edges'], ['nonManifoldVertices', 'Non-manifold vertices'], ['holes', 'Holes'],
  ['seams', 'Seams'], ['eulerCharacteristic', 'Euler characteristic'], ['genus', 'Genus'], ['solid', 'Solid'],
  ['bbox', 'Bounding box'], ['area', 'Surface area'], ['volume', 'Volume']];

function renderShellStats(shell) {
  document.querySelector('#shell-stats')?.remove();
  if (!shell) return;
  const group = document.createElement('div');
  group.className = 'stats-group';
  group.id = 'shell-stats';
  group.innerHTML = `<h3>Shell #${shell.id}</h3>`;
  const dl = document.createElement('dl');
  for (const [key, label] of shellStatKeys) {
    const dt = document.createElement('dt');
    dt.textContent = label;
    const dd = document.createElement('dd');
    const span = document.createElement('span');
    span.dataset.shellStat = key;
    span.textContent = statText(shell[key]);
    dd.append(span);
    if (key === 'bbox') dd.className = 'long';
    if ((['closed', 'manifold', 'consistent'].includes(key) && shell[key] === false) ||
        (key.endsWith('Edges') || key === 'nonManifoldVertices' || key === 'holes' || key === 'seams') && shell[key] > 0) {
      dd.classList.add('bad');
    }
    dl.append(dt, dd);
  }
  group.append(dl);
  $('#stats').prepend(group);
}

function renderShells(mesh) {
  const ol = $('#shell-list');
  ol.textContent = '';
  selectedShell = null;
  const shells = mesh.shells ?? [];
  $('#shells-panel').hidden = shells.length === 0;
  const fragment = document.createDocumentFragment();
  for (const shell of shells.slice(0, 2000)) {
    const li = document.createElement('li');
    li.dataset.shell = String(shell.id);
    li.title = `Isolate shell ${shell.id}`;
    const color = shell.orientation === 'inward' ? colors.inward : colors.front;
    li.innerHTML = `<i class="swatch big" style="--c:${color}"></i><span class="id">#${shell.id}</span>` +
      `<span class="edges">${shell.triangles} tri${shell.triangles === 1 ? '' : 's'}</span>` +
      `<span class="orientation ${shell.orientation}">${shell.closed ? 'closed' : 'not closed'} · ${shell.orientation}` +
      `${shellNesting(shell)} · V ${+shell.volume.toPrecision(3)}</span>`;
    li.addEventListener('click', () => {
      const wasActive = li.classList.contains('active');
      document.querySelectorAll('.loop-list li.active, .defect-kind li.active').forEach((e) => e.classList.remove('active'));
      delete document.body.dataset.focusedDefect;
      selectedShell = wasActive ? null : shell.id;
      if (!wasActive) li.classList.add('active');
      viewer.isolateShell(selectedShell);
      renderShellStats(wasActive ? null : shell);
    });
    fragment.append(li);
  }
  ol.append(fragment);
}

// Defects, grouped by kind; a click frames and highlights one.
// What the nesting says about a shell (with intersections): a cavity, a body inside another,
// an inside-out part, or overlapping bodies.
function shellNesting(shell) {
  if (shell.intersectsShells === undefined) return '';
  if (shell.intersectsShells.length) return ` · <b class="overlap">overlaps #${shell.intersectsShells.join(', #')}</b>`;
  if (shell.depth === null) return shell.selfIntersects ? ' · self-intersecting' : '';
  const odd = shell.depth % 2 === 1;
  const what = shell.orientation === 'inward' ? (odd ? `cavity in #${shell.parent}` : 'inside out')
    : shell.orientation === 'outward' ? (odd ? `body inside #${shell.parent}` : shell.depth ? `island in #${shell.parent}` : '')
      : '';
  return (what ? ` · ${what}` : '') + (shell.selfIntersects ? ' · self-intersecting' : '');
}

const defectLabels = {
  holes: 'Holes', seams: 'Seams', nonManifoldEdges: 'Non-manifold edges', inconsistentEdges: 'Inconsistent edges',
  nonManifoldVertices: 'Non-manifold vertices', degenerateTriangles: 'Degenerate triangles',
  zeroAreaTriangles: 'Zero-area triangles', duplicateTriangles: 'Duplicate triangles',
  selfIntersections: 'Self-intersections',
};
const kMaxDefectItems = 200; // per kind in the list (the counts say how many there are)

function defectText(kind, d) {
  switch (kind) {
    case 'holes':
    case 'seams': return `#${d.id} · ${d.edges} edges · shell ${d.shell}`;
    case 'nonManifoldEdges': return `edge ${d.vertices[0]}–${d.vertices[1]} · ${d.triangles.length} triangles`;
    case 'inconsistentEdges': return `edge ${d.vertices[0]}–${d.vertices[1]} · triangles ${d.triangles[0]}, ${d.triangles[1]}`;
    case 'nonManifoldVertices': return `vertex ${d.vertex} · ${d.cycles} cycles`;
    case 'zeroAreaTriangles': return `triangle ${d.triangle} · collinear corners`;
    case 'duplicateTriangles': return `triangles ${d.triangles.join(', ')} · ${d.orientation}`;
    case 'selfIntersections': return `triangles ${d.triangles[0]} × ${d.triangles[1]} · ${d.kind}`;
    default: return `triangle ${d.triangle} · corners ${d.corners.join(', ')} coincide`;
  }
}

function renderDefects(mesh) {
  const root = $('#defect-list');
  root.textContent = '';
  let any = false;
  for (const kind of [...DEFECT_KINDS, ...GEOMETRY_DEFECT_KINDS]) {
    const geometric = kind === 'zeroAreaTriangles' || kind === 'duplicateTriangles' || kind === 'selfIntersections';
    const n = (geometric ? mesh.intersections : mesh.defects) ? mesh.defectCount(kind) : 0;
    if (!n) continue;
    any = true;
    const details = document.createElement('details');
    details.className = 'defect-kind';
    details.dataset.kind = kind;
    details.open = true;
    details.innerHTML = `<summary>${defectLabels[kind]} <span class="count" data-defect-count="${kind}">${n}</span></summary>`;
    const ol = document.createElement('ol');
    for (let i = 0; i < Math.min(n, kMaxDefectItems); i++) {
      const d = mesh.defect(kind, i);
      const li = document.createElement('li');
      li.dataset.defectKind = kind;
      li.dataset.defectIndex = String(i);
      li.textContent = defectText(kind, d);
      li.addEventListener('click', () => {
        document.querySelectorAll('.loop-list li.active, .defect-kind li.active').forEach((e) => e.classList.remove('active'));
        if (selectedShell !== null) {
          selectedShell = null;
          viewer.isolateShell(null);
          renderShellStats(null);
        }
        li.classList.add('active');
        document.body.dataset.focusedDefect = `${kind}:${i}`;
        viewer.focusDefect(kind, d);
      });
      ol.append(li);
    }
    if (n > kMaxDefectItems) {
      const more = document.createElement('li');
      more.className = 'more';
      more.textContent = `… and ${n - kMaxDefectItems} more`;
      ol.append(more);
    }
    details.append(ol);
    root.append(details);
  }
  $('#defects-panel').hidden = !any;
}

function renderLoops(list, loops, kind, colorOf) {
  const ol = $(list);
  ol.textContent = '';
  const fragment = document.createDocumentFragment();
  for (const loop of loops) {
    const li = document.createElement('li');
    li.dataset[kind] = String(loop.id);
    li.title = `Frame ${kind} ${loop.id}`;
    li.innerHTML = `<i class="swatch big" style="--c:${colorOf(loop)}"></i><span class="id">#${loop.id}</span>` +
      `<span class="edges" data-edges="${loop.edgeCount}">${loop.edgeCount} edge${loop.edgeCount === 1 ? '' : 's'}</span>` +
      `<span class="perimeter">perimeter ${+loop.perimeter.toPrecision(4)}</span>`;
    li.addEventListener('click', () => {
      if (kind === 'hole') editor.selectHole(loop.id);
      const wasActive = li.classList.contains('active');
      document.querySelectorAll('.loop-list li.active, .defect-kind li.active').forEach((e) => e.classList.remove('active'));
      delete document.body.dataset.focusedDefect;
      if (selectedShell !== null) {
        selectedShell = null;
        renderShellStats(null);
        viewer.isolateShell(null);
      }
      if (wasActive) {
        viewer.frameAll();
        return;
      }
      li.classList.add('active');
      viewer.focusLoop(loop, colorOf(loop));
    });
    fragment.append(li);
  }
  ol.append(fragment);
}

function arraysBytes(mesh) {
  let bytes = 0;
  const add = (v) => { if (ArrayBuffer.isView(v)) bytes += v.byteLength; };
  for (const value of Object.values(mesh)) {
    add(value);
    if (value && typeof value === 'object' && !ArrayBuffer.isView(value) && !Array.isArray(value)) Object.values(value).forEach(add);
  }
  for (const loop of [...(mesh.holes ?? []), ...(mesh.seams ?? [])]) Object.values(loop).forEach(add);
  return bytes;
}

function renderVerdict(stats) {
  const el = $('#verdict');
  const problems = [];
  const plural = (n, word) => `${n} ${word}${n === 1 ? '' : 's'}`;
  if (stats.holes) problems.push(plural(stats.holes, 'hole'));
  if (stats.seams) problems.push(plural(stats.seams, 'seam'));
  if (stats.nonManifoldEdges) problems.push(plural(stats.nonManifoldEdges, 'non-manifold edge'));
  if (stats.inconsistentEdges) problems.push(plural(stats.inconsistentEdges, 'flipped-face edge'));
  if (stats.nonManifoldVertices) problems.push(plural(stats.nonManifoldVertices, 'non-manifold vertex').replace('vertexs', 'vertices'));
  if (stats.degenerateTriangles) problems.push(plural(stats.degenerateTriangles, 'degenerate triangle'));
  if (stats.zeroAreaTriangles) problems.push(plural(stats.zeroAreaTriangles, 'zero-area triangle'));
  if (stats.duplicateTriangles) problems.push(plural(stats.duplicateTriangles, 'duplicate triangle'));
  if (stats.selfIntersections) problems.push(plural(stats.selfIntersections, 'self-intersecting pair'));
  const good = stats.watertight && stats.manifold;
  // The solid badge: the mesh bounds a volume without ambiguity (exact geometry).
  const solid = stats.solid === null ? '' : stats.solid ? ' <span class="badge solid">solid</span>'
    : ' <span class="badge not-solid">not solid</span>';
  el.className = `verdict ${good && stats.solid !== false ? 'good' : 'bad'}`;
  el.innerHTML = good
    ? `<span class="label">Watertight and manifold</span>${solid} · ${plural(stats.shells, 'shell')}, genus ${stats.genus}` +
      (problems.length ? ` · ${problems.join(', ')}` : '')
    : `<span class="label">${stats.watertight ? 'Watertight, not manifold' : 'Not watertight'}</span>${solid} · ${problems.join(', ') || 'empty mesh'}`;
}

function showMesh(mesh, { name, credit, parseMs, sceneMs, totalMs }) {
  const stats = mesh.stats;
  renderStats(stats, name);
  renderVerdict(stats);
  for (const el of document.querySelectorAll('[data-count]')) {
    const n = stats[el.dataset.count];
    el.textContent = n === undefined || n === null ? '' : String(n);
    el.closest('.toggle')?.classList.toggle('problem', n > 0);
  }
  const holes = mesh.holes ?? [];
  const seams = mesh.seams ?? [];
  renderLoops('#hole-list', holes, 'hole', (h) => holeColor(h.id));
  renderLoops('#seam-list', seams, 'seam', () => colors.seams);
  renderShells(mesh);
  renderDefects(mesh);
  const inward = (mesh.shells ?? []).filter((sh) => sh.orientation === 'inward').length;
  const inwardCount = document.querySelector('[data-count="inwardShells"]');
  inwardCount.textContent = String(inward);
  inwardCount.closest('.toggle')?.classList.toggle('problem', inward > 0);
  $('#holes-empty').hidden = holes.length > 0;
  $('#seams-panel').hidden = seams.length === 0;
  const warnings = mesh.warnings ?? [];
  $('#warnings-panel').hidden = warnings.length === 0;
  $('#warning-list').innerHTML = '';
  for (const w of warnings) {
    const li = document.createElement('li');
    li.innerHTML = '<code></code> <span></span>';
    li.firstChild.textContent = w.code;
    li.lastChild.textContent = w.message;
    $('#warning-list').append(li);
  }
  const ms = (x) => (x < 1000 ? `${Math.round(x)} ms` : `${(x / 1000).toFixed(2)} s`);
  $('#load-time').textContent = ms(totalMs);
  $('#load-time').title = `read + parse + topology in the worker: ${ms(parseMs)}; building the 3D view: ${ms(sceneMs)}`;
  $('#memory').textContent = formatBytes(arraysBytes(mesh));
  $('#memory').title = 'Size of the mesh and topology arrays handed over by the worker';
  $('#credit').textContent = credit;
}

function clearPanels() {
  $('#stats').textContent = '';
  $('#hole-list').textContent = '';
  $('#seam-list').textContent = '';
  $('#seams-panel').hidden = true;
  $('#shell-list').textContent = '';
  $('#shells-panel').hidden = true;
  $('#defect-list').textContent = '';
  $('#defects-panel').hidden = true;
  selectedShell = null;
  delete document.body.dataset.focusedDefect;
  $('#warnings-panel').hidden = true;
  $('#holes-empty').hidden = false;
  $('#verdict').textContent = '';
  $('#verdict').className = 'verdict';
  $('#load-time').textContent = '—';
  $('#memory').textContent = '—';
  $('#credit').textContent = '';
  document.querySelector('[data-stat="file"]').textContent = '';
  for (const el of document.querySelectorAll('[data-count]')) el.textContent = '';
}

// ---------------------------------------------------------------------------------------------
// Wiring

function buildSampleMenu() {
  const select = $('#sample-select');
  const groups = new Map();
  for (const s of samples) {
    if (!groups.has(s.group)) {
      const g = document.createElement('optgroup');
      g.label = s.group;
      groups.set(s.group, g);
      select.append(g);
    }
    const option = new Option(s.label, s.id);
    groups.get(s.group).append(option);
  }
  const custom = new Option('— your file —', '');
  custom.disabled = true;
  select.prepend(custom);
  select.addEventListener('change', () => {
    if (!select.value) return;
    history.replaceState(null, '', `?sample=${encodeURIComponent(select.value)}`);
    loadSample(select.value);
  });
}

function markCustom() {
  $('#sample-select').value = '';
}

function loadFile(file) {
  markCustom();
  history.replaceState(null, '', location.pathname);
  return load(file, { name: file.name, credit: `Your file, ${formatBytes(file.size)}; it stays on this computer.` });
}

$('#open-button').addEventListener('click', () => $('#file-input').click());
$('#file-input').addEventListener('change', (event) => {
  const file = event.target.files?.[0];
  event.target.value = ''; // choosing the same file again still fires "change"
  if (file) loadFile(file);
});

$('#url-form').addEventListener('submit', (event) => {
  event.preventDefault();
  const url = $('#url-input').value.trim();
  if (!url) return;
  markCustom();
  history.replaceState(null, '', `?url=${encodeURIComponent(url)}`);
  loadUrl(url);
});

$('#cancel-button').addEventListener('click', () => {
  if (!current) return;
  current.userCancelled = true;
  current.controller.abort();
});
$('#error-close').addEventListener('click', hideError);
$('#frame-button').addEventListener('click', () => {
  document.querySelectorAll('.loop-list li.active, .defect-kind li.active').forEach((e) => e.classList.remove('active'));
  delete document.body.dataset.focusedDefect;
  if (selectedShell !== null) {
    selectedShell = null;
    renderShellStats(null);
    viewer.isolateShell(null);
    return;
  }
  viewer.frameAll();
});

for (const input of document.querySelectorAll('[data-layer]')) {
  input.addEventListener('change', () => viewer.setVisible(input.dataset.layer, input.checked));
}

window.addEventListener('keydown', (event) => {
  if (event.target.closest?.('input, select, textarea') || event.ctrlKey || event.metaKey || event.altKey) return;
  if (event.key === 'f' || event.key === 'F') $('#frame-button').click();
  if (event.key === 'w' || event.key === 'W') $('[data-layer="wireframe"]').click();
  if (event.key === 'Escape' && current) $('#cancel-button').click();
});

// Drag and drop anywhere on the page. dragenter/dragleave fire for every child, so count them.
let dragDepth = 0;
const isFileDrag = (event) => [...(event.dataTransfer?.types ?? [])].some((t) => t === 'Files' || t === 'text/uri-list');
window.addEventListener('dragenter', (event) => {
  if (!isFileDrag(event)) return;
  event.preventDefault();
  dragDepth++;
  $('#drop-overlay').hidden = false;
});
window.addEventListener('dragover', (event) => {
  if (!isFileDrag(event)) return;
  event.preventDefault();
  event.dataTransfer.dropEffect = 'copy';
});
window.addEventListener('dragleave', () => {
  dragDepth = Math.max(0, dragDepth - 1);
  if (dragDepth === 0) $('#drop-overlay').hidden = true;
});
window.addEventListener('drop', (event) => {
  event.preventDefault();
  dragDepth = 0;
  $('#drop-overlay').hidden = true;
  const file = event.dataTransfer?.files?.[0];
  if (file) {
    loadFile(file);
    return;
  }
  const url = event.dataTransfer?.getData('text/uri-list')?.split('\n').find((l) => l && !l.startsWith('#'));
  if (url) {
    markCustom();
    loadUrl(url.trim());
  }
});

buildSampleMenu();
const params = new URLSearchParams(location.search);
if (params.get('url')) {
  markCustom();
  $('#url-input').value = params.get('url');
  loadUrl(params.get('url'));
} else {
  loadSample(params.get('sample') ?? defaultSampleId);
}

// ---------------------------------------------------------------------------------------------
// Edit mode

const editor = createEditor({
  viewer,
  show(em) {
    viewer.setMesh(em, { keepView: true });
    showMesh(em, { name: loaded?.name ?? '', credit: '', parseMs: 0, sceneMs: 0, totalMs: 0 });
  },
  status(text) { $('#edit-status').textContent = text; },
});
const tool = () => document.querySelector('input[name="edit-tool"]:checked').value;

async function stopEditing() {
  if (!editor.mesh) return;
  editor.stop();
  $('#edit-mode').checked = false;
  $('#edit-tools').hidden = true;
  document.body.dataset.editing = 'false';
}

$('#edit-mode').addEventListener('change', async (event) => {
  if (!event.target.checked) {
    await stopEditing();
    if (loaded) {
      viewer.setMesh(loaded.mesh, { keepView: true });
      showMesh(loaded.mesh, { name: loaded.name, credit: '', parseMs: 0, sceneMs: 0, totalMs: 0 });
    }
    return;
  }
  if (!loaded) {
    event.target.checked = false;
    return;
  }
  await editor.start(loaded.mesh);
  $('#edit-tools').hidden = false;
  document.body.dataset.editing = 'true';
});
// A click (not a drag of the view) on the model edits it.
let down = null;
$('#viewport').addEventListener('pointerdown', (e) => { down = { x: e.clientX, y: e.clientY }; });
$('#viewport').addEventListener('pointerup', (e) => {
  if (!editor.mesh || !down || Math.hypot(e.clientX - down.x, e.clientY - down.y) > 4) return;
  if (e.target !== viewer.renderer.domElement) return;
  editor.click(viewer.pick(e.clientX, e.clientY), tool());
});
$('#fill-fan').addEventListener('click', () => editor.fill('fan'));
$('#fill-ear').addEventListener('click', () => editor.fill('ear'));
$('#undo-button').addEventListener('click', () => editor.undo());
$('#edit-download').addEventListener('click', () => editor.download(loaded?.name ?? 'mesh'));
